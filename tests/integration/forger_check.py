#!/usr/bin/env python3
"""Bus authentication against a forging publisher (docs/hil.md, "Authenticated bus").

  forged-2d    `ggins run` flown twice: clean, and with bus_forger (a local process
               without the run's key, reading the URLs from hal_sim's command line
               and the run id from the bus) publishing forged frames (copies of frame K
               as K+1..K+3 and K+100..K+102, a changed one), outputs (position moved
               1 m), STOP/START, a configuration, a hal_sim status, a RESEND request
               and a paced flood. Truth: the clean flight. The attacked one must be
               bit-identical (timeseries.csv byte for byte, final and max errors to
               the last digit) and summary.json must count every forged message the
               forger sent, on the channel it sent it on, with no conflict.
  forged-3d    the same against `ggins run3d`.
  conflict-2d  `ggins run --conflict-prob`: the run tool itself (it holds the key)
               sends a second, different frame for some seqs, and hal_sim a second,
               different output. The receivers must count each as a conflict, take
               the first copies (outputs = clean flight), and the run must not be
               completed (exit 1).
Python standard library only.
"""
import argparse
import json
import os
import subprocess
import sys
import time

FAILS = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        FAILS.append(what)


def read(p):
    with open(p, "rb") as f:
        return f.read()


def run_clean(cmd, out):
    p = subprocess.run(cmd + ["-o", out], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=240)
    return p.returncode, p.stdout


