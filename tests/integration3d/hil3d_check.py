#!/usr/bin/env python3
"""Host-in-the-loop check of the 3-D system over real LCM:
`ggins run3d` (truth3d) -> hal_sim in 3-D mode (gg_nav3d_task_cycle) -> back.

  hil      a short run over LCM: every step answered (no loss, no rejection),
           files written, and the errors equal to the in-process run (--direct)
           of the same scenario: the LCM transport (frames as doubles + sub-ulp
           residuals, configuration as double-double pairs) must not change a bit;
           and again with 5 % of every transport fault: recovered, counted in
           summary.json (hal_sim's counters), the same bit for bit.
  cli      --help, --list-scenarios, unknown scenario, bad key.
  realtime --realtime: paced at the sensor rate, lateness / output latency / overruns reported.

usage: hil3d_check.py CASE --ggins-run3d PATH --workdir DIR [--scenario S] [--duration S]
Python stdlib only.
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys

FAILS = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


def run(exe, out, *args):
    p = subprocess.run([exe, "--out", out, "--no-plots", "-q", *args], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, timeout=600)
    print(p.stdout)
    check(p.returncode == 0, "%s %s: exit 0" % (os.path.basename(exe), " ".join(args)))
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def nav_csv(path):
    """timeseries.csv with the DEADLINE health bit (bit 9: a step that overran its period on
    this machine's clock, timing and not navigation) cleared; everything else as written."""
    with open(path) as f:
        lines = f.read().splitlines()
    col = lines[0].split(",").index("health")
    cb = lines[0].split(",").index("health_bits")  # the same word decoded
    out = [lines[0]]
    for ln in lines[1:]:
        x = ln.split(",")
        x[col] = str(int(x[col]) & ~(1 << 9))
        x[cb] = "|".join(b for b in x[cb].split("|") if b != "DEADLINE")
        out.append(",".join(x))
    return out


def case_hil(a):
    lcm_dir = os.path.join(a.workdir, "lcm")
    dir_dir = os.path.join(a.workdir, "direct")
    common = ["--scenario", a.scenario, "--duration", str(a.duration)]
    s = run(a.ggins_run3d, lcm_dir, *common)
    d = run(a.ggins_run3d, dir_dir, "--direct", *common)
    n = int(round(a.duration * 100)) + 1
    check(s["steps_expected"] == n and s["steps_flown"] == n and s["steps_unflown"] == 0 and s["status"] == "completed",
          "every step answered over LCM (%d), status completed" % n)
    check(s["steps_rejected"] == 0, "no step rejected")
    check(s.get("hal_sim", {}).get("frames_lost", -1) == 0, "hal_sim lost no frame")
    check(s.get("hal_sim", {}).get("steps", -1) == n, "hal_sim stepped the firmware %d times" % n)
    for f in ("summary.json", "timeseries.csv", "run.lcmlog", "scenario.toml"):
        check(os.path.getsize(os.path.join(lcm_dir, f)) > 0, "%s written" % f)
    for k in ("position_error_m", "velocity_error_mps", "attitude_error_rad", "gravity_error_mps2",
              "gradient_error_ecef_E", "gradient_error_body_E", "height_error_m"):
        check(s["errors"][k] == d["errors"][k],
              "%s identical over LCM and in process (%s vs %s)" % (k, s["errors"][k], d["errors"][k]))
    check(nav_csv(os.path.join(lcm_dir, "timeseries.csv")) == nav_csv(os.path.join(dir_dir, "timeseries.csv")),
          "timeseries.csv identical over LCM and in process (but for DEADLINE)")
    # the same flight with 5 % of every transport fault (and undecodable payloads):
    # recovered, counted, and the same bit for bit
    lossy_dir = os.path.join(a.workdir, "lossy")
    x = run(a.ggins_run3d, lossy_dir, *common, "--drop-prob", "0.05", "--dup-prob", "0.05", "--reorder-prob", "0.05",
            "--drop-output-prob", "0.05", "--garbage-prob", "0.05")
    check(nav_csv(os.path.join(lossy_dir, "timeseries.csv")) == nav_csv(os.path.join(dir_dir, "timeseries.csv")),
          "timeseries.csv with transport faults identical to the in-process run (but for DEADLINE)")
    for k in ("position_error_m", "attitude_error_rad", "gravity_error_mps2", "gradient_error_ecef_E"):
        check(x["errors"][k] == d["errors"][k], "%s identical with transport faults (%s)" % (k, x["errors"][k]))
    check(x["steps_flown"] == d["steps_flown"] == n, "all %d steps flown with transport faults" % n)
    hs, inj = x.get("hal_sim", {}), x.get("transport", {}).get("injected", {})
    for k in ("foreign_messages", "decode_errors", "auth_failed_frame", "auth_failed_config", "auth_failed_control",
              "resend_requests", "frames_duplicate", "outputs_dropped_injected", "outputs_republished"):
        check(k in hs, "summary hal_sim.%s reported (%s)" % (k, hs.get(k)))
    check(min(inj.get("dropped", 0), inj.get("duplicated", 0), inj.get("reordered", 0)) > 0
          and hs.get("outputs_dropped_injected", 0) > 0, "faults were injected (%s)" % inj)
    check(hs.get("decode_errors") == inj.get("garbage") and inj.get("garbage", 0) > 0,
          "hal_sim counted every undecodable payload (%s of %s)" % (hs.get("decode_errors"), inj.get("garbage")))
    check(hs.get("resend_requests", 0) > 0
          and hs.get("frames_duplicate", 0) >= inj.get("duplicated", 0) - inj.get("duplicated_copies", 0),
          "hal_sim asked for the dropped frames and counted the duplicates")
    check(x["bus_auth"]["rejected_total"] == 0 and x["bus_auth"]["conflicts_total"] == 0, "no MAC reject, no conflict")


def case_realtime(a):
    """--realtime in 3-D: one frame per sensor period, paced; timing reported."""
    out = os.path.join(a.workdir, "rt")
    s = run(a.ggins_run3d, out, "--scenario", a.scenario, "--duration", "2", "--realtime", "--no-log")
    check(s["steps_flown"] == 201 and s.get("hal_sim", {}).get("frames_lost", -1) == 0, "201 steps, none lost")
    check(0.5 < s["realtime_factor"] < 1.05, "paced at the sensor rate (real-time factor %.3f)" % s["realtime_factor"])
    rt = s.get("realtime", {})
    check(rt.get("lateness_us", {}).get("n") == 201 and rt.get("output_latency_us", {}).get("n") == 201
          and "deadline_overruns" in rt, "lateness, output latency and overruns reported (%s)"
          % {k: rt.get(k) for k in ("lateness_us", "output_latency_us", "deadline_overruns")})
    check(s["transport"]["frame_messages"] >= 201, "one frame per message")


def case_cli(a):
    p = subprocess.run([a.ggins_run3d, "--help"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    check(p.returncode == 0 and "summary.json" in p.stdout and "--direct" in p.stdout, "--help explains the run")
    p = subprocess.run([a.ggins_run3d, "--list-scenarios"], stdout=subprocess.PIPE, text=True)
    check(p.returncode == 0 and all(x in p.stdout for x in ("3d-stabilized-1h", "3d-strapdown-1h", "3d-tumble")),
          "built-in 3-D scenarios listed")
    p = subprocess.run([a.ggins_run3d, "--scenario", "no-such"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True)
    check(p.returncode == 2 and "unknown scenario" in p.stdout, "unknown scenario: exit 2 with message")
    bad = os.path.join(a.workdir, "bad.toml")
    with open(bad, "w") as f:
        f.write("[gyro]\nbias = 1\n")
    p = subprocess.run([a.ggins_run3d, "--scenario", bad], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    check(p.returncode == 2 and "unknown key 'gyro.bias'" in p.stdout, "unknown key: exit 2 naming the key")
    # an unaided flight's plot: the 3-D error model's one-sigma envelope (ggins covariance3d on
    # the scenario as flown: 120 s, the file says 3600 s)
    sc = os.path.join(a.workdir, "bias-sigma.toml")
    with open(sc, "w") as f:
        f.write('name = "bias-sigma"\n[accel]\nbias_sigma_mps2 = 1e-9\n[time]\nduration_s = 3600\n')
    out = os.path.join(a.workdir, "envelope")
    p = subprocess.run([a.ggins_run3d, "--scenario", sc, "--direct", "--duration", "120", "-q", "--out", out],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    cov = os.path.join(out, "covariance", "covariance3d.csv")
    rows = list(csv.DictReader(open(cov))) if os.path.exists(cov) else []
    end = rows[-1] if rows else {}
    check(p.returncode == 0 and rows and float(rows[0]["t_s"]) == 0.0 and float(end["t_s"]) == 120.0 and
          float(end["rn_m"]) > 0 and os.path.exists(os.path.join(out, "errors.png")),
          "unaided run3d: covariance/covariance3d.csv for the envelope spans the flight as flown (t to %s s, "
          "sigma north %s m)" % (end.get("t_s"), end.get("rn_m")))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=["hil", "cli", "realtime"])
    ap.add_argument("--ggins-run3d", required=True)
    ap.add_argument("--workdir", required=True)
    ap.add_argument("--scenario", default="3d-tumble")
    ap.add_argument("--duration", type=float, default=5.0)
    a = ap.parse_args()
    shutil.rmtree(a.workdir, ignore_errors=True)
    os.makedirs(a.workdir)
    {"hil": case_hil, "cli": case_cli, "realtime": case_realtime}[a.case](a)
    if FAILS:
        print("%d check(s) failed" % len(FAILS))
        sys.exit(1)
    print("all checks passed")


if __name__ == "__main__":
    main()
