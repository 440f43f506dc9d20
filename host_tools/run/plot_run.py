#!/usr/bin/env python3
"""Plots of one `ggins run` output folder: errors.png (position, velocity and
gravity error against time, per axis and norm) from timeseries.csv.

usage: plot_run.py OUTPUT_DIR
Needs matplotlib and numpy (Debian: python3-matplotlib python3-numpy).
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = sys.argv[1]
    d = np.genfromtxt(os.path.join(out, "timeseries.csv"), delimiter=",", names=True)
    d = np.atleast_1d(d)
    try:
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
    except (OSError, ValueError):
        s = {}
    t = d["t_s"]
    unit, tl = (3600.0, "time [h]") if t[-1] > 7200 else ((60.0, "time [min]") if t[-1] > 300 else (1.0, "time [s]"))
    t = t / unit
    rows = [("err_r", "position error [m]", "err_r_norm_m"),
            ("err_v", "velocity error [m/s]", "err_v_norm_mps"),
            ("err_g", "gravity error [m/s$^2$]", "err_g_norm_mps2")]
    fig, axs = plt.subplots(len(rows), 1, figsize=(9, 9), sharex=True)
    for ax, (p, label, norm) in zip(axs, rows):
        for a, c in (("x", "C0"), ("z", "C1")):
            ax.plot(t, d[p + "_" + a], c, label=a)
        ax.plot(t, d[norm], "k:", lw=1, label="norm")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper left", fontsize=8)
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
    axs[-1].set_xlabel(tl)
    title = "ggins run: %s" % s.get("scenario", os.path.basename(out))
    if s:
        title += "  (%s, %d steps, frames lost %s)" % (s.get("mode", "?"), s.get("steps", 0), s.get("frames_lost", "?"))
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "errors.png"), dpi=110)
    plt.close(fig)

    # the same errors on a log scale: the numerical floor and the unstable mode
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for p, label, norm in rows:
        y = np.abs(d[norm])
        ax.semilogy(t, np.where(y > 0, y, np.nan), label=label.replace(" error", ""))
    ax.set_xlabel(tl)
    ax.set_ylabel("error norm (SI units)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "errors_log.png"), dpi=110)
    plt.close(fig)
    print("plots: %s, %s" % (os.path.join(out, "errors.png"), os.path.join(out, "errors_log.png")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
