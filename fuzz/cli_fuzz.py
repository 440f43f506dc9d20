#!/usr/bin/env python3
"""Command-line fuzzing of the host tools (every ggins command): random
adversarial values (NaN, inf, signs, huge numbers, junk text, paths under a file, broken
2-D and 3-D scenario files) on each tool's options, run as a user would run the program.
run/run3d are fuzzed with --print-scenario (every option and the scenario parsed, checked
and applied; no flight), spy with --check (its arguments and class path checked; no window).
Every run must end with an exit code of the scheme in `ggins --help` (0 done, 1 failed,
2 bad arguments, 3 machine lacks a need, 4 degraded or corrupt log, 5 incomplete record),
with a message when not 0: a signal (abort, segfault), an uncaught exception ('terminate')
or any other exit code is a finding. Runs over the time limit are killed and counted, not
findings (a valid command line may start a long computation).

  fuzz/cli_fuzz.py --bin build/bin [--runs 240] [--seed 1] [--timeout 5]

Bounded in runs and time; no network. Exit 1 on a finding (printed with its command line).
"""
import argparse
import os
import random
import subprocess
import sys
import tempfile

DOCUMENTED = (0, 1, 2, 3, 4, 5)  # the exit codes of `ggins --help` (130: interrupted, not sent here)
VALUES = ["nan", "-nan", "inf", "-inf", "0", "-0", "-1", "1e308", "-1e308", "1e-320", "2147483648",
          "18446744073709551616", "-9223372036854775809", "abc", "", "1e", "0x10", " 1", "1,5", "--", "-"]

