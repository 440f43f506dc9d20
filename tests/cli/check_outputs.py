#!/usr/bin/env python3
"""What ggins coldatom writes: its CSVs and its plots (plot_coldatom.py, unless --no-plot); an
output it cannot write is an error (exit 1, naming the file).

usage: check_outputs.py ggins-coldatom=/path (a tool not given is skipped)
"""
import csv
import json
import os
import re
import subprocess
import sys
import tempfile

tools = dict(a.split("=", 1) for a in sys.argv[1:])
tmp = tempfile.mkdtemp(prefix="ggins-outputs-")
FAILS = []
UNIT = re.compile(r"_(m|mps|mps2|rad|radps|s|am|E|1|deg|km)$")


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


def has_matplotlib():
    return subprocess.run(["/usr/bin/python3", "-c", "import matplotlib"], capture_output=True).returncode == 0


def run(tool, args):
    return subprocess.run([tools[tool]] + args, capture_output=True, text=True, timeout=600, cwd=tmp)


if "ggins-coldatom" in tools:
    quick = ["--no-egm96", "--flights", "1", "--threads", "1", "--duration", "60", "--particles", "50"]
    d = os.path.join(tmp, "ca")
    r = run("ggins-coldatom", quick + ["--out", d])
    csvs = ["route_gzz.csv", "error_vs_time_base.csv", "gradient_base_flight0.csv", "summary_none.json"]
    check(r.returncode == 0 and all(os.path.exists(os.path.join(d, f)) for f in csvs),
          f"coldatom: exit {r.returncode}, wrote {', '.join(csvs)}" + ("" if r.returncode == 0 else "\n" + r.stderr[-800:]))
    if has_matplotlib():
        pngs = ["coldatom-route.png", "coldatom-error-vs-time.png", "coldatom-gradient.png"]
        missing = [p for p in pngs if not os.path.exists(os.path.join(d, p))]
        check(not missing, "coldatom: plots " + ", ".join(pngs) + (f" (missing {missing})" if missing else ""))
    else:
        print("skip coldatom plots (no matplotlib)")
    d = os.path.join(tmp, "ca-noplot")
    r = run("ggins-coldatom", quick + ["--out", d, "--no-plot"])
    check(r.returncode == 0 and not [f for f in os.listdir(d) if f.endswith(".png")], "coldatom --no-plot: no plot")
    d = os.path.join(tmp, "ca-blocked")
    os.makedirs(os.path.join(d, "error_vs_time_base.csv"))  # a folder where the CSV goes
    r = run("ggins-coldatom", quick + ["--out", d, "--no-plot"])
    check(r.returncode == 1 and "cannot write" in r.stderr and "error_vs_time_base.csv" in r.stderr,
          f"coldatom: a CSV it cannot write: exit {r.returncode} (want 1), {r.stderr.strip()[-200:]!r}")
else:
    print("skip ggins-coldatom (not built)")

print(f"{len(FAILS)} failure(s)")
sys.exit(1 if FAILS else 0)
