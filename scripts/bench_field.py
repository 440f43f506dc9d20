#!/usr/bin/env python3
"""Point synthesis, side by side in one run: ggins (gravity_eval_points) vs
pyshtools.gravmag.MakeGravGridPoint on the same random points.

Degree 360 (EGM96): CPU time per point of pyshtools for G alone and of ggins
for V + G + Gamma (precisions mixed, double, long double, and the Cunningham
engine), the ratio, and the agreement per component (G against pyshtools in
spherical components r, theta, phi; all ten components against the
Cunningham long-double evaluation).
Degree 2190 (a synthetic Kaula-rule set, synthetic_kaula(2190, seed 1)): time
per point of both, G against pyshtools, V, G, Gamma of mixed against long
double. Times are thread CPU time (time.thread_time / CLOCK_THREAD_CPUTIME_ID),
best of --reps passes.
"""
import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np

GM96, R96 = 3.986004415e14, 6378136.3


def points(n, seed, r0):
    rng = np.random.default_rng(seed)
    lat = rng.uniform(-80, 80, n)          # geocentric latitude, deg
    lon = rng.uniform(0, 360, n)
    h = rng.uniform(0, 10e3, n)            # above the sphere r = a
    r = r0 + h
    th, ph = np.radians(90 - lat), np.radians(lon)
    xyz = np.stack([r * np.sin(th) * np.cos(ph), r * np.sin(th) * np.sin(ph), r * np.cos(th)], axis=1)
    return lat, lon, r, xyz


def run_ours(exe, model, nmax, prec, xyz, reps, dump=None):
    cmd = [exe, model, str(nmax), "--prec", prec, "--reps", str(reps)]
    if dump:
        cmd += ["--dump", dump]
    inp = "\n".join(" ".join(f"{v:.17e}" for v in p) for p in xyz) + "\n"
    out = subprocess.run(cmd, input=inp, capture_output=True, text=True, check=True)
    us = float([l for l in out.stderr.splitlines() if l.startswith("cpu_us_per_point")][0].split()[1])
    vals = np.array([[np.longdouble(t) for t in line.split()] for line in out.stdout.strip().splitlines()], dtype=np.longdouble)
    return us, vals


def pysh_g(pysh, cilm, gm, r0, lat, lon, r, reps):
    best, res = 1e300, None
    for _ in range(reps):
        t0 = time.thread_time()
        res = [pysh.gravmag.MakeGravGridPoint(cilm, gm, r0, r[i], lat[i], lon[i]) for i in range(len(r))]
        best = min(best, (time.thread_time() - t0) / len(r))
    return 1e6 * best, np.array(res)


def sph(vals, lat, lon):
    th, ph = np.radians(90 - lat), np.radians(lon)
    rh = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], 1)
    thh = np.stack([np.cos(th) * np.cos(ph), np.cos(th) * np.sin(ph), -np.sin(th)], 1)
    phh = np.stack([-np.sin(ph), np.cos(ph), 0 * ph], 1)
    g = vals[:, 1:4].astype(float)
    return np.stack([(g * rh).sum(1), (g * thh).sum(1), (g * phh).sum(1)], 1)


NAMES = ["V", "gx", "gy", "gz", "Gxx", "Gxy", "Gxz", "Gyy", "Gyz", "Gzz"]