# option -> a few sensible values (mixed with the adversarial ones above)
TOOLS = {
    "ggins-covariance": {
        "base": ["--duration", "60", "--no-plot", "-o", "{out}"],
        "opts": {"-s": ["welker-table1", "{scenario}", "{missing}", "{a_file}"], "--dt": ["1", "0.5"],
                 "--output-dt": ["10"], "--method": ["transition", "lyapunov", "m"], "--gradient": ["centre", "baseline"],
                 "--g": ["9.8"], "--sigma-g0": ["2e-12"], "--duration": ["60", "600"], "-o": ["{out}", "{under_file}"]},
    },
    "ggins-covariance3d": {
        "base": ["--duration", "60", "--no-plot", "-o", "{out}"],
        "opts": {"-s": ["gc3d-stabilized", "gc3d-strapdown", "{missing}", "{a_file}"], "--platform": ["stabilized", "strapdown"],
                 "--field": ["normal", "point-mass"], "--omega-ie": ["0", "7.29e-5"], "--lat0-deg": ["45"],
                 "--lon0-deg": ["0"], "--heading-deg": ["90"], "--speed": ["200"], "--height": ["1000"],
                 "--duration": ["60"], "--acc-bias-sigma": ["1e-9"], "--gyro-bias-sigma": ["1e-8"],
                 "--acc-noise-sigma": ["0"], "--gyro-noise-sigma": ["0"], "--rate-hz": ["100"], "--g0-sigma": ["0"],
                 "--psi0-sigma": ["0"], "--baro": ["true", "false", "maybe"], "--baro-bias-sigma": ["1"],
                 "--dt": ["1"], "--output-dt": ["10"], "--method": ["transition", "lyapunov"], "-o": ["{out}", "{under_file}"]},
    },
    "ggins-run": {
        "base": ["--print-scenario"],
        "opts": {"-s": ["welker-table1", "{scenario}", "{missing}", "{a_file}", "rw-compare-model"],
                 "--duration": ["20", "1e9"], "--seed": ["3"], "--csv-rate": ["1", "0"], "--truth-rate": ["0", "10"],
                 "--drop-prob": ["0.1", "1"], "--dup-prob": ["0.1"], "--reorder-prob": ["0.1"],
                 "--drop-output-prob": ["0.1"], "--garbage-prob": ["0.1"], "--fault-seed": ["2"],
                 "--batch": ["1", "128"], "--out": ["{out}", "{under_file}"], "--defaults": [""]},
    },
    "ggins-run3d": {
        "base": ["--print-scenario"],
        "opts": {"-s": ["3d-stabilized-1h", "{scenario3}", "{missing}", "{a_file}", "3d-route-45n"],
                 "--duration": ["20", "1e9"], "--seed": ["3"], "--csv-rate": ["1", "0"], "--no-aids": [""],
                 "--out": ["{out}", "{under_file}"], "--defaults": [""]},
    },
    "ggins-field": {
        "base": ["--model", "normal"],
        "opts": {"--model": ["normal", "point-mass", "kaula", "rw", "x"], "--at": ["45,10,1000", "95,0,0", "1,2"],
                 "--ecef": ["7e6,0,0", "0,0,0"], "--nmax": ["4", "5401"], "--gm": ["3.986e14"], "--seed": ["1"],
                 "--route": ["3d-route-45n", "{scenario3}", "{missing}"], "--step": ["600", "0"],
                 "--format": ["csv", "json", "xml"], "--frame": ["ecef", "ned", "both"], "-o": ["{out}.csv", "{under_file}"],
                 "--csv": ["{a_file}", "{missing}"]},
    },
    "ggins-gmap": {
        "base": ["--lat-min", "45", "--lat-max", "45.05", "--lon-min", "10", "--lon-max", "10.05", "--degree", "8",
                 "--egm96", "{missing}", "--out", "{out}.bin"],
        "opts": {"--lat-min": ["45", "-91"], "--lat-max": ["45.1"], "--lon-min": ["10"], "--lon-max": ["10.1"],
                 "--spacing": ["0.05", "0"], "--alt": ["1000"], "--h-range": ["500"], "--degree": ["2", "361"],
                 "--noise-e": ["0.001"], "--seed": ["1"], "--threads": ["1", "0"], "--out": ["{out}.bin", "{under_file}"],
                 "--json": ["{out}.json", "{under_file}"]},
    },
    "ggins-profile": {
        "base": ["--filters-only", "--pf-shots", "1"],
        "opts": {"--pf-shots": ["1", "2"], "--pf-chunk": ["1", "50"], "--duration": ["1"], "--keep": ["{out}", "{under_file}"]},
    },
    "ggins-replay": {
        "base": ["{a_file}"],
        "opts": {"--prefix": ["GG"], "--run-id": ["1", "-1"], "--json": ["{out}.json", "{under_file}"], "--show": ["0", "10"]},
    },
    "ggins-scenario-reference": {
        "base": [],
        "opts": {"-o": ["{out}.md", "{under_file}"], "--check": ["{a_file}", "{missing}"]},
    },
    "ggins-montecarlo": {
        "base": ["--duration", "10", "-n", "2", "--run-exe", "{missing}", "-o", "{out}"],
        "opts": {"-s": ["welker-table1", "{scenario}", "{missing}"], "-n": ["2", "1"], "-j": ["1", "0"], "--seed0": ["1"],
                 "--duration": ["10"], "--z": ["3"], "-o": ["{out}", "{under_file}"]},
    },
    "ggins-montecarlo3d": {
        "base": ["--duration", "10", "-n", "2", "-j", "1", "-o", "{out}"],
        "opts": {"-s": ["gc3d-stabilized", "{scenario3}", "{missing}"], "-n": ["2"], "--seed": ["1"], "--rate-hz": ["10"],
                 "--duration": ["10"], "--output-dt": ["5"], "-j": ["1"], "--speed": ["100"], "--lat0-deg": ["45"],
                 "--acc-bias-sigma": ["1e-9"], "--gyro-bias-sigma": ["1e-8"], "-o": ["{out}", "{under_file}"]},
    },
    "ggins-spy": {
        "base": ["--check"],
        "opts": {"--lcm-url": ["udpm://239.255.76.67:7667?ttl=0", "file://{a_file}", "memq://", "udp://x", "{a_file}"],
                 "-l": ["udpm://239.255.76.67:7667?ttl=0", "tcpq://127.0.0.1:7700", "-h"],
                 "--lcm-url=udpm://239.255.76.67:7667?ttl=0": [""], "--lcm-url=": [""], "-h": [""], "--check": [""],
                 "--bogus": [""], "-p": ["x"]},
    },
    "ggins-campaign": {
        # --list: the spec parsed, checked and expanded, no cluster started; --report: the
        # summary rebuilt from an (empty or missing) store
        "base": ["--list", "{campaign}"],
        "opts": {"-o": ["{out}", "{under_file}"], "--seeds": ["1", "0"], "--retries": ["0", "1"],
                 "--stop-after": ["1", "0"], "-w": ["1", "0"], "--report": [""], "--no-plot": [""], "-q": [""],
                 "--data": ["{missing}", "{a_file}"], "--bin": ["{missing}", "{a_file}"],
                 "--scheduler": ["tcp://127.0.0.1:1", "x"], "--scheduler-file": ["{missing}", "{a_file}"]},
    },
    "ggins-logtime info": {
        "exe": "ggins-logtime", "base": ["info"],
        "opts": {"": ["{log}", "{log}", "{a_file}", "{missing}"]},  # "": the positional LOG
    },
    "ggins-logtime retime": {
        "exe": "ggins-logtime", "base": ["retime", "{log}", "{out}.lcmlog"],
        "opts": {"--speed": ["1", "0", "1e-300"]},
    },
    "ggins-logtime csv": {
        "exe": "ggins-logtime", "base": ["csv", "{log}", "{channel}"],
        "opts": {"": ["{out}.csv", "{under_file}", "{a_file}"]},  # "": the positional OUT
    },
    "ggins-rw-eq8": {
        "base": ["--runs", "2", "--hours", "0.01", "--rate-hz", "1"],
        "opts": {"--runs": ["2"], "--hours": ["0.01"], "--rate-hz": ["1"], "--speed-kn": ["330"], "--height-m": ["0"],
                 "--lat0-deg": ["30"], "--rms-arcsec": ["4.5"], "--corr-nmi": ["33"], "--seed": ["1"],
                 "--check-every-s": ["10"], "--band": ["0.9"]},
    },
}

