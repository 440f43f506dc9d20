#!/usr/bin/env python3
"""--print-scenario [--defaults] of ggins covariance, montecarlo and montecarlo3d: the
template is valid TOML that the same command accepts; the scenario as it would fly,
written to a file and printed again from it, is the same text (every key written, the
file reads back to the same values); --defaults alone is refused (exit 2). ggins
covariance flies its printed scenario (per-axis sigmas and [initial] included) to the
same numbers as the original.

usage: check_print_scenario.py ggins-covariance=/path ... (tools not given are skipped)
"""
import json
import os
import subprocess
import sys
import tempfile
import tomllib

tools = dict(a.split("=", 1) for a in sys.argv[1:])
tmp = tempfile.mkdtemp(prefix="ggins-print-")
FAILS = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


def run(tool, args):
    return subprocess.run([tools[tool]] + args, capture_output=True, text=True, timeout=300, cwd=tmp)


def put(name, text):
    p = os.path.join(tmp, name)
    open(p, "w").write(text)
    return p


AXES = """name = "axes"
[trajectory]
type = "north-flight"
speed_mps = 250.0
lat0_deg = 30.0
[time]
duration_s = 300.0
rate_hz = 10.0
[accel]
bias_sigma_mps2 = [1e-12, 2e-12, 3e-12, 4e-12, 5e-12, 6e-12, 7e-12, 8e-12]
[initial]
gravity_sigma_mps2 = [1e-12, 3e-12]
position_sigma_m = 2.0
"""

CASES = {  # tool: scenarios to print, with the overrides the command takes
    "ggins-covariance": [["-s", "welker-table1", "--duration", "600"], ["-s", put("axes.toml", AXES)],
                         ["-s", "welker-baro-10h"]],
    "ggins-montecarlo": [["-s", "welker-table1", "--duration", "60", "--seed0", "7"]],
    "ggins-montecarlo3d": [["-s", "gc3d-baro", "--duration", "120", "--rate-hz", "10", "--acc-bias-sigma", "3e-12"],
                           ["-s", "gc3d-strapdown"], ["-s", "3d-stabilized-1h", "--duration", "60"]],
}

for tool, cases in CASES.items():
    if tool not in tools:
        print(f"skip {tool} (not built)")
        continue
    r = run(tool, ["--defaults"])
    check(r.returncode == 2 and "--defaults" in r.stderr, f"{tool} --defaults alone: exit {r.returncode} (want 2)")
    r = run(tool, ["--print-scenario", "--defaults"])
    try:
        tomllib.loads(r.stdout)
        valid = True
    except tomllib.TOMLDecodeError as e:
        valid = False
        print(e)
    check(r.returncode == 0 and valid and len(r.stdout) > 200, f"{tool} --print-scenario --defaults: a TOML template")
    t = put(tool + "-template.toml", r.stdout)
    r = run(tool, ["-s", t, "--print-scenario"])
    check(r.returncode == 0, f"{tool}: accepts its template (exit {r.returncode}) {r.stderr.strip()[:300]}")
    for i, args in enumerate(cases):
        r1 = run(tool, args + ["--print-scenario"])
        f1 = put(f"{tool}-{i}.toml", r1.stdout)
        r2 = run(tool, ["-s", f1, "--print-scenario"])
        check(r1.returncode == 0 and r2.returncode == 0 and r1.stdout == r2.stdout and len(r1.stdout) > 200,
              f"{tool} {' '.join(args)} --print-scenario: printed again from the file, the same text"
              + ("" if r1.stdout == r2.stdout else f"\n{r1.stderr}{r2.stderr}"))
        if tool == "ggins-covariance":  # flown from the printed file: the same numbers
            a = run(tool, args + ["--json", "--no-plot", "-o", os.path.join(tmp, f"cov-{i}-a")])
            b = run(tool, ["-s", f1, "--json", "--no-plot", "-o", os.path.join(tmp, f"cov-{i}-b")])
            ja, jb = (json.loads(x.stdout) if x.returncode == 0 else {} for x in (a, b))
            for j in (ja, jb):
                for k in ("scenario_source", "source", "output_dir", "files", "wall_s"):
                    j.pop(k, None)
                for k in ("source", "defaulted"):  # where it was read from, which keys the file left out
                    j.get("parameters", {}).pop(k, None)
            diff = sorted(k for k in set(ja) | set(jb) if ja.get(k) != jb.get(k))
            check(a.returncode == 0 and b.returncode == 0 and ja and not diff,
                  f"{tool} {' '.join(args)}: the printed scenario flies to the same numbers"
                  + (f" (differ: {diff})\n{a.stderr[-300:]}{b.stderr[-300:]}" if diff or not ja else ""))
print(f"{len(FAILS)} failure(s)")
sys.exit(1 if FAILS else 0)
