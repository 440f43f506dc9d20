#!/usr/bin/env python3
"""Plots of one `ggins run3d` output folder (timeseries.csv, summary.json):
errors.png, against time on log axes: the position error north/east/down
(NED at the true position) and its norm, with a one-sigma envelope (root sum
square of the position sigmas): the aid's own covariance when the flight had
an aid, else the 3-D error model's along the same trajectory (OUTPUT_DIR/
covariance/covariance3d.csv, which `ggins run3d` computes with `ggins
covariance3d` from the scenario as flown); the attitude error, the gravity
error (NED) and the gradient error (Eotvos).

An aided flight's unaided reference (the same task with its aids off, flown
on the same frames: timeseries.csv unaided_err_*) is drawn on the same panel,
so aided and unaided are read off one plot; --unaided DIR adds the output
folder of another flight (e.g. one flown with --no-aids).

usage: plot_run3d.py OUTPUT_DIR [--unaided OUTPUT_DIR]
Needs matplotlib and numpy (Debian: python3-matplotlib python3-numpy).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ggins_plot_common import FRAME_3D, envelope, error_model, log_line, read_run, run_title, time_axis  # noqa: E402

NED = (("n", "north"), ("e", "east"), ("d", "down"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="output folder of ggins run3d")
    ap.add_argument("--unaided", help="output folder of the same flight without its aid (drawn on the same panel)")
    a = ap.parse_args()
    d, s = read_run(a.out)
    t, tl = time_axis(d["t_s"])
    aids = [x.get("name", "aid") for x in s.get("aids", [])]
    fig, axs = plt.subplots(4, 1, figsize=(9, 12), sharex=True)
    ax = axs[0]
    no_env = ""
    if "aid_sig_r_rss_m" in d.dtype.names:
        envelope(ax, t, d["aid_sig_r_rss_m"], label="aid 1σ envelope (RSS of its position sigmas)", color="0.4",
                 log=True)
    else:
        cov, why = error_model(a.out, "covariance3d.csv", d["t_s"])
        if cov is not None:
            envelope(ax, t, np.sqrt(cov["rn_m"] ** 2 + cov["re_m"] ** 2 + cov["rd_m"] ** 2),
                     label="error model 1σ (ggins covariance3d, RSS of N, E, D)", color="0.4", log=True)
        else:
            no_env = "; no covariance envelope: " + why
    for c, (k, lab) in enumerate(NED):
        log_line(ax, t, d["err_%s_m" % k], "|%s|" % lab, "C%d" % c)
    log_line(ax, t, d["err_r_m"], "|dr| " + ("aided (%s)" % ", ".join(aids) if aids else ""), "k", lw=1.2)
    if "unaided_err_r_m" in d.dtype.names:  # the unaided reference flown on the same frames
        log_line(ax, t, d["unaided_err_r_m"], "|dr| unaided (same frames)", "C3", lw=1.2, ls="--")
    if a.unaided:
        du, su = read_run(a.unaided)
        tu, _ = time_axis(du["t_s"])
        scale = (t[-1] / d["t_s"][-1]) if len(t) and d["t_s"][-1] else 1.0
        log_line(ax, du["t_s"] * scale, du["err_r_m"], "|dr| unaided (%s)" % su.get("scenario", a.unaided), "C3",
                 lw=1.2, ls="--")
    ax.set_ylabel("position error [m]")
    ax = axs[1]
    for c, (k, lab) in enumerate(NED):
        log_line(ax, t, d["att_err_%s_rad" % k], "|psi %s|" % lab, "C%d" % c)
    log_line(ax, t, d["att_err_rad"], "|psi|", "k")
    ax.set_ylabel("attitude error [rad]")
    ax = axs[2]
    for c, (k, lab) in enumerate(NED):
        log_line(ax, t, d["err_g%s_mps2" % k], "|dG %s|" % lab, "C%d" % c)
    log_line(ax, t, d["err_g_mps2"], "|dG|", "k")
    ax.set_ylabel("gravity error [m/s²]")
    ax = axs[3]
    log_line(ax, t, d["err_gamma_e_E"], "max |dGamma| (ECEF axes)", "C0")
    log_line(ax, t, d["err_gamma_b_E"], "max |dGamma| (body axes)", "C1")
    ax.axhline(1e-4, color="C3", ls="--", lw=0.8, label="1e-4 E")
    ax.set_ylabel("gradient error [E = 1e-9 s⁻²]")
    for ax in axs:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", ncol=3)
    axs[-1].set_xlabel(tl)
    e = s.get("errors", {})

    def fin(k):
        return e.get(k, {}).get("final", float("nan"))

    fig.suptitle("%s\n%s platform; navigation - truth, %s%s\nfinal |dr| %.3g m, |psi| %.3g rad, |dG| %.3g m/s², "
                 "max |dGamma| %.3g E" % (run_title(s, "ggins run3d: " + os.path.basename(a.out)), s.get("platform", "?"),
                                          FRAME_3D, no_env, fin("position_error_m"), fin("attitude_error_rad"),
                                          fin("gravity_error_mps2"), e.get("gradient_error_ecef_E", {}).get("max", 0)),
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "errors.png"), dpi=100)
    plt.close(fig)
    print("plots: %s" % os.path.join(a.out, "errors.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
