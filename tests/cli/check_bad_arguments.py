#!/usr/bin/env python3
"""Bad command-line values and scenario keys of the host tools: each case must exit with
the expected code (2: bad arguments, 1: the run failed), name the option or key in
stderr, and never die of a signal or an uncaught exception (exit 134 / 139, 'terminate').

usage: check_bad_arguments.py ggins-run3d=/path/to/ggins-run3d ...
"""
import os
import subprocess
import sys
import tempfile

tools = dict(a.split("=", 1) for a in sys.argv[1:])
tmp = tempfile.mkdtemp(prefix="ggins-cli-")
afile = os.path.join(tmp, "a_file")
open(afile, "w").write("not a folder\n")
out = os.path.join(tmp, "out")


def scen(name, text):
    p = os.path.join(tmp, name + ".toml")
    open(p, "w").write(text)
    return p


BASE = """name = "cli-test"
[trajectory]
type = "north-flight"
speed_mps = 300.0
[time]
duration_s = 60.0
rate_hz = 10.0
[accel]
bias_sigma_mps2 = 2e-12
"""
typo_key = scen("typo_key", BASE.replace("speed_mps", "sped_mps"))
unknown_section = scen("unknown_section", BASE + "[trajectoryy]\nspeed_mps = 1.0\n")
unknown_initial = scen("unknown_initial", BASE + "[initial]\nposition_sigma = 1.0\n")
nan_sigma = scen("nan_sigma", BASE.replace("bias_sigma_mps2 = 2e-12", "bias_sigma_mps2 = nan"))
neg_sigma = scen("neg_sigma", BASE + "[initial]\nvelocity_sigma_mps = -1.0\n")
nan_axis = scen("nan_axis", BASE.replace("bias_sigma_mps2 = 2e-12", "bias_sigma_mps2 = [1e-12, nan, 1e-12, 1e-12, 1e-12, 1e-12, 1e-12, 1e-12]"))
axes = scen("axes", BASE.replace("bias_sigma_mps2 = 2e-12", "bias_sigma_mps2 = [1e-12, 2e-12, 1e-12, 1e-12, 1e-12, 1e-12, 1e-12, 1e-12]"))
empty = scen("empty", "# nothing\n")
nan_rate = scen("nan_rate", "[time]\nrate_hz = nan\n")
good = scen("good", BASE + "[initial]\ngravity_sigma_mps2 = [1e-12, 3e-12]\n")
# A user's file with comments, blank lines and the covariance-only [initial] table before
# the others: an error names the user's file and the key's line there (counted by hand).
HEAD = '# a user\'s scenario\n\nname = "cli-test"\n\n[initial]\nposition_sigma_m = 1.0\n\n'  # 7 lines
BODY = BASE[BASE.index("[trajectory]"):]  # line 8 on: [trajectory], type, speed_mps, [time], duration_s, rate_hz, ...
typo_line = scen("typo_line", HEAD + BODY.replace("speed_mps", "sped_mps"))  # line 10
bad_value_line = scen("bad_value_line", HEAD + BODY.replace("rate_hz = 10.0", "rate_hz = -10.0"))  # line 13
typo_initial_line = scen("typo_initial_line", HEAD.replace("position_sigma_m", "position_sigma") + BODY)  # line 6
bad_axis_line = scen("bad_axis_line", HEAD + BODY.replace(  # bias_sigma_mps2 on line 15, its element 5 on line 17
    "bias_sigma_mps2 = 2e-12", "bias_sigma_mps2 = [\n  1e-12, 1e-12, 1e-12, 1e-12,\n  1e-12, -1e-12, 1e-12, 1e-12]"))
bad_initial_line = scen("bad_initial_line", "# x\n" + BASE + "\n[initial]\nvelocity_sigma_mps = nan\n")  # line 13

GMAP = ["--lat-min", "45", "--lat-max", "45.05", "--lon-min", "10", "--lon-max", "10.05"]

