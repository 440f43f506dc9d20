#!/usr/bin/env python3
"""`ggins run3d --direct` (the firmware stepped in process) on routes and faults:

  route    the hand-written route scenarios/3d-route-45n.toml (45 N eastbound,
           two 45 deg turns, a climb, a speed change; 660 s, perfect sensors,
           baro loop): every step used, no fault bit, position error < 1 cm.
  bias     the same route's first 60 s with a 1e-8 m/s^2 step bias on
           accelerometer 1, axis x, from 5 s: ACC_FAULT and ACC_REBUILT raised,
           no step rejected, position error < 1 cm (the reading is rebuilt).
  nanpair  the first 60 s with both readings of pair 2/5, axis z, NaN for 1.5 s
           from 10 s: ACC_NONFINITE on exactly those steps, the run completes and
           the task navigates after it (error < 1 cm).

usage: run3d_route_check.py CASE --ggins-run3d PATH --workdir DIR
Python stdlib only.
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROUTE = os.path.join(HERE, "..", "..", "scenarios", "3d-route-45n.toml")
ACC_NONFINITE, ACC_FAULT, ACC_REBUILT = 0x2, 0x8000, 0x10000
FAULT_BITS = ACC_NONFINITE | 0x4 | 0x8 | ACC_FAULT | ACC_REBUILT | 0x20000 | 0x100
FAILS = []
CHECKS = [0]


def check(cond, what):
    CHECKS[0] += 1
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


def run(a, scenario, *args, want_rc=0):
    out = os.path.join(a.workdir, "out")
    p = subprocess.run([a.ggins_run3d, "--direct", "--no-plots", "--no-log", "-q", "--out", out,
                        "--scenario", scenario, *args],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    print(p.stdout)
    check(p.returncode == want_rc, "ggins run3d --direct exit %d (got %d)" % (want_rc, p.returncode))
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    return s, rows


def with_faults(a, name, faults):
    with open(ROUTE) as f:
        text = f.read()
    path = os.path.join(a.workdir, name + ".toml")
    with open(path, "w") as f:
        f.write(text.replace('name = "3d-route-45n"', 'name = "%s"' % name) + "\n" + faults)
    return path


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=["route", "bias", "nanpair"])
    ap.add_argument("--ggins-run3d", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    shutil.rmtree(a.workdir, ignore_errors=True)
    os.makedirs(a.workdir)
    if a.case == "route":
        s, _ = run(a, "3d-route-45n")
        check(s["trajectory"] == "route", "trajectory type route")
        check(s["steps_flown"] == 66001 and s["steps_rejected"] == 0, "66001 steps, none rejected")
        check((s["health_seen"]["raw"] & FAULT_BITS) == 0, "no fault bit (health_or 0x%x)" % s["health_seen"]["raw"])
        pe = s["errors"]["position_error_m"]
        check(pe["max"] < 0.01, "position error max %.3e m < 1 cm (final %.3e m)" % (pe["max"], pe["final"]))
    elif a.case == "bias":
        sc = with_faults(a, "route-bias", '[sensor_faults]\n[[sensor_faults.fault]]\nkind = "step"\nsensor = 1\n'
                         'axis = "x"\nstart_s = 5.0\nsize = 1e-8\n')
        s, rows = run(a, sc, "--duration", "60", "--csv-rate", "100")
        check(s["steps_rejected"] == 0, "no step rejected")
        h = s["health_seen"]["raw"]
        check(h & ACC_FAULT and h & ACC_REBUILT, "ACC_FAULT and ACC_REBUILT raised (health_or 0x%x)" % h)
        first = min((float(r["t_s"]) for r in rows if int(r["health"]) & ACC_FAULT), default=None)
        check(first is not None and 5.0 <= first <= 5.011, "flagged at %s s (fault from 5 s)" % first)
        pe = s["errors"]["position_error_m"]
        check(pe["max"] < 0.01, "position error max %.3e m < 1 cm" % pe["max"])
    else:
        sc = with_faults(a, "route-nanpair", '[sensor_faults]\n'
                         '[[sensor_faults.fault]]\nkind = "nan"\nsensor = 2\naxis = "z"\nstart_s = 10.0\nduration_s = 1.5\n'
                         '[[sensor_faults.fault]]\nkind = "nan"\nsensor = 5\naxis = "z"\nstart_s = 10.0\nduration_s = 1.5\n')
        # frames rejected while the pair is NaN: completed but degraded (exit 4)
        s, rows = run(a, sc, "--duration", "60", "--csv-rate", "100", want_rc=4)
        check(s["degraded"] is True, "summary.json: degraded")
        flagged = [float(r["t_s"]) for r in rows if int(r["health"]) & ACC_NONFINITE]
        check(flagged and abs(min(flagged) - 10.0) < 1e-9 and abs(max(flagged) - 11.49) < 1e-9,
              "ACC_NONFINITE from 10 s to 11.49 s only (%s .. %s)" % (flagged[:1], flagged[-1:]))
        check(s["steps_rejected"] <= 150, "at most the 150 NaN frames unused (%d)" % s["steps_rejected"])
        check(s["steps_flown"] == 6001, "the run completes (6001 steps)")
        after = [r for r in rows if float(r["t_s"]) > 11.5]
        check(all((int(r["health"]) & 0x100) == 0 for r in after), "no frame rejected after the NaN pair")
        pe = s["errors"]["position_error_m"]
        check(pe["final"] < 0.01, "navigating after it: final position error %.3e m < 1 cm" % pe["final"])
    print("%d passed, %d failed" % (CHECKS[0] - len(FAILS), len(FAILS)))
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
