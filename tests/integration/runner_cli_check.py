#!/usr/bin/env python3
"""Command-line values of ggins run, ggins run3d and ggins replay: a value that
is not finite, out of its range or not an integer is refused before anything
flies, exit 2, with a message naming the option, the value and the allowed
range (ggins/cli_checks.hpp). Each case also must not create the output folder.
And a flight shorter than the barometer loop's settling time: no settled statistics
(null, not 0), the scenario written as flown with the duration flown.

usage: runner_cli_check.py --ggins-run PATH --ggins-run3d PATH --ggins-replay PATH --workdir DIR
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys

FAILS = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


# option, value, text of the allowed range expected in the message
CASES = [
    ("--duration", "nan", "(0, 10000000]"),
    ("--duration", "-5", "(0, 10000000]"),
    ("--duration", "inf", "(0, 10000000]"),
    ("--duration", "0", "(0, 10000000]"),
    ("--csv-rate", "nan", "(0, 1000000]"),
    ("--csv-rate", "0", "(0, 1000000]"),
    ("--truth-rate", "-1", "[0, 1000000]"),
    ("--seed", "-1", "[0, 18446744073709551615]"),
    ("--seed", "1.5", "[0, 18446744073709551615]"),
    ("--fault-seed", "-1", "[0, 18446744073709551615]"),
    ("--drop-prob", "nan", "[0, 0.99]"),
    ("--drop-prob", "1", "[0, 0.99]"),
    ("--conflict-prob", "-0.1", "[0, 0.99]"),
    ("--deadline-ms", "nan", "(0, 60000]"),
    ("--batch", "0", "[1, 128]"),
    ("--window", "5000", "[1, 4096]"),
    ("--resend-timeout-ms", "0", "[1, 60000]"),
    ("--max-resend", "x", "[1, 100000]"),
]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ggins-run", required=True)
    ap.add_argument("--ggins-run3d", required=True)
    ap.add_argument("--ggins-replay", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    shutil.rmtree(a.workdir, ignore_errors=True)
    os.makedirs(a.workdir)
    out = os.path.join(a.workdir, "never")
    for exe in (a.ggins_run, a.ggins_run3d):
        tool = os.path.basename(exe)
        for opt, val, rng in CASES:
            p = subprocess.run([exe, "--direct", "--no-plots", "-o", out, opt, val], capture_output=True, text=True,
                               timeout=60)
            msg = p.stderr + p.stdout
            check(p.returncode == 2 and opt in msg and val in msg and rng in msg and not os.path.exists(out),
                  "%s %s %s: exit %d, message names option, value and range %s (%r)"
                  % (tool, opt, val, p.returncode, rng, msg.strip().splitlines()[0] if msg.strip() else ""))
    # replay: the log need not exist for a bad option value to be named first; use an empty file
    log = os.path.join(a.workdir, "empty.lcmlog")
    open(log, "wb").close()
    for opt, val, rng in [("--run-id", "-3", "[0, 9223372036854775807]"), ("--show", "nan", "[0, 1000000]")]:
        p = subprocess.run([a.ggins_replay, log, opt, val], capture_output=True, text=True, timeout=60)
        msg = p.stderr + p.stdout
        check(p.returncode == 2 and opt in msg and val in msg and rng in msg,
              "ggins-replay %s %s: exit %d, option, value and range named" % (opt, val, p.returncode))
    blocker = os.path.join(a.workdir, "a-file")
    open(blocker, "w").close()
    p = subprocess.run([a.ggins_replay, log, "--json", os.path.join(blocker, "r.json")], capture_output=True, text=True,
                       timeout=60)
    check(p.returncode == 2 and "--json" in p.stderr and "not a folder" in p.stderr,
          "ggins-replay --json under a file: exit %d, named (%r)" % (p.returncode, p.stderr.strip()[:120]))
    # a short flight of a barometer-loop scenario (shorter than the loop's settling time):
    # no settled statistics (null, not 0), and the scenario written as flown says the
    # duration flown and parses again to the same flight length
    short = os.path.join(a.workdir, "short")
    p = subprocess.run([a.ggins_run, "--direct", "--no-plots", "-q", "-s", "welker-baro-10h", "--duration", "20",
                        "-o", short], capture_output=True, text=True, timeout=120)
    check(p.returncode == 0, "short flight of welker-baro-10h (20 s) completes (exit %d)" % p.returncode)
    if p.returncode == 0:
        s = json.load(open(os.path.join(short, "summary.json")))
        v, g = s["vertical"], s["gravimeter"]
        check(v["settle_s"] > 20 and v["samples_after_settle"] == 0 and v["rms_error_after_settle_m"] is None
              and v["max_abs_error_after_settle_m"] is None,
              "vertical: settle_s %.0f s > 20 s, no settled rms (null, not 0)" % v["settle_s"])
        check(g["samples"] == 0 and g["rms_error_mps2"] is None, "gravimeter: no settled rms (null, not 0)")
        p = subprocess.run([a.ggins_run, "-s", os.path.join(short, "scenario.toml"), "--print-scenario"],
                           capture_output=True, text=True, timeout=60)
        check(p.returncode == 0 and re.search(r"^duration_s = 20(\.0)?$", p.stdout, re.M) is not None,
              "scenario.toml as flown parses again and says duration_s = 20")
        check(s["duration_s"] == 20 and s["steps_expected"] == int(round(20 * s["rate_hz"])) + 1,
              "the report's duration and steps are those flown (%s s, %d steps)" % (s["duration_s"], s["steps_expected"]))
    print("%d failure(s)" % len(FAILS))
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