# (tool, arguments, expected exit code, text that stderr must contain)
CASES = [
    ("ggins-covariance", ["-s", typo_key, "--no-plot", "-o", out + "/c1"], 2, "sped_mps"),
    ("ggins-covariance", ["-s", unknown_section, "--no-plot", "-o", out + "/c2"], 2, "trajectoryy"),
    ("ggins-covariance", ["-s", unknown_initial, "--no-plot", "-o", out + "/c3"], 2, "initial.position_sigma"),
    ("ggins-covariance", ["-s", nan_sigma, "--no-plot", "-o", out + "/c4"], 2, "bias_sigma_mps2"),
    ("ggins-covariance", ["-s", neg_sigma, "--no-plot", "-o", out + "/c5"], 2, "initial.velocity_sigma_mps"),
    ("ggins-covariance", ["-s", nan_axis, "--no-plot", "-o", out + "/c7"], 2, "bias_sigma_mps2"),
    ("ggins-covariance", ["-s", empty, "--no-plot", "-o", out + "/c6"], 2, "sets no key"),
    ("ggins-covariance", ["-s", typo_line, "--no-plot", "-o", out + "/c8"], 2, "typo_line.toml:10: unknown key 'trajectory.sped_mps'"),
    ("ggins-covariance", ["-s", bad_value_line, "--no-plot", "-o", out + "/c9"], 2, "bad_value_line.toml:13: time.rate_hz = -10"),
    ("ggins-covariance", ["-s", bad_initial_line, "--no-plot", "-o", out + "/c10"], 2,
     "bad_initial_line.toml:13: initial.velocity_sigma_mps = nan"),
    ("ggins-covariance", ["-s", typo_initial_line, "--no-plot", "-o", out + "/c11"], 2,
     "typo_initial_line.toml:6: unknown key 'initial.position_sigma'"),
    ("ggins-covariance", ["-s", bad_axis_line, "--no-plot", "-o", out + "/c12"], 2,
     "bad_axis_line.toml:17: accel.bias_sigma_mps2[5] = -1e-12"),
    ("ggins-covariance", ["--duration", "nan"], 2, "--duration"),
    ("ggins-covariance", ["--dt", "nan"], 2, "--dt"),
    ("ggins-covariance", ["--sigma-g0", "nan"], 2, "--sigma-g0"),
    ("ggins-covariance", ["--duration", "1e9", "--dt", "1e-3"], 2, "--dt"),
    ("ggins-covariance", ["-o", os.path.join(afile, "sub")], 2, "--out"),
    ("ggins-covariance3d", ["--acc-bias-sigma", "nan"], 2, "--acc-bias-sigma"),
    ("ggins-covariance3d", ["--duration", "nan"], 2, "--duration"),
    ("ggins-covariance3d", ["--half-base", "0", "0.5", "0.5"], 2, "--half-base"),
    ("ggins-covariance3d", ["--lat0-deg", "inf"], 2, "--lat0-deg"),
    ("ggins-covariance3d", ["-o", os.path.join(afile, "sub")], 2, "--out"),
    ("ggins-covariance3d", ["--g0-sigma", "1e308"], 2, "--g0-sigma"),
    ("ggins-covariance3d", ["--dt", "1e4", "--duration", "60"], 2, "--dt"),
    ("ggins-covariance", ["--dt", "100", "--duration", "60"], 2, "--dt"),
    ("ggins-gmap", ["--lat-min", "nan", "--lat-max", "1", "--lon-min", "0", "--lon-max", "1", "--out", out + "/g.bin"], 2,
     "--lat-min"),
    ("ggins-gmap", GMAP + ["--out", os.path.join(afile, "sub")], 2, "--out"),
    ("ggins-gmap", GMAP + ["--json", os.path.join(afile, "sub")], 2, "--json"),
    ("ggins-gmap", GMAP + ["--seed", "-1", "--out", out + "/g.bin"], 2, "--seed"),
    ("ggins-gmap", GMAP + ["--threads", "0", "--out", out + "/g.bin"], 2, "--threads"),
    ("ggins-gmap", GMAP + ["--spacing", "nan", "--out", out + "/g.bin"], 2, "--spacing"),
    ("ggins-field", ["--gm", "nan"], 2, "--gm"),
    ("ggins-field", ["--seed", "-1"], 2, "--seed"),
    ("ggins-field", ["--step", "nan"], 2, "--step"),
    ("ggins-field", ["--model", "normal", "--at", "45,0,0", "-o", os.path.join(afile, "sub")], 2, "--out"),
    ("ggins-field", ["--model", "normal", "--at", "95,0,0"], 2, "latitude"),
    ("ggins-field", ["--model", "normal", "--at", "45,nan,0"], 2, "--at"),
    ("ggins-field", ["--model", "normal"], 2, "no points"),
    ("ggins-profile", ["--duration", "nan"], 2, "--duration"),
    ("ggins-profile", ["--keep", os.path.join(afile, "sub")], 2, "--keep"),
    ("ggins-run", ["-s", empty, "--print-scenario"], 2, "sets no key"),
    ("ggins-run", ["-s", nan_rate, "--print-scenario"], 2, "time.rate_hz = nan"),
    ("ggins-run", ["--defaults"], 2, "--defaults"),
    ("ggins-run3d", ["-s", empty, "--print-scenario"], 2, "sets no key"),
    ("ggins-run3d", ["-s", nan_rate, "--print-scenario"], 2, "time.rate_hz = nan"),
    ("ggins-spy", ["--check", "--bogus"], 2, "--bogus"),
    ("ggins-spy", ["--check", "--lcm-url=udp://x"], 2, "udp://x"),
    ("ggins-spy", ["--check", "--lcm-url="], 2, "--lcm-url"),
    ("ggins-spy", ["--check", "-l"], 2, "-l"),
    ("ggins-spy", ["--check", "-l", "udpm://a", "--lcm-url=udpm://b"], 2, "twice"),
]
# controls: valid command lines still run (the checks do not refuse good input)
CONTROLS = [
    ("ggins-covariance", ["-s", good, "--no-plot", "-o", out + "/good"], 0, ""),
    ("ggins-covariance", ["-s", axes, "--no-plot", "-o", out + "/axes"], 0, ""),
    ("ggins-covariance3d", ["--duration", "60", "--no-plot", "-o", out + "/good3d"], 0, ""),
    ("ggins-field", ["--model", "normal", "--at", "45,10,1000"], 0, ""),
    ("ggins-run", ["--print-scenario", "--defaults"], 0, ""),
    ("ggins-run3d", ["-s", "3d-route-45n", "--print-scenario"], 0, ""),
    ("ggins-spy", ["--check", "--lcm-url=udpm://239.255.76.67:7667?ttl=0"], 0, ""),
    ("ggins-spy", ["--check", "-l", "file:///tmp/x.lcmlog"], 0, ""),
]

failed = 0
passed = 0
for tool, args, want, needle in CASES + CONTROLS:
    if tool not in tools:
        print(f"skip {tool} (not built)")
        continue
    r = subprocess.run([tools[tool]] + args, capture_output=True, text=True, timeout=60, cwd=tmp)
    err = r.stderr
    ok = r.returncode == want and needle in err and "terminate" not in err
    if want == 2:  # the message gives the allowed values
        ok = ok and ("allowed" in err or "not in" in err or "unknown key" in err or "must be" in err)
    line = f"{tool} {' '.join(args)}: exit {r.returncode} (want {want})"
    if ok:
        passed += 1
        print("ok   " + line + " | " + (err.strip().splitlines() or [""])[0][:150])
    else:
        failed += 1
        print("FAIL " + line + f", stderr must name '{needle}':\n" + err[-800:])
print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
