#!/usr/bin/env python3
"""What ggins coldatom and ggins mapnav write: coldatom's CSVs and its plots (plot_coldatom.py,
unless --no-plot), an output it cannot write is an error (exit 1, naming the file); mapnav's
timeseries.csv with a unit in every column, and a mean over no sample (NIS of a flight with no
update used) null in summary.json, not 0.

usage: check_outputs.py ggins-coldatom=/path ggins-mapnav=/path (tools not given are skipped)
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

if "ggins-mapnav" in tools:
    d = os.path.join(tmp, "mn")
    # a gate no innovation passes: every update refused, no NIS sample
    r = run("ggins-mapnav", ["--hours", "0.05", "--update", "60", "--gate", "1e-9", "--runs", "1", "--threads", "1",
                             "--no-plot", "--out", d])
    ok = r.returncode == 0 and os.path.exists(os.path.join(d, "summary.json"))
    check(ok, f"mapnav: a 180 s voyage whose every update is gated: exit {r.returncode}" + ("" if ok else "\n" + r.stderr[-800:]))
    if ok:
        rep = json.load(open(os.path.join(d, "summary.json")))
        s, aid = rep["ensemble"]["results"], rep["aids"][0]  # the report's statistics and filter counters
        check(aid["updates"] == 0 and aid["gated"] > 0 and s["nis_samples"] == 0 and s["nis_mean"] is None and
              rep["ensemble"]["filter_per_run"][0]["nis_mean"] is None,
              f"mapnav: NIS over no update is null (nis_mean {s['nis_mean']!r}, samples {s['nis_samples']})")
        check(s["nees_samples"] > 0 and isinstance(s["nees_mean"], float), f"mapnav: NEES over {s['nees_samples']} epochs")
        check("NIS none" in r.stdout, "mapnav: the text says there is no NIS sample")
        with open(os.path.join(d, "timeseries.csv")) as f:
            head = next(csv.reader(f))
        bad = [c for c in head if not UNIT.search(c)]
        check(not bad, "mapnav: every column of timeseries.csv carries its unit" + (f" (not: {bad})" if bad else ""))
else:
    print("skip ggins-mapnav (not built)")
print(f"{len(FAILS)} failure(s)")
sys.exit(1 if FAILS else 0)
