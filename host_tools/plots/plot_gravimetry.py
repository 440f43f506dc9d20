"""Plots of a ggins gravimetry product folder (survey.csv, gravimetry.json):

  profiles.png  the scalar disturbance and the deflections along each line against the
                truth at the same wavelength, with the stated one-sigma band;
  spectrum.png  rms error against the filter's full wavelength (scalar and horizontal),
                beside the rms of the signal itself: where the product stops resolving;
  map.png       the estimated disturbance on the survey's lines and gridded (grid.csv),
                the truth, the error.

Usage: plot_gravimetry.py OUT_DIR. Needs matplotlib (Debian python3-matplotlib).
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    d = sys.argv[1]
    with open(os.path.join(d, "survey.csv")) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(d, "gravimetry.json")) as f:
        js = json.load(f)
    col = {k: [r[k] for r in rows] for k in rows[0]}
    num = {k: [float(x) for x in v] for k, v in col.items() if k not in ("type",)}
    lines = []
    for i, ln in enumerate(num["line"]):
        if not lines or lines[-1][0] != ln:
            lines.append([ln, []])
        lines[-1][1].append(i)
    wl = js["wavelength_m"] / 1000.0

    n = len(lines)
    fig, ax = plt.subplots(n, 2, figsize=(12, 2.0 * n + 1), squeeze=False)
    for k, (ln, idx) in enumerate(lines):
        t = [num["time_s"][i] / 60 for i in idx]
        for c, (q, tq, sq, unit) in enumerate([("dg_mgal", "truth_dg_mgal", "sigma_dg_mgal", "mGal"),
                                               ("xi_arcsec", "truth_xi_arcsec", "sigma_xi_arcsec", "arcsec")]):
            a = ax[k][c]
            e = [num[q][i] for i in idx]
            tr = [num[tq][i] for i in idx]
            s = [num[sq][i] for i in idx]
            a.fill_between(t, [x - y for x, y in zip(e, s)], [x + y for x, y in zip(e, s)], color="C0", alpha=0.2,
                           lw=0)
            a.plot(t, tr, "k", lw=1.2, label="truth")
            a.plot(t, e, "C0", lw=1, label="estimate (1-sigma band)")
            name = ("Tie %d" if ln >= 1000 else "Line %d") % ln
            a.set_ylabel("%s\n%s" % (name, unit))
            if k == 0:
                a.set_title(("gravity disturbance" if c == 0 else "deflection xi (north)") +
                            ", %.1f km full wavelength" % wl)
                a.legend(fontsize=7, loc="best")
    for c in range(2):
        ax[-1][c].set_xlabel("time (min)")
    fig.suptitle("%s mode: dg rms %.3f mGal, deflection rms %.3f arcsec" %
                 (js["mode"], js["all"]["rms_dg_mgal"], js["all"]["rms_xi_arcsec"]))
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.4 / (2.0 * n + 1)))
    fig.savefig(os.path.join(d, "profiles.png"), dpi=90)
    plt.close(fig)

    fig, a = plt.subplots(figsize=(7, 4.5))
    sp = js["spectrum"]
    w = [p["wavelength_km"] for p in sp]
    a.loglog(w, [p["rms_dg_mgal"] for p in sp], "o-", label="error, scalar dg")
    a.loglog(w, [p["rms_horizontal_mgal"] for p in sp], "s-", label="error, horizontal (N, E)")
    a.loglog(w, [p["signal_rms_dg_mgal"] for p in sp], "k--", label="signal, scalar dg (truth filtered)")
    a.axhline(1.0, color="r", lw=0.8, ls=":", label="1 mGal")
    a.set_xlabel("full wavelength of the filter (km)")
    a.set_ylabel("rms (mGal)")
    a.grid(True, which="both", alpha=0.3)
    a.legend(fontsize=8)
    a.set_title("error against wavelength (%s mode)" % js["mode"])
    fig.tight_layout()
    fig.savefig(os.path.join(d, "spectrum.png"), dpi=90)
    plt.close(fig)

    grid = None
    gpath = os.path.join(d, "grid.csv")
    if os.path.exists(gpath):
        with open(gpath) as f:
            f.readline()  # the "# nodes ..." comment
            grid = list(csv.DictReader(f))
    fig, ax = plt.subplots(2 if grid else 1, 3, figsize=(15, 9 if grid else 4.5), sharex=True, sharey=True,
                           squeeze=False)
    lon, lat = num["lon_deg"], num["lat_deg"]
    vals = [num["dg_mgal"], num["truth_dg_mgal"], num["err_dg_mgal"]]
    lim = max(abs(x) for x in vals[1]) or 1
    elim = max(abs(x) for x in vals[2]) or 1
    for a, v, title, vl in zip(ax[0], vals, ["estimate", "truth (true path)", "error"], [lim, lim, elim]):
        sc = a.scatter(lon, lat, c=v, s=4, cmap="RdBu_r", vmin=-vl, vmax=vl)
        a.set_title("lines: %s (mGal)" % title)
        fig.colorbar(sc, ax=a)
    if grid:
        nx = max(int(r["ix"]) for r in grid) + 1
        ny = max(int(r["iy"]) for r in grid) + 1

        def field(k):
            z = [[float("nan")] * nx for _ in range(ny)]
            for r in grid:
                z[int(r["iy"])][int(r["ix"])] = float(r[k])
            return z
        glon = [[float("nan")] * nx for _ in range(ny)]
        glat = [[float("nan")] * nx for _ in range(ny)]
        for r in grid:
            glon[int(r["iy"])][int(r["ix"])] = float(r["lon_deg"])
            glat[int(r["iy"])][int(r["ix"])] = float(r["lat_deg"])
        for a, k, title, vl in zip(ax[1], ["dg_mgal", "truth_dg_mgal", "err_dg_mgal"], ["estimate", "truth", "error"],
                                   [lim, lim, elim]):
            pc = a.pcolormesh(glon, glat, field(k), cmap="RdBu_r", vmin=-vl, vmax=vl, shading="nearest")
            a.set_title("gridded: %s (mGal)" % title)
            fig.colorbar(pc, ax=a)
    for a in ax[-1]:
        a.set_xlabel("longitude (deg)")
    for row in ax:
        row[0].set_ylabel("latitude (deg)")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "map.png"), dpi=90)
    plt.close(fig)


if __name__ == "__main__":
    main()
