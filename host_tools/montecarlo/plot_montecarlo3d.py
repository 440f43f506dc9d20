#!/usr/bin/env python3
"""Plot ggins-montecarlo3d output: sample one-sigma of N firmware runs (markers)
against the covariance one-sigma (lines), north/east/down, for position,
velocity, gravity and (strapdown) attitude.

usage: plot_montecarlo3d.py montecarlo3d.csv montecarlo3d.png [--title T]
Needs matplotlib (Debian python3-matplotlib: /usr/bin/python3).
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    with open(a.csv) as f:
        rows = list(csv.DictReader(f))
    col = {k: [float(r[k]) for r in rows] for k in rows[0]}
    t = [x / 60.0 for x in col["t_s"]]
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    panels = [
        (ax[0, 0], "r", "m", 1.0, "position error 1σ [m]"),
        (ax[0, 1], "v", "mps", 100.0, "velocity error 1σ [cm/s]"),
        (ax[1, 0], "g", "mps2", 1e3, "gravity error 1σ [mm/s²]"),
        (ax[1, 1], "psi", "rad", 1e6, "attitude error 1σ [µrad]"),
    ]
    colors = {"n": "C0", "e": "C1", "d": "C2"}
    for axis, b, u, scale, label in panels:
        if "cov_%sn_%s" % (b, u) not in col:
            axis.axis("off")
            continue
        top = 0.0
        for c, name in zip("ned", ["north", "east", "down"]):
            k = "%s%s_%s" % (b, c, u)
            cv = [(x, v * scale) for x, v in zip(t, col["cov_" + k]) if v > 0]
            mc = [(x, v * scale) for x, v in zip(t, col["mc_" + k]) if v > 0]
            if cv:
                axis.semilogy([p[0] for p in cv], [p[1] for p in cv], color=colors[c], label=name + " covariance")
                top = max(top, max(p[1] for p in cv))
            if mc:
                axis.semilogy([p[0] for p in mc], [p[1] for p in mc], "o", ms=3, color=colors[c],
                              label=name + " Monte Carlo")
        if top > 0:
            axis.set_ylim(top * 1e-6, top * 3)
        axis.set_xlabel("time [min]")
        axis.set_ylabel(label)
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize=7)
    fig.suptitle("ggins montecarlo3d: %s" % a.title)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
