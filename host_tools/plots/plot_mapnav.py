"""Plots of a ggins mapnav run (first Monte Carlo run): attitude, velocity and
position errors of the map-matching UKF (GGAN) and of pure inertial, as in
Gao et al. Figs. 1-3. usage: plot_mapnav.py <out folder>"""
import csv, pathlib, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

out = pathlib.Path(sys.argv[1])
rows = list(csv.DictReader(open(out / "timeseries.csv")))
t = [float(r["t_s"]) / 3600 for r in rows]
col = lambda k: [float(r[k]) for r in rows]
fig, ax = plt.subplots(3, 2, figsize=(12, 10), sharex=True)
for j, (pre, title) in enumerate([("ggan", "GGAN (map-matching UKF)"), ("ins", "pure inertial")]):
    for k, lab in [("pitch_am", "pitch"), ("roll_am", "roll"), ("yaw_am", "yaw")]:
        ax[0][j].plot(t, col(f"{pre}_{k}"), label=lab)
    ax[0][j].set_ylabel("attitude error, arcmin")
    for k in ["vE", "vN", "vU"]:
        ax[1][j].plot(t, col(f"{pre}_{k}_mps"), label=k)
    ax[1][j].set_ylabel("velocity error, m/s")
    for k, lab in [("lat_m", "latitude"), ("lon_m", "longitude"), ("h_m", "height")]:
        ax[2][j].plot(t, col(f"{pre}_{k}"), label=lab)
    if pre == "ggan":
        for k, c in [("sig_N_m", "C0"), ("sig_E_m", "C1")]:
            ax[2][j].plot(t, [3 * v for v in col(k)], c + ":", lw=0.8, label=f"3 sigma {k[4]}")
            ax[2][j].plot(t, [-3 * v for v in col(k)], c + ":", lw=0.8)
    ax[2][j].set_ylabel("position error, m")
    ax[2][j].set_xlabel("time, h")
    ax[0][j].set_title(title)
    for a in ax[:, j]:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
fig.tight_layout()
fig.savefig(out / "errors.png", dpi=110)
print(f"plot: {out / 'errors.png'}")
