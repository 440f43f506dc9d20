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
    ax.set_ylabel("m")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax = axs[1]
    ax.plot(t, d["baro_innov_m"], "C1", lw=0.8, label="barometer innovation h_ins - h_baro [m]")
    ax.set_ylabel("m")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    axs[-1].set_xlabel(tl)
    v = s.get("vertical", {})
    fig.suptitle(title + ("\nbaro loop %s, rms vertical error after %.0f s: %.3g m" % (
        "on" if v.get("baro_loop") else "off", v.get("settle_s", 0), v.get("rms_error_after_settle_m", float("nan")))),
        fontsize=9)
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
        ax.set_ylabel("estimate - true [mGal]")
        ax.grid(True, alpha=0.3)
        axs[-1].set_xlabel(tl + ("   (latitude %.2f .. %.2f deg)" % (lat[0], lat[-1]) if "true_r_x_m" in d.dtype.names else ""))
        fig.suptitle(title + "\ngravimeter (%s mode): rms error %.3g mGal after %.0f s, true rms %.3g mGal" % (
            g.get("mode", "?"), g.get("rms_error_mps2", float("nan")) * mgal, g.get("settle_s", 0),
            g.get("rms_true_disturbance_mps2", float("nan")) * mgal), fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "gravimeter.png"), dpi=110)
        plt.close(fig)
        made.append(os.path.join(out, "gravimeter.png"))
    return made


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
    made = [os.path.join(out, "errors.png"), os.path.join(out, "errors_log.png")]
    if "err_h_m" in d.dtype.names:
        made += plot_vertical(out, d, s, t, tl, title)
    print("plots: %s" % ", ".join(made))
    return 0


if __name__ == "__main__":
    sys.exit(main())
