#!/usr/bin/env python3
"""Several `ggins run3d` flights of one route on one plot: the navigation
computers compared on the same sensors (for example gravity dead reckoning
with the map aid, dead reckoning alone, the model-mode INS with the map aid).

combination.png, against time, on log axes:
  1. the horizontal position error |dr_NE| of each flight, with its aid's
     one-sigma envelope (root sum square of the aid's position sigmas) where
     the flight had an aid;
  2. the vertical position error |dr_D| (the channel of the unstable mode:
     +sqrt(2) omega_s with gravity dead reckoning, +omega_s with a gravity
     model, omega_s^2 = 2 g / r);
  3. the gravity error |dG| (NED at the true position).
Errors are navigation minus truth; the NED frame is the local geodetic one at
the true position.

usage: plot_combination.py LABEL=OUTPUT_DIR [LABEL=OUTPUT_DIR ...] -o PNG
Needs matplotlib and numpy (Debian: python3-matplotlib python3-numpy).
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ggins_plot_common import FRAME_3D, envelope, log_line, read_run, time_axis  # noqa: E402


def parse_run(arg):
    if "=" not in arg:
        raise argparse.ArgumentTypeError("expected LABEL=OUTPUT_DIR, got %r" % arg)
    label, out = arg.split("=", 1)
    if not label or not os.path.isfile(os.path.join(out, "timeseries.csv")):
        raise argparse.ArgumentTypeError("%r: no timeseries.csv in %r" % (arg, out))
    return label, out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", type=parse_run, metavar="LABEL=OUTPUT_DIR", help="a flight and its legend label")
    ap.add_argument("-o", "--out", required=True, help="PNG to write")
    ap.add_argument("--title", default="", help="figure title (default: the first flight's scenario)")
    ap.add_argument("--clip-m", type=float, default=1e5,
                    help="top of the position axes, m (a diverging flight leaves the plot there; its legend says when)")
    a = ap.parse_args()
    fig, axs = plt.subplots(3, 1, figsize=(9, 10), sharex=True)
    tl = "time since start"
    title = a.title
    for c, (label, out) in enumerate(a.runs):
        d, s = read_run(out)
        t, tl = time_axis(d["t_s"])
        if not title:
            title = s.get("scenario", out)
        col = "C%d" % c
        h = np.hypot(np.asarray(d["err_n_m"], dtype=float), np.asarray(d["err_e_m"], dtype=float))
        r = np.asarray(d["err_r_m"], dtype=float)
        out_at = np.flatnonzero(~(r <= a.clip_m))
        if out_at.size:
            label = "%s (|dr| > %.0e m from %.3g %s)" % (label, a.clip_m, t[out_at[0]], tl.split("[")[-1].rstrip("]"))
        log_line(axs[0], t, h, label, col, lw=1.1)
        if "aid_sig_r_rss_m" in d.dtype.names and s.get("aids"):
            envelope(axs[0], t, d["aid_sig_r_rss_m"], label="%s: aid 1σ (RSS)" % label, color=col, log=True)
        log_line(axs[1], t, d["err_d_m"], label, col, lw=1.1)
        log_line(axs[2], t, d["err_g_mps2"], label, col, lw=1.1)
    axs[0].set_ylabel("horizontal position error |dr_NE| [m]")
    axs[1].set_ylabel("vertical position error |dr_D| [m]")
    axs[2].set_ylabel("gravity error |dG| [m/s²]")
    for ax in axs[:2]:
        ax.set_ylim(1e-1, a.clip_m)
    axs[2].set_ylim(1e-6, 10.0)
    axs[2].set_xlabel(tl)
    for ax in axs:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    fig.suptitle("%s\n%s" % (title, FRAME_3D), fontsize=9)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    print("plot_combination: %s" % a.out)


if __name__ == "__main__":
    main()
