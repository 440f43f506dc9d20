#!/usr/bin/env python3
"""Ctrl-C from a terminal during a host-in-the-loop run: SIGINT to the whole
process group of `ggins run` / `ggins run3d` (as a terminal sends it) while it
flies over LCM. Checked, independently of the runner:

  - the runner exits 130 within seconds, and no hal_sim of the run is left
    (hal_sim was stopped in order, not killed by the signal: its log holds no
    error, the report does not say it "exited unexpectedly");
  - summary.json exists, status "interrupted", interrupted true, completed false;
  - the steps are accounted: steps_flown + steps_unflown = steps_expected,
    0 < steps_flown < steps_expected, frames_lost 0 (unflown steps are not lost),
    final_seq = steps_flown - 1, flown_s = final_seq * dt_s;
  - timeseries.csv holds rows up to the last step flown and no further;
  - the health word is decoded beside its raw value with frame.h's bit values
    (parsed here from frame.h, not taken from the runner's table).

usage: interrupt_check.py {run2d,run3d} --ggins-run PATH --ggins-run3d PATH --workdir DIR
"""
import argparse
import csv
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FAILS = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


def frame_h_bits():
    bits = {}
    with open(os.path.join(ROOT, "firmware", "include", "ggins", "frame.h")) as f:
        for m in re.finditer(r"#define\s+GG_HEALTH_(\w+)\s+(0x[0-9A-Fa-f]+)u", f.read()):
            bits[m.group(1)] = int(m.group(2), 16)
    return bits


def hal_sims_of(run_id):
    """pids of processes whose command line names hal_sim and this run id."""
    found = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open("/proc/%s/cmdline" % pid, "rb") as f:
                argv = f.read().split(b"\0")
        except OSError:
            continue
        if argv and argv[0].endswith(b"hal_sim") and str(run_id).encode() in argv:
            found.append(int(pid))
    return found


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=["run2d", "run3d"])
    ap.add_argument("--ggins-run")
    ap.add_argument("--ggins-run3d")
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    shutil.rmtree(a.workdir, ignore_errors=True)
    os.makedirs(a.workdir)
    out = os.path.join(a.workdir, "out")
    if a.case == "run2d":
        cmd = [a.ggins_run, "-s", "welker-perfect", "--duration", "1200"]
    else:
        cmd = [a.ggins_run3d, "-s", "3d-strapdown-1h", "--duration", "1200"]
    cmd += ["--no-plots", "--progress", "on", "--csv-rate", "10", "-o", out]
    # its own session: the signal goes to its process group, as from a terminal
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True, text=True)
    t_end = time.time() + 60
    started = False
    while time.time() < t_end:  # wait until steps are flowing (the first progress line past t = 0)
        line = p.stderr.readline()
        if not line:
            break
        if re.search(r"t = +[1-9][0-9.]* /", line):
            started = True
            break
    if not started and p.poll() is not None and p.returncode == 3:
        print("SKIP: UDP multicast on loopback unavailable")
        return 0
    check(started, "the flight started (%s)" % " ".join(cmd[:3]))
    t_sig = time.time()
    os.killpg(p.pid, signal.SIGINT)
    try:
        so, se = p.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        so, se = p.communicate()
    dt = time.time() - t_sig
    check(p.returncode == 130, "exit status 130 after SIGINT to the process group (got %s, %.1f s)" % (p.returncode, dt))
    check("unexpectedly" not in se, "no 'hal_sim exited unexpectedly' (stderr tail: %r)" % se[-200:])
    path = os.path.join(out, "summary.json")
    check(os.path.exists(path), "summary.json written")
    if not os.path.exists(path):
        return 1
    s = json.load(open(path))
    time.sleep(0.5)
    left = hal_sims_of(s.get("run_id"))
    check(not left, "no hal_sim of the run left (%s)" % left)
    hal_log = open(os.path.join(out, "hal_sim.log")).read() if os.path.exists(os.path.join(out, "hal_sim.log")) else ""
    check("error" not in hal_log.lower(), "hal_sim.log holds no error (%r)" % hal_log[-200:])
    check(s["status"] == "interrupted" and s["interrupted"] is True and s["completed"] is False,
          "status interrupted (%s, interrupted %s, completed %s)" % (s["status"], s["interrupted"], s["completed"]))
    n, fl, un = s["steps_expected"], s["steps_flown"], s["steps_unflown"]
    check(n == round(1200 * s["rate_hz"]) + 1, "steps_expected %d = 1200 s x rate + 1 (the --duration applied)" % n)
    check(0 < fl < n and fl + un == n, "steps flown %d + unflown %d = expected %d" % (fl, un, n))
    check(s["frames_lost"] == 0, "frames_lost 0: the unflown steps are not counted as lost (%d)" % s["frames_lost"])
    check(s["final_seq"] == fl - 1, "final_seq %d = steps_flown - 1" % s["final_seq"])
    check(abs(s["flown_s"] - s["final_seq"] * s["dt_s"]) < 1e-9, "flown_s %.2f = final_seq x dt_s" % s["flown_s"])
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    last = int(rows[-1]["seq"]) if rows else -1
    check(rows and last <= s["final_seq"] and s["final_seq"] - last < s["rate_hz"] / 10 + 1,
          "timeseries.csv ends at the last step flown (last row seq %d, final_seq %d)" % (last, s["final_seq"]))
    fh = frame_h_bits()
    raw = s["health_seen"]["raw"]
    names = sorted(k for k, v in fh.items() if raw & v)
    check(sorted(s["health_seen"]["bits"]) == names, "health_seen bits %s = frame.h's decoding of 0x%x" % (names, raw))
    e = s["errors"]["position_error_m"]
    check(e["final"] <= e["max"] and e["max"] < 1e-3, "errors of the last step flown present (final %.3g m)" % e["final"])
    print("%d failure(s)" % len(FAILS))
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