SCENARIO3_LINES = ["name = \"f3\"", "[trajectory]", "type = \"flight\"", "type = \"route\"", "lat_deg = {v}",
                   "height_m = {v}", "velocity_ned_mps = [{v}, 0, 0]", "[[trajectory.waypoint]]", "lon_deg = {v}",
                   "speed_mps = {v}", "[[trajectory.maneuver]]", "t_s = {v}", "duration_s = {v}", "[time]",
                   "rate_hz = {v}", "[gyro]", "bias_radps = [{v}, 0, 0]", "[aid_ukf]", "enabled = {v}", "map = {v}",
                   "max_passes = {v}", "average_s = {v}", "[gravity]", "model = \"egm96\"", "[gravity.sh]", "nmax = {v}",
                   "[sensor_faults]", "[[sensor_faults.fault]]", "kind = \"step\"", "sensor = {v}", "[platform]",
                   "kind = \"strapdown\"", "c_m = {v}", "[bogus]", "= ="]

SCENARIO_LINES = ["name = \"f\"", "[trajectory]", "type = \"north-flight\"", "speed_mps = {v}", "height_m = {v}",
                  "[time]", "duration_s = {v}", "rate_hz = {v}", "[accel]", "bias_sigma_mps2 = {v}",
                  "noise_sigma_mps2 = [{v}, 1, 2]", "[initial]", "gravity_sigma_mps2 = [{v}, {v}]",
                  "position_sigma_m = {v}", "[bogus]", "x = 1", "[baro]", "noise_sigma_m = {v}", "[navigation.baro]",
                  "enable = true", "poles_radps = [{v}, 0.1, 0.1]", "= =", "[platform]", "a_m = {v}"]


CAMPAIGN_LINES = ["[campaign]", "name = \"c\"", "command = \"run\"", "command = \"rw-eq8\"", "command = {v}",
                  "scenario = \"welker-table1\"", "scenario = {v}", "seeds = {v}", "seed0 = {v}", "[[point]]",
                  "name = {v}", "\"--hours\" = {v}", "\"--hours\" = [{v}, 1]", "\"accel.bias_sigma_mps2\" = {v}",
                  "\"time.duration_s\" = {start = {v}, stop = 10, step = {v}}",
                  "\"--dt\" = {start = 0, stop = {v}, num = {v}}", "[outputs]", "series_dt = {v}", "[bogus]", "= ="]

LCM_SYNC = 0xEDA1DA01


