#!/usr/bin/env python3
"""Plot ggins-covariance output: one-sigma position, velocity and gravity errors
against time, and the unstable mode's part of the position error against
exp(sqrt(2) w_s t) (Welker, Pachter & Huffman, section VI).

usage: plot_covariance.py covariance.csv covariance.png [--title T]
Needs matplotlib (Debian python3-matplotlib: run with /usr/bin/python3).
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from ggins_plot_common import read_csv_figure, save  # noqa: E402


def main():
    a, col, t, fig, ax = read_csv_figure()
    panels = [
        (ax[0, 0], [("x_m", "δx"), ("z_m", "δz")], 1.0, "position error 1σ [m]"),
        (ax[0, 1], [("vx_mps", "δv_x"), ("vz_mps", "δv_z")], 100.0, "velocity error 1σ [cm/s]"),
        (ax[1, 0], [("gx_mps2", "δG_x"), ("gz_mps2", "δG_z")], 1e3, "gravity error 1σ [mm/s²]"),
    ]
    for axis, series, scale, label in panels:
        for key, name in series:
            if key in col:
                axis.plot(t, [v * scale for v in col[key]], label=name)
        axis.set_xlabel("time [min]")
        axis.set_ylabel(label)
        axis.grid(True, alpha=0.3)
        axis.legend()
    # Unstable mode: its part of δx against exp(sqrt2 w_s t), matched at the end.
    axis = ax[1, 1]
    if "unstable_x_m" in col:
        ts = col["t_s"]
        lam = col["lambda_u_ps"][-1]
        axis.semilogy(t, col["x_m"], label="δx 1σ (total)")
        axis.semilogy(t, col["unstable_x_m"], "--", label="δx 1σ, unstable-mode part")
        ref_end = col["unstable_x_m"][-1]
        ref = [ref_end * math.exp(lam * (s - ts[-1])) for s in ts]
        axis.semilogy(t, ref, ":", label="∝ exp(√2 ω_s t), λ=%.4g/s" % lam)
        axis.set_ylim(max(1e-6, min(v for v in col["x_m"] if v > 0)), 2 * max(col["x_m"]))
        axis.set_xlabel("time [min]")
        axis.set_ylabel("[m]")
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize=8)
    save(fig, "ggins covariance: %s" % a.title, a.png)


if __name__ == "__main__":
    main()