def diff_line(a, b):
    d = np.max(np.abs((a - b).astype(np.longdouble)), axis=0)
    parts = []
    for k, name in enumerate(NAMES):
        parts.append(f"{name} {float(d[k]) * (1e9 if k >= 4 else 1):.1e}")
    return "  ".join(parts) + "   (V m^2/s^2, g m/s^2, Gamma E)"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--eval", required=True)
    ap.add_argument("--egm96", required=True)
    ap.add_argument("--npts", type=int, default=200)
    ap.add_argument("--npts2190", type=int, default=8)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--seed", type=int, default=2024)
    ap.add_argument("--skip2190", action="store_true")
    args = ap.parse_args()
    import pyshtools as pysh
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, load {os.getloadavg()}; "
          f"pyshtools {pysh.__version__}, numpy {np.__version__}")

    # ---- degree 360, EGM96 ----
    L = 360
    raw = np.loadtxt(args.egm96)
    cilm = np.zeros((2, L + 1, L + 1))
    for n, m, c, s in raw[:, :4]:
        n, m = int(n), int(m)
        if n <= L:
            cilm[0, n, m], cilm[1, n, m] = c, s
    cilm[0, 0, 0] = 1.0
    lat, lon, r, xyz = points(args.npts, args.seed, R96)
    t_py, g_py = pysh_g(pysh, cilm, GM96, R96, lat, lon, r, args.reps)
    res = {}
    for prec in ["mixed", "double", "ld"]:
        res[prec] = run_ours(args.eval, args.egm96, L, prec, xyz, args.reps)
    res["cunningham"] = run_ours(args.eval, args.egm96, L, "cunningham", xyz, 1)
    print(f"\ndegree 360 (EGM96), {args.npts} points, lat +-80 deg, h 0-10 km, CPU us per point (best of {args.reps}):")
    print(f"  pyshtools MakeGravGridPoint (G only)        {t_py:10.1f}")
    for prec, label in [("mixed", "ggins V+G+Gamma, mixed (ld n<=8, double)"), ("double", "ggins V+G+Gamma, double"),
                        ("ld", "ggins V+G+Gamma, long double"), ("cunningham", "ggins Cunningham engine (long double)")]:
        print(f"  {label:<44s}{res[prec][0]:10.1f}   ratio to pyshtools {res[prec][0] / t_py:6.3f}")
    ratio = res["mixed"][0] / t_py
    print(f"RATIO mixed V+G+Gamma / pyshtools G = {ratio:.3f} (target <= 0.333: {'MET' if ratio <= 1 / 3 else 'NOT MET'})")
    print("\naccuracy, degree 360:")
    for prec in ["mixed", "double", "ld"]:
        d = np.max(np.abs(sph(res[prec][1], lat, lon) - g_py), axis=0)
        print(f"  {prec:<6s} vs pyshtools:  g_r {d[0]:.1e}  g_theta {d[1]:.1e}  g_phi {d[2]:.1e} m/s^2")
    for prec in ["mixed", "double", "ld"]:
        print(f"  {prec:<6s} vs Cunningham long double:  " + diff_line(res[prec][1], res["cunningham"][1]))

    if args.skip2190:
        return 0
    # ---- degree 2190, synthetic Kaula set ----
    L = 2190
    lat, lon, r, xyz = points(args.npts2190, args.seed + 1, 6378136.3)
    with tempfile.TemporaryDirectory() as td:
        dump = os.path.join(td, "kaula.bin")
        res2 = {"mixed": run_ours(args.eval, "kaula:1", L, "mixed", xyz, args.reps, dump=dump)}
        with open(dump, "rb") as f:
            nmax = int(np.frombuffer(f.read(4), dtype=np.int32)[0])
            gm, a = np.frombuffer(f.read(16), dtype=np.float64)
            nc = (nmax + 1) * (nmax + 2) // 2
            c = np.frombuffer(f.read(8 * nc), dtype=np.float64)
            s = np.frombuffer(f.read(8 * nc), dtype=np.float64)
    res2["ld"] = run_ours(args.eval, "kaula:1", L, "ld", xyz, 1)
    cilm = np.zeros((2, L + 1, L + 1))
    n_idx = np.concatenate([np.full(n + 1, n) for n in range(L + 1)])
    m_idx = np.concatenate([np.arange(n + 1) for n in range(L + 1)])
    cilm[0, n_idx, m_idx], cilm[1, n_idx, m_idx] = c, s
    t_py2, g_py2 = pysh_g(pysh, cilm, gm, a, lat, lon, r, 1)
    print(f"\ndegree 2190 (synthetic_kaula(2190, 1)), {args.npts2190} points, CPU us per point:")
    print(f"  pyshtools MakeGravGridPoint (G only)        {t_py2:10.1f}")
    print(f"  ggins V+G+Gamma, mixed                      {res2['mixed'][0]:10.1f}   ratio {res2['mixed'][0] / t_py2:6.3f}")
    print(f"  ggins V+G+Gamma, long double                {res2['ld'][0]:10.1f}")
    for prec in ["mixed", "ld"]:
        d = np.max(np.abs(sph(res2[prec][1], lat, lon) - g_py2), axis=0)
        print(f"  {prec:<6s} vs pyshtools:  g_r {d[0]:.1e}  g_theta {d[1]:.1e}  g_phi {d[2]:.1e} m/s^2")
    print("  mixed vs long double:  " + diff_line(res2["mixed"][1], res2["ld"][1]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