def lcm_log(rng):
    """A byte string shaped like an LCM event log: events with random channels (some of the
    ggins channels), payloads of random bytes, and one of the corruptions a log meets (cut
    short, a bad sync word, an absurd length, time going back)."""
    import struct
    out = b""
    t = 1_000_000
    for k in range(rng.randint(0, 6)):
        ch = rng.choice(["GG3D_OUTPUT", "GG_FRAME", "GG_OUTPUT", "GG3D_FRAME", "x", ""]).encode()
        data = bytes(rng.getrandbits(8) for _ in range(rng.randint(0, 64)))
        t += rng.choice([10_000, 0, -5_000_000])
        dlen = len(data)
        if rng.random() < 0.1:
            dlen = rng.choice([0x7FFFFFFF, -1, 1 << 30])
        sync = LCM_SYNC if rng.random() > 0.05 else 0xDEADBEEF
        out += struct.pack(">IqqiI" if dlen >= 0 else ">Iqqii", sync, k, t, len(ch), dlen) + ch + data
    if out and rng.random() < 0.3:
        out = out[:rng.randint(0, len(out))]
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True)
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=5.0)
    ap.add_argument("--only", default="", help="comma-separated tools to fuzz (e.g. ggins-campaign,ggins-logtime); "
                    "default every built one")
    ap.add_argument("--show", type=int, default=-1, help="print each run with this exit code and its first stderr line")
    a = ap.parse_args()
    a.bin = os.path.abspath(a.bin)
    rng = random.Random(a.seed)
    tmp = tempfile.mkdtemp(prefix="ggins-clifuzz-")
    a_file = os.path.join(tmp, "a_file")
    open(a_file, "w").write("x\n")
    tools = [t for t in TOOLS if os.path.exists(os.path.join(a.bin, TOOLS[t].get("exe", t)))]
    if a.only:
        want = a.only.split(",")
        unknown = [w for w in want if not any(t == w or TOOLS[t].get("exe") == w for t in TOOLS)]
        if unknown:
            ap.error(f"--only: unknown tool(s) {unknown}; known: {sorted(TOOLS)}")
        tools = [t for t in tools if t in want or TOOLS[t].get("exe") in want]
        if not tools:
            ap.error(f"--only: none of {want} is built in {a.bin}")
    findings, counts, killed = [], {c: 0 for c in DOCUMENTED}, 0
    for i in range(a.runs):
        tool = tools[i % len(tools)]
        spec = TOOLS[tool]
        scen = os.path.join(tmp, f"s{i}.toml")
        vals = VALUES[:12] + ["1", "0.5", "\"s\"", "true", "[]"]
        lines = rng.sample(SCENARIO_LINES, rng.randint(1, len(SCENARIO_LINES)))
        open(scen, "w").write("\n".join(l.replace("{v}", rng.choice(vals)) for l in lines) + "\n")
        scen3 = os.path.join(tmp, f"s3_{i}.toml")
        lines = rng.sample(SCENARIO3_LINES, rng.randint(1, len(SCENARIO3_LINES)))
        open(scen3, "w").write("\n".join(l.replace("{v}", rng.choice(vals)) for l in lines) + "\n")
        camp = os.path.join(tmp, f"c{i}.toml")
        lines = rng.sample(CAMPAIGN_LINES, rng.randint(1, len(CAMPAIGN_LINES)))
        open(camp, "w").write("\n".join(l.replace("{v}", rng.choice(vals)) for l in lines) + "\n")
        log = os.path.join(tmp, f"l{i}.lcmlog")
        open(log, "wb").write(lcm_log(rng))
        subst = {"{missing}": os.path.join(tmp, "missing"), "{out}": os.path.join(tmp, f"o{i}"),
                 "{under_file}": os.path.join(a_file, "sub"), "{a_file}": a_file, "{scenario}": scen,
                 "{scenario3}": scen3, "{campaign}": camp, "{log}": log,
                 "{channel}": rng.choice(["GG3D_OUTPUT", "GG_FRAME", "GG_OUTPUT", "x", ""])}
        args = list(spec["base"])
        for opt in rng.sample(sorted(spec["opts"]), rng.randint(1, min(3, len(spec["opts"])))):
            v = rng.choice(VALUES) if rng.random() < 0.6 else rng.choice(spec["opts"][opt])
            if opt == "":  # a positional argument
                args += [v]
            else:
                args += [opt] if spec["opts"][opt] == [""] else [opt, v]
        for k, v in subst.items():
            args = [x.replace(k, v) for x in args]
        cmd = [os.path.join(a.bin, spec.get("exe", tool))] + args
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=a.timeout, cwd=tmp)
        except subprocess.TimeoutExpired:
            killed += 1
            continue
        if r.returncode == a.show:
            print(f"exit {r.returncode}: {' '.join(args)[:150]} | {(r.stderr.strip().splitlines() or [''])[-1][:200]}")
        bad = r.returncode not in DOCUMENTED or "terminate called" in r.stderr
        if r.returncode != 0 and not (r.stderr.strip() or r.stdout.strip()):
            bad = True  # a failure must say why (replay gives its verdict on stdout)
        if bad:
            findings.append((cmd, r.returncode, r.stderr[-600:]))
        else:
            counts[r.returncode] += 1
    for cmd, rc, err in findings:
        print(f"FINDING exit {rc}: {' '.join(repr(x) for x in cmd)}\n{err}")
    print(f"cli_fuzz: {a.runs} runs of {', '.join(tools)}: " +
          ", ".join(f"exit {c} {n}" for c, n in counts.items() if n) +
          f", killed at {a.timeout:g} s {killed}, findings {len(findings)}")
    print(f"{a.runs - len(findings)} passed, {len(findings)} failed")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
