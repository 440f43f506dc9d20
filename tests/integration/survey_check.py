#!/usr/bin/env python3
"""Programmed anomaly grid over LCM (column b of docs/comparison.md).

Truth: a spherical point-mass Earth. Onboard model: the same GM plus a J2 term
the truth does not have, so the model is wrong by the J2 part, whose
along-track (north) component is, independently of any project code,
  dg_n = -(GM / r^2) J2 (a / r)^2 3 sin(phi) cos(phi)     (phi geocentric latitude).
  without grid  the conventional INS's along-track error follows the Schuler
                response to that error, dx = dg_n (1 - cos w t) / w^2 (dg_n averaged
                over the track; within 10 %);
  with grid     [navigation.survey] without noise programs exactly truth minus
                model at the nodes (2 km): the error stays below 1 cm (bilinear
                interpolation of the smooth J2 field: ~1e-9 m/s^2);
  replay        the grid run's log replays bit for bit (ggins replay: the grid
                travels in the configuration message).
A perfect barometer damps the vertical channel in both. Python stdlib only.
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys

GM = 3.986004418e14
A = 6378137.0
J2 = 1.08262982131e-3
H = 3000.0
V = 300.0
LAT0 = 20.0
T = 300.0
FAILURES = []


def check(ok, what):
    print("%s %s" % ("ok  " if ok else "FAIL", what))
    if not ok:
        FAILURES.append(what)


def scenario(path, survey):
    text = """name = "survey-check"
[trajectory]
type = "north-flight"
speed_mps = %r
height_m = %r
lat0_deg = %r
radius_m = %r
[gravity]
model = "point-mass"
gm_m3ps2 = %r
[time]
duration_s = %r
rate_hz = 10.0
[navigation]
gravity = "model"
[navigation.model]
gm_m3ps2 = %r
a_m = %r
j = [%r]
[navigation.baro]
enable = true
poles_radps = [0.01, 0.02, 0.03]
[baro]
enable = true
rate_hz = 10.0
""" % (V, H, LAT0, A, GM, T, GM, A, J2)
    if survey:
        text += """[navigation.survey]
spacing_m = 2000.0
margin_m = 20000.0
noise_gravity_mgal = 0.0
noise_deflection_arcsec = 0.0
"""
    with open(path, "w") as f:
        f.write(text)
    return path


def run(ggins_run, out, sc, log):
    if os.path.exists(out):
        shutil.rmtree(out)
    cmd = [ggins_run, "--out", out, "--progress", "off", "--no-plots", "-s", sc] + ([] if log else ["--no-log"])
    print("$ " + " ".join(cmd))
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    print(p.stdout.rstrip())
    check(p.returncode == 0, "ggins-run exit status 0 (got %d)" % p.returncode)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    return s, rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ggins-run", required=True)
    ap.add_argument("--ggins-replay", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    rho = A + H
    w = math.sqrt(GM / rho ** 3)

    # (1) model error without a grid: Schuler response to the J2 term's north component
    s, rows = run(a.ggins_run, os.path.join(a.workdir, "nogrid"), scenario(os.path.join(a.workdir, "nogrid.toml"), False), False)
    check("survey_grid" not in s, "no survey_grid without [navigation.survey]")
    n = 200
    dgs = []
    for i in range(n + 1):
        phi = math.radians(LAT0) + V * T * i / n / rho
        dgs.append(-(GM / rho ** 2) * J2 * (A / rho) ** 2 * 3 * math.sin(phi) * math.cos(phi))
    dg = sum(dgs) / len(dgs)
    pred = dg * (1 - math.cos(w * T)) / w ** 2
    got = float(rows[-1]["err_along_m"])
    check(abs(got - pred) < 0.1 * abs(pred) and abs(pred) > 100,
          "without grid: along-track error at %g s %.1f m, predicted %.1f m (dg_n %.3e m/s^2)" % (T, got, pred, dg))

    # (2) the same with the noise-free survey grid programmed
    out = os.path.join(a.workdir, "grid")
    s, rows = run(a.ggins_run, out, scenario(os.path.join(a.workdir, "grid.toml"), True), True)
    g = s.get("survey_grid", {})
    n_th = math.ceil((V * T + 2 * 20000.0) / 2000.0) + 1
    check(g.get("nodes_theta") == n_th and g.get("nodes_rho") == 2,
          "summary survey_grid: %s x %s nodes (expected %d x 2)" % (g.get("nodes_theta"), g.get("nodes_rho"), n_th))
    check(abs(g.get("rms_true_tangential_mps2", 0) - abs(dg)) < 0.1 * abs(dg),
          "grid tangential rms %.3e m/s^2 = |dg_n| %.3e within 10 %%" % (g.get("rms_true_tangential_mps2", 0), abs(dg)))
    worst = max(abs(float(r["err_along_m"])) for r in rows)
    check(worst < 0.01, "with grid: max |along-track error| %.2e m (< 0.01 m)" % worst)
    health = s.get("health_counts", {})
    check(not any("MODEL_OUTSIDE" in k for k in health), "never outside the grid (health %s)" % health)

    # (3) replay of the grid run: bit for bit
    p = subprocess.run([a.ggins_replay, os.path.join(out, "run.lcmlog")], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, timeout=600)
    print(p.stdout.rstrip())
    check(p.returncode == 0 and "BIT-EXACT" in p.stdout, "replay of the grid run bit-exact")

    print("FAILED: %d" % len(FAILURES) if FAILURES else "all passed")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
