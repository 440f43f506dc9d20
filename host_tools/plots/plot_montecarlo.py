#!/usr/bin/env python3
"""Plot ggins-montecarlo output: every run's error with the covariance's
+-1 sigma / +-3 sigma envelopes and the Monte Carlo sample one-sigma.

usage: plot_montecarlo.py OUTDIR [--title T]   (reads montecarlo.csv, run_errors.csv)
"""
import argparse
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

KEYS = [("x_m", "δx [m]", 1.0), ("z_m", "δz [m]", 1.0), ("vx_mps", "δv_x [cm/s]", 100.0),
        ("vz_mps", "δv_z [cm/s]", 100.0), ("gx_mps2", "δG_x [mm/s²]", 1e3), ("gz_mps2", "δG_z [mm/s²]", 1e3)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    with open(os.path.join(a.outdir, "montecarlo.csv")) as f:
        rows = list(csv.DictReader(f))
    t = [float(r["t_s"]) / 60 for r in rows]
    runs = {}
    with open(os.path.join(a.outdir, "run_errors.csv")) as f:
        for r in csv.DictReader(f):
            runs.setdefault(r["run"], []).append(r)
    fig, ax = plt.subplots(3, 2, figsize=(12, 11))
    for i, (key, label, scale) in enumerate(KEYS):
        axis = ax[i // 2, i % 2]
        for rr in runs.values():
            axis.plot([float(r["t_s"]) / 60 for r in rr], [float(r[key]) * scale for r in rr],
                      color="0.6", lw=0.4, alpha=0.5)
        cov = [float(r["cov_" + key]) * scale for r in rows]
        mc = [float(r["mc_" + key]) * scale for r in rows]
        for m, style, name in ((1, "-", "±1σ covariance"), (3, "--", "±3σ covariance")):
            axis.plot(t, [m * c for c in cov], "b" + style, lw=1.2, label=name)
            axis.plot(t, [-m * c for c in cov], "b" + style, lw=1.2)
        axis.plot(t, mc, "r:", lw=1.5, label="Monte Carlo 1σ")
        axis.set_ylabel(label)
        axis.set_xlabel("time [min]")
        axis.grid(True, alpha=0.3)
        if i == 0:
            axis.legend(fontsize=8)
    fig.suptitle("ggins montecarlo: %s" % a.title)
    fig.tight_layout()
    fig.savefig(os.path.join(a.outdir, "montecarlo.png"), dpi=100)


if __name__ == "__main__":
    main()
