#!/usr/bin/python3
"""Plots of ggins-coldatom output (docs/cold-atom-pf.md).
usage: plot_coldatom.py <out folder> [<png folder>]"""
import csv, json, os, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

d = sys.argv[1]
o = sys.argv[2] if len(sys.argv) > 2 else d


def rd(p):
    with open(p) as f:
        r = list(csv.DictReader(f))
    return {k: [float(x[k]) for x in r] for k in r[0]}


route = rd(os.path.join(d, "route_gzz.csv"))
v = 100.0


def shade(ax):  # the Channel (EGM96 only)
    s = route["s_km"]; land = route["land"]
    sea = [s[i] for i in range(len(s)) if land[i] < 0.5]
    if sea:
        ax.axvspan(min(sea) * 1e3 / v, max(sea) * 1e3 / v, color="0.9", label="Channel: EGM96 only")


fig, ax = plt.subplots(figsize=(9, 3.2))
ax.plot([x * 1e3 / v for x in route["s_km"]], route["gzz_E"], lw=0.6)
shade(ax)
ax.set_xlabel("time along the route (s)"); ax.set_ylabel("Gamma_zz at 3000 m (E)")
ax.set_title("Liverpool -> Toulouse: EGM96 + synthetic terrain over land")
ax.legend(loc="upper right"); fig.tight_layout(); fig.savefig(os.path.join(o, "coldatom-route.png"), dpi=110)

p = os.path.join(d, "error_vs_time_base.csv")
if os.path.exists(p):
    e = rd(p)
    fig, ax = plt.subplots(figsize=(9, 3.6))
    shade(ax)
    ax.plot(e["t_s"], e["unaided_mean_m"], label="unaided INS (mean)")
    ax.plot(e["t_s"], e["aided_mean_m"], label="PF-aided (mean)")
    ax.plot(e["t_s"], e["aided_p90_m"], ":", label="PF-aided (90th percentile)")
    for sub, c, lab in (("ins", "C3", "6-state INS particles, session 3 (mean)"), ("v1", "0.5", "first version (mean)")):
        p1 = os.path.join(d, sub, "error_vs_time_base.csv")
        if os.path.exists(p1):  # the earlier filters on the same flights
            e1 = rd(p1)
            ax.plot(e1["t_s"], e1["aided_mean_m"], "--", color=c, lw=0.9, label=lab)
    ax.set_xlabel("time (s)"); ax.set_ylabel("horizontal error (m)")
    js = json.load(open(os.path.join(d, "summary_none.json")))[0]
    ax.set_title("horizontal radial error, %d flights, phase noise %.1f mrad" % (js["flights"], js["phase_noise_mrad"]))
    ax.legend(); fig.tight_layout(); fig.savefig(os.path.join(o, "coldatom-error-vs-time.png"), dpi=110)

for sw, key, lab in (("phase", "phase_noise_mrad", "phase noise (mrad)"), ("fail", "p_fail", "failure probability")):
    p = os.path.join(d, "summary_%s.json" % sw)
    if not os.path.exists(p):
        continue
    js = json.load(open(p))
    x = [r[key] * (100 if sw == "fail" else 1) for r in js]
    fig, ax = plt.subplots(figsize=(5.5, 3.6))
    ax.errorbar(x, [r["mean_aided_m"] for r in js], yerr=[r["std_over_flights_aided_m"] for r in js], marker="o",
                capsize=3, label="PF-aided: mean over time and flights (bar: std over flights)")
    ax.plot(x, [r["mean_unaided_m"] for r in js], "s--", label="unaided INS")
    ax.set_xlabel(lab + (" (%)" if sw == "fail" else "")); ax.set_ylabel("mean horizontal error (m)")
    ax.set_title("%d flights per point" % js[0]["flights"])
    ax.legend(fontsize=7); fig.tight_layout(); fig.savefig(os.path.join(o, "coldatom-sweep-%s.png" % sw), dpi=110)

# filter diagnostics (ggins-coldatom --dump-flights): actual error of the particle mean against
# the cloud's spread, mean over the flights, this version and the first one
import glob


def diag(folder):
    fs = sorted(glob.glob(os.path.join(folder, "flight_base_*.csv")))
    if not fs:
        return None
    rows = [rd(f) for f in fs]
    n = min(len(r["t_s"]) for r in rows)
    avg = lambda k: [sum(r[k][j] for r in rows) / len(rows) for j in range(n)]
    z2 = [sum((r["pmean_err_m"][j] / r["spread_m"][j]) ** 2 for r in rows) / len(rows) for j in range(n)]
    return rows[0]["t_s"][:n], avg("pmean_err_m"), avg("spread_m"), z2, len(rows)


dn, di, d1 = diag(d), diag(os.path.join(d, "ins")), diag(os.path.join(d, "v1"))
if dn:
    fig, ax = plt.subplots(2, 1, figsize=(9, 5.8), sharex=True)
    for a in ax:
        shade(a)
    for dd, lab, c in ((dn, "Rao-Blackwellised (this version)", "C1"), (di, "6-state INS particles", "C3"),
                       (d1, "first version", "0.5")):
        if dd is None:
            continue
        t, em, sp, z2, nf = dd
        ax[0].plot(t, em, color=c, label="%s: error of the particle mean" % lab)
        ax[0].plot(t, sp, ":", color=c, label="%s: particle spread (rms, N+E)" % lab)
        w = 30  # 300 s running mean of the normalised squared error
        zs = [sum(z2[max(0, j - w):j + 1]) / (j + 1 - max(0, j - w)) for j in range(len(z2))]
        ax[1].plot(t, zs, color=c, label=lab)
    ax[0].set_ylabel("m (mean over %d flights)" % dn[4]); ax[0].legend(fontsize=7)
    ax[1].axhline(1.0, color="k", lw=0.6)
    ax[1].set_yscale("log"); ax[1].set_ylabel("mean (error / spread)^2\n(1: consistent; 300 s mean)")
    ax[1].set_xlabel("time (s)"); ax[1].legend(fontsize=7)
    fig.tight_layout(); fig.savefig(os.path.join(o, "coldatom-diagnostics.png"), dpi=110)

p = os.path.join(d, "gradient_base_flight0.csv")
if os.path.exists(p):
    g = rd(p)
    fig, ax = plt.subplots(2, 1, figsize=(9, 5.5), sharex=True)
    ax[0].plot(g["t_s"], g["true_E"], "k-", lw=0.8, label="truth (batch mean)")
    ax[0].plot(g["t_s"], g["ellipse_fit_E"], "r.", ms=2, label="ellipse fit (20 pairs)")
    ax[0].plot(g["t_s"], g["pf_E"], "b-", lw=0.6, label="map at the PF-corrected position")
    ax[0].set_ylabel("Gamma_zz (E)"); ax[0].legend(fontsize=7)
    ax[1].plot(g["t_s"], [a - b for a, b in zip(g["ellipse_fit_E"], g["true_E"])], "r.", ms=2, label="ellipse fit")
    ax[1].plot(g["t_s"], [a - b for a, b in zip(g["pf_E"], g["true_E"])], "b.", ms=2, label="PF")
    ax[1].set_ylabel("error (E)"); ax[1].set_xlabel("time (s)"); ax[1].legend(fontsize=7)
    fig.tight_layout(); fig.savefig(os.path.join(o, "coldatom-gradient.png"), dpi=110)
print("plots in", o)