def run_attacked(cmd, out, forger, mode, start_seq, flood):
    r = subprocess.Popen(cmd + ["-o", out], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    f = subprocess.run([forger, "--runner-pid", str(r.pid), "--mode", mode, "--start-seq", str(start_seq),
                        "--flood", str(flood), "--timeout", "60"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
    so, _ = r.communicate(timeout=240)
    try:
        fj = json.loads(f.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        fj = {"error": "no JSON from the forger: " + f.stdout}
    return r.returncode, so, f.returncode, fj


KNOWN_OPTS = {"--lcm-url", "--lcm-url-out", "--prefix", "--run-id", "--key-fd", "--gap-timeout-ms", "--idle-timeout-s",
              "--drop-output-prob", "--inject-seed"}


def check_cmdline(fj):
    cmd = fj.get("hal_sim_cmdline", [])
    opts = {a for a in cmd[1:] if a.startswith("--")}
    check(opts <= KNOWN_OPTS and "--key-fd" in opts,
          "hal_sim's command line (public in /proc) holds no key, only --key-fd and the run's settings: %s" % sorted(opts))


def check_counts(s_bus, fj, prefix, runner_channels):
    sent = fj.get("sent", {})
    rej = s_bus.get("rejected_unauthenticated", {})
    for c in ["FRAME", "CONTROL", "HAL", "REQUEST"] + runner_channels:
        ch = prefix + c
        check(sent.get(ch, 0) > 0 and rej.get(ch, -1) == sent.get(ch, 0),
              "%-16s forged %5d, counted and dropped %5d" % (ch, sent.get(ch, 0), rej.get(ch, -1)))
    check(set(rej) == set(sent), "no other channel counted forged messages (%s)" % sorted(rej))
    check(s_bus.get("rejected_total") == fj.get("sent_total"),
          "every forged message counted: %s of %s" % (s_bus.get("rejected_total"), fj.get("sent_total")))
    check(s_bus.get("conflicts_total") == 0, "no conflict (forged messages cannot take a seq)")


def case_forged_2d(a):
    os.makedirs(a.workdir, exist_ok=True)
    # long enough that the attack (a paced flood) ends during the flight: batched
    # lockstep flies 2-D at ~1000x real time
    n = 100001
    cmd = [a.ggins_run, "-s", "welker-table1", "--duration", "1000", "--no-plots", "-q"]
    rc0, out0 = run_clean(cmd, os.path.join(a.workdir, "clean"))
    check(rc0 == 0, "clean flight completed (exit %d)" % rc0)
    rc1, out1, frc, fj = run_attacked(cmd, os.path.join(a.workdir, "attacked"), a.forger, "2d", 1000, 2000)
    check(frc == 0 and "error" not in fj, "the forger attacked the running flight: %s" % json.dumps(fj)[:300])
    check(rc1 == 0, "attacked flight completed (exit %d)%s" % (rc1, "" if rc1 == 0 else "\n" + out1[-2000:]))
    if FAILS:
        return
    check(fj["seq_at_end"] < n - 1000, "the attack ended during the flight (frame %d of %d)" % (fj["seq_at_end"], n))
    s0 = json.load(open(os.path.join(a.workdir, "clean", "summary.json")))
    s1 = json.load(open(os.path.join(a.workdir, "attacked", "summary.json")))
    check(nav_rows(os.path.join(a.workdir, "clean", "timeseries.csv")) == nav_rows(
        os.path.join(a.workdir, "attacked", "timeseries.csv")),
        "timeseries.csv the same as the clean flight, byte for byte but for the DEADLINE bit")
    for k in ["errors", "steps_flown", "steps_rejected", "vertical", "horizontal"]:
        check(s0[k] == s1[k], "summary %-18s the same to the last digit (final |dr| %r m)"
              % (k, s1["errors"]["position_error_m"]["final"]))
    # DEADLINE flags a step that took longer than its period on this machine's clock (a busy
    # machine descheduling hal_sim): timing, not navigation; every other bit must be the same
    nav_bits = [[b for b in s["health_seen"]["bits"] if b != "DEADLINE"] for s in (s0, s1)]
    check(nav_bits[0] == nav_bits[1], "summary health bits the same but for DEADLINE (%s)" % nav_bits[1])
    check(s1["completed"] and s1["steps_flown"] == n, "all %d steps flown" % n)
    check(s1["transport"]["outputs_received"] == n, "one accepted output per step")
    bus = s1["bus_auth"]
    check_counts(bus, fj, "GGINS_", ["NAV", "CONFIG"])
    pc = s1["log"]["per_channel"]
    for c in ["NAV", "HAL", "REQUEST"]:  # received by the run tool: kept in the log apart from the authentic ones
        check(pc.get("GGINS_" + c + ".UNAUTHENTICATED", 0) == fj["sent"].get("GGINS_" + c, -1),
              "log: GGINS_%s.UNAUTHENTICATED holds the %d forged ones" % (c, fj["sent"].get("GGINS_" + c, -1)))
    check(s1["log"]["complete"], "log complete")
    check_cmdline(fj)


# DEADLINE (0x200) flags a step that overran its period on this machine's clock (a busy
# machine descheduling the process): a timing flag, not navigation, so it is masked here
def nav_rows(path):
    rows = read(path).decode().splitlines()
    head = rows[0].split(",")
    ih = head.index("health")
    ib = head.index("health_bits")  # the same word decoded
    out = [rows[0]]
    for r in rows[1:]:
        f = r.split(",")
        f[ih] = str(int(f[ih]) & ~0x200)
        f[ib] = "|".join(b for b in f[ib].split("|") if b != "DEADLINE")
        out.append(",".join(f))
    return out


def case_forged_3d(a):
    os.makedirs(a.workdir, exist_ok=True)
    # batched lockstep flies 3-D at a few hundred times real time: long enough for the whole attack
    n = 60001
    cmd = [a.ggins_run3d, "-s", "3d-stabilized-1h", "--duration", "600", "--no-plots", "-q"]
    rc0, out0 = run_clean(cmd, os.path.join(a.workdir, "clean"))
    check(rc0 == 0, "clean 3-D flight completed (exit %d)" % rc0)
    rc1, out1, frc, fj = run_attacked(cmd, os.path.join(a.workdir, "attacked"), a.forger, "3d", 1000, 2000)
    check(frc == 0 and "error" not in fj, "the forger attacked the running flight: %s" % json.dumps(fj)[:300])
    check(rc1 == 0, "attacked 3-D flight completed (exit %d)%s" % (rc1, "" if rc1 == 0 else "\n" + out1[-2000:]))
    if FAILS:
        return
    check(fj["seq_at_end"] < n - 1000, "the attack ended during the flight (frame %d of %d)" % (fj["seq_at_end"], n))
    s0 = json.load(open(os.path.join(a.workdir, "clean", "summary.json")))
    s1 = json.load(open(os.path.join(a.workdir, "attacked", "summary.json")))
    check(nav_rows(os.path.join(a.workdir, "clean", "timeseries.csv")) == nav_rows(
        os.path.join(a.workdir, "attacked", "timeseries.csv")),
        "timeseries.csv the same as the clean flight, byte for byte but for the DEADLINE bit")
    for k in ["errors", "parity", "steps_rejected", "steps_flown"]:
        check(s0[k] == s1[k], "summary %-28s the same to the last digit: %r" % (k, s1[k]))
    check(s0["health_seen"]["raw"] & ~0x200 == s1["health_seen"]["raw"] & ~0x200,
          "summary health_seen the same but for DEADLINE: %r" % (s1["health_seen"]["raw"] & ~0x200))
    check(s1.get("completed") and s1["steps_flown"] == n, "all %d steps flown" % n)
    check(s1["hal_sim"]["steps"] == n, "hal_sim stepped the firmware %d times (no forged frame flown)" % n)
    check_counts(s1["bus_auth"], fj, "GGINS_", ["NAV3D", "CONFIG3D"])
    check_cmdline(fj)


def case_conflict_2d(a):
    os.makedirs(a.workdir, exist_ok=True)
    cmd = [a.ggins_run, "-s", "welker-table1", "--duration", "20", "--no-plots", "-q"]
    rc0, _ = run_clean(cmd, os.path.join(a.workdir, "clean"))
    rc1, out1 = run_clean(cmd + ["--conflict-prob", "0.01"], os.path.join(a.workdir, "conflict"))
    check(rc0 == 0, "clean flight completed")
    s1 = json.load(open(os.path.join(a.workdir, "conflict", "summary.json")))
    inj = s1["transport"]["injected"]["conflicting"]
    c = s1["bus_auth"]["conflicts"]
    check(inj > 5, "%d conflicting authenticated frames sent" % inj)
    check(c["frames"] == inj and s1["transport"]["hal_sim"]["frames_conflict"] == inj,
          "hal_sim counted each as a conflict (%d)" % c["frames"])
    inj_out = s1["transport"]["hal_sim"]["outputs_conflict_injected"]
    check(inj_out > 5 and c["outputs"] == inj_out,
          "%d conflicting authenticated outputs sent by hal_sim, %d counted by the run tool" % (inj_out, c["outputs"]))
    check(s1["bus_auth"]["rejected_total"] == 0, "none taken for a forgery (their MACs are valid)")
    check(rc1 == 1 and not s1["completed"] and "conflicting authenticated" in s1.get("error", ""),
          "the run is not completed and exits 1 (exit %d, error %r)" % (rc1, s1.get("error", "")[:80]))
    check(read(os.path.join(a.workdir, "clean", "timeseries.csv")) == read(
        os.path.join(a.workdir, "conflict", "timeseries.csv")),
          "the first copy of each seq was flown, the second never (timeseries.csv = clean flight)")
    hl = open(os.path.join(a.workdir, "conflict", "hal_sim.log")).read()
    check("conflict" in hl, "hal_sim reported the conflicts in its log")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=["forged-2d", "forged-3d", "conflict-2d"])
    ap.add_argument("--ggins-run")
    ap.add_argument("--ggins-run3d")
    ap.add_argument("--forger", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    t = time.time()
    {"forged-2d": case_forged_2d, "forged-3d": case_forged_3d, "conflict-2d": case_conflict_2d}[a.case](a)
    print("%s: %s in %.1f s" % (a.case, "FAILED (%d)" % len(FAILS) if FAILS else "passed", time.time() - t))
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
