#!/usr/bin/env python3
"""Plots of one `ggins run3d` output folder: errors.png (position error N/E/D,
attitude error, gravity error, gradient error against time) from
timeseries.csv and summary.json.

usage: plot_run3d.py OUTPUT_DIR
Needs matplotlib and numpy (Debian: python3-matplotlib python3-numpy).
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def logplot(ax, t, y, label, color):
    y = np.abs(np.asarray(y, dtype=float))
    y = np.where(y > 0, y, np.nan)
    ax.semilogy(t, y, color=color, lw=0.9, label=label)


def main(out):
    d = np.genfromtxt(os.path.join(out, "timeseries.csv"), delimiter=",", names=True)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    t = d["t_s"]
    tl = "time [s]"
    if t[-1] > 3 * 3600:
        t, tl = t / 3600.0, "time [h]"
    elif t[-1] > 600:
        t, tl = t / 60.0, "time [min]"
    fig, axs = plt.subplots(4, 1, figsize=(9, 12), sharex=True)
    ax = axs[0]
    for c, (k, lab) in enumerate([("err_n_m", "north"), ("err_e_m", "east"), ("err_d_m", "down")]):
        logplot(ax, t, d[k], "|%s|" % lab, "C%d" % c)
    logplot(ax, t, d["err_r_m"], "|dr|", "k")
    ax.set_ylabel("position error [m]")
    ax = axs[1]
    for c, (k, lab) in enumerate([("att_err_n_rad", "north"), ("att_err_e_rad", "east"), ("att_err_d_rad", "down")]):
        logplot(ax, t, d[k], "|psi %s|" % lab, "C%d" % c)
    logplot(ax, t, d["att_err_rad"], "|psi|", "k")
    ax.set_ylabel("attitude error [rad]")
    ax = axs[2]
    for c, (k, lab) in enumerate([("err_gn_mps2", "north"), ("err_ge_mps2", "east"), ("err_gd_mps2", "down")]):
        logplot(ax, t, d[k], "|dG %s|" % lab, "C%d" % c)
    logplot(ax, t, d["err_g_mps2"], "|dG|", "k")
    ax.set_ylabel("gravity error [m/s^2]")
    ax = axs[3]
    logplot(ax, t, d["err_gamma_e_E"], "max |dGamma| (ECEF)", "C0")
    logplot(ax, t, d["err_gamma_b_E"], "max |dGamma| (body)", "C1")
    ax.axhline(1e-4, color="C3", ls="--", lw=0.8, label="1e-4 E")
    ax.set_ylabel("gradient error [E]")
    for ax in axs:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", ncol=4)
    axs[-1].set_xlabel(tl)
    fig.suptitle("%s (%s, %s): final |dr| %.3g m, |psi| %.3g rad, |dG| %.3g m/s^2, max |dGamma| %.3g E" % (
        s["scenario"], s["platform"], s["mode"].split(" ")[0], s["errors"]["position_error_m"]["final"],
        s["errors"]["attitude_error_rad"]["final"], s["errors"]["gravity_error_mps2"]["final"], s["errors"]["gradient_error_ecef_E"]["max"]), fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "errors.png"), dpi=100)
    plt.close(fig)
    print("plots: %s" % os.path.join(out, "errors.png"))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    main(sys.argv[1])
