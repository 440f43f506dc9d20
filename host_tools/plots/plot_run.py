#!/usr/bin/env python3
"""Plots of one `ggins run` output folder (timeseries.csv, summary.json):
errors.png (position, velocity and gravity error against time, per axis of
the flight's inertial frame, x equatorial and z polar, and the norm, with the
one-sigma envelope of `ggins covariance` for the same scenario around each
axis: OUTPUT_DIR/covariance/covariance.csv, which `ggins run` computes from the
scenario as flown, or --covariance), errors_log.png (the norms on a log scale),
vertical.png and gravimeter.png (vertical channel, barometer loop).

usage: plot_run.py OUTPUT_DIR [--covariance covariance.csv]
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

from ggins_plot_common import FRAME_2D, envelope, error_model, read_run, run_title, time_axis  # noqa: E402


def plot_vertical(out, d, s, t, tl, title):
    """vertical.png: vertical error (log scale when it spans decades) and the
    barometer; gravimeter.png: the along-track gravity map, estimate against
    the true vertical disturbance (true minus onboard model, along up)."""
    made = []
    eh = d["err_h_m"]
    fig, axs = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    ax = axs[0]
    big = np.nanmax(np.abs(eh)) > 1e4 if len(eh) else False
    if big:
        ax.semilogy(t, np.abs(eh), "C3", label="|vertical error| (nav - true altitude)")
    else:
        ax.plot(t, eh, "C3", label="vertical error (nav - true altitude)")
        due = d["baro_due"] > 0
        if np.any(due):
            ax.plot(t[due], d["baro_err_m"][due], "C0.", ms=1.5, alpha=0.5, label="barometer error (sample - true)")
    ax.plot(t, d["err_horiz_m"], "C2", lw=1, label="horizontal error")
    ax.set_ylabel("vertical / horizontal error [m]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax = axs[1]
    ax.plot(t, d["baro_innov_m"], "C1", lw=0.8, label="barometer innovation h_ins - h_baro")
    ax.set_ylabel("barometer innovation [m]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    axs[-1].set_xlabel(tl)
    v = s.get("vertical", {})
    rms = v.get("rms_error_after_settle_m")
    if rms is None:  # a flight shorter than the settling time has no settled statistics
        sub = "baro loop %s (flight shorter than the settling time %.0f s: no settled rms)" % (
            "on" if v.get("baro_loop") else "off", v.get("settle_s", 0))
    else:
        sub = "baro loop %s, rms vertical error after %.0f s: %.3g m" % (
            "on" if v.get("baro_loop") else "off", v.get("settle_s", 0), rms)
    fig.suptitle(title + "\n" + sub, fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "vertical.png"), dpi=110)
    plt.close(fig)
    made.append(os.path.join(out, "vertical.png"))

    g = s.get("gravimeter", {})
    if s.get("vertical", {}).get("baro_loop"):
        mgal = 1e5  # 1 mGal = 1e-5 m/s^2
        fig, axs = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
        if "h_true_m" in d.dtype.names and "true_r_x_m" in d.dtype.names:
            lat = np.degrees(np.arctan2(d["true_r_z_m"], d["true_r_x_m"]))
        ax = axs[0]
        ax.plot(t, d["gd_true_up_mps2"] * mgal, "k", lw=1.2, label="true (field - onboard model) . up")
        if g.get("poles_radps"):  # the truth through the loop's H_g = p1 p2 p3 / prod (s + p_i) (lag shown)
            y = d["gd_true_up_mps2"].copy()
            ts = d["t_s"]
            for pi in g["poles_radps"]:
                out_f = np.zeros_like(y)
                for k in range(1, len(y)):
                    a = np.exp(-pi * (ts[k] - ts[k - 1]))
                    out_f[k] = a * out_f[k - 1] + (1 - a) * 0.5 * (y[k] + y[k - 1])
                y = out_f
            ax.plot(t, y * mgal, "0.5", lw=1, ls="--", label="true through the loop's H_g (lag)")
        ax.plot(t, d["gd_est_up_mps2"] * mgal, "C3", lw=1, label="gravimeter estimate")
        ax.set_ylabel("vertical gravity disturbance [mGal]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
        ax = axs[1]
        ax.plot(t, d["gd_err_up_mps2"] * mgal, "C3", lw=1)
        ax.axvline(g.get("settle_s", 0) / (t[-1] and (d["t_s"][-1] / t[-1]) or 1.0), color="0.5", ls=":")
        ax.set_ylabel("gravimeter error, estimate - true [mGal]")
        ax.grid(True, alpha=0.3)
        axs[-1].set_xlabel(tl + ("   (latitude %.2f .. %.2f deg)" % (lat[0], lat[-1]) if "true_r_x_m" in d.dtype.names else ""))
        if g.get("rms_error_mps2") is None:
            sub = "gravimeter (%s mode): flight shorter than the settling time %.0f s, no settled rms" % (
                g.get("mode", "?"), g.get("settle_s", 0))
        else:
            sub = "gravimeter (%s mode): rms error %.3g mGal after %.0f s, true rms %.3g mGal" % (
                g.get("mode", "?"), g["rms_error_mps2"] * mgal, g.get("settle_s", 0),
                g.get("rms_true_disturbance_mps2") * mgal)
        fig.suptitle(title + "\n" + sub, fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "gravimeter.png"), dpi=110)
        plt.close(fig)
        made.append(os.path.join(out, "gravimeter.png"))
    return made


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="output folder of ggins run")
    ap.add_argument("--covariance", help="covariance.csv of `ggins covariance` for the same scenario: 1σ envelopes "
                    "(default OUTPUT_DIR/covariance/covariance.csv when it exists)")
    a = ap.parse_args()
    out = a.out
    d, s = read_run(out)
    t, tl = time_axis(d["t_s"])
    if a.covariance:
        c = np.atleast_1d(np.genfromtxt(a.covariance, delimiter=",", names=True))
        tc = c["t_s"]
        cov = {k: np.interp(d["t_s"], tc, c[k], left=np.nan, right=np.nan) for k in c.dtype.names if k != "t_s"}
        no_cov = ""
    else:
        cov, no_cov = error_model(out, "covariance.csv", d["t_s"])
    rows = [("err_r", "m", 1.0, "position error", "m", "err_r_norm_m", ("x_m", "z_m")),
            ("err_v", "mps", 1.0, "velocity error", "m/s", "err_v_norm_mps", ("vx_mps", "vz_mps")),
            ("err_g", "mps2", 1.0, "gravity error", "m/s$^2$", "err_g_norm_mps2", ("gx_mps2", "gz_mps2"))]
    fig, axs = plt.subplots(len(rows), 1, figsize=(9, 9), sharex=True)
    for ax, (p, u, scale, what, unit, norm, ck) in zip(axs, rows):
        for (a_, c), k in zip((("x", "C0"), ("z", "C1")), ck):
            name = "%s (equatorial)" % a_ if a_ == "x" else "%s (polar)" % a_
            if cov is not None and k in cov:
                envelope(ax, t, cov[k] * scale, label="±1σ %s (ggins covariance)" % a_, color=c)
            ax.plot(t, d["%s_%s_%s" % (p, a_, u)] * scale, c, lw=1, label=name)
        ax.plot(t, d[norm] * scale, "k:", lw=1, label="norm")
        ax.set_ylabel("%s [%s]" % (what, unit))
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper left", fontsize=8, ncol=2)
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
    axs[-1].set_xlabel(tl)
    title = run_title(s, "ggins run: " + os.path.basename(out))
    fig.suptitle(title + "\nnavigation - truth, %s" % FRAME_2D
                 + ("" if cov is not None else "\n(no covariance envelope: ggins covariance: %s)" % no_cov),
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "errors.png"), dpi=110)
    plt.close(fig)

    # the same errors on a log scale: the numerical floor and the unstable mode
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for (p, u, scale, what, unit, norm, ck), c in zip(rows, ("C0", "C1", "C2")):
        y = np.abs(d[norm])
        ax.semilogy(t, np.where(y > 0, y, np.nan), c, label="|%s| [%s]" % (what, unit.replace("$^2$", "²")))
    ax.set_xlabel(tl)
    ax.set_ylabel("error norm [m, m/s, m/s²]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(title + "\nnorms of navigation - truth (%s)" % FRAME_2D, fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "errors_log.png"), dpi=110)
    plt.close(fig)
    made = [os.path.join(out, "errors.png"), os.path.join(out, "errors_log.png")]
    if "err_h_m" in d.dtype.names:
        made += plot_vertical(out, d, s, t, tl, title)
    print("plots: %s" % ", ".join(made))
    return 0


if __name__ == "__main__":
    sys.exit(main())
