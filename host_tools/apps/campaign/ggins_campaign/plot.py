"""Plots of a campaign's summary.json (run with a Python that has matplotlib):
  error_vs_<param>.png  every final output against the swept parameter: mean with its 95 %
                        confidence band, and the sample sigma
  sigma_vs_time_p<k>.png  per point: sample sigma of each state against time and, where there
                        is one, the covariance prediction with its chi-square band
usage: plot.py <campaign output folder>"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1]
S = json.load(open(os.path.join(out, "summary.json")))
pts = S["points"]
skip = lambda k: k == "t_final_s" or k.endswith("_dof")


def num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


# 1. error against each swept parameter (others at their values in the points)
for key in S["sweep_keys"]:
    xs = [P["params"].get(key) for P in pts]
    if len(set(map(str, xs))) < 2 or not all(num(x) for x in xs):
        continue
    others = [k for k in S["param_keys"] if k != key]
    groups = {}
    for P in pts:
        groups.setdefault(tuple(str(P["params"].get(k)) for k in others), []).append(P)
    outs = [k for k in pts[0]["final"] if not skip(k)][:12]
    nc = min(3, len(outs))
    nr = int(math.ceil(len(outs) / nc))
    fig, axs = plt.subplots(nr, nc, figsize=(4.2 * nc, 3.0 * nr), squeeze=False)
    for ax, k in zip(axs.flat, outs):
        for g, P_ in groups.items():
            P_ = sorted(P_, key=lambda P: P["params"][key])
            x = [P["params"][key] for P in P_]
            m = [P["final"][k]["mean"] for P in P_]
            lo = [P["final"][k].get("ci95_lo", float("nan")) for P in P_]
            hi = [P["final"][k].get("ci95_hi", float("nan")) for P in P_]
            sg = [P["final"][k]["sigma"] for P in P_]
            lab = ",".join("%s=%s" % (o.lstrip("-"), v) for o, v in zip(others, g))
            line, = ax.plot(x, m, "o-", ms=3, label=("mean " + lab).strip())
            ax.fill_between(x, lo, hi, color=line.get_color(), alpha=0.2)
            ax.plot(x, sg, "s--", ms=3, color=line.get_color(), alpha=0.7, label=("sigma " + lab).strip())
        ax.set_title(k, fontsize=9)
        ax.set_xlabel(key.lstrip("-"), fontsize=8)
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=7)
    for ax in list(axs.flat)[len(outs):]:
        ax.axis("off")
    axs.flat[0].legend(fontsize=6)
    fig.suptitle("%s: final values vs %s (mean, 95 %% CI band; sample sigma), N = %d per point"
                 % (S["campaign"], key.lstrip("-"), S["seeds_per_point"]), fontsize=10)
    fig.tight_layout()
    p = os.path.join(out, "error_vs_%s.png" % key.lstrip("-").replace(".", "_"))
    fig.savefig(p, dpi=100)
    plt.close(fig)
    print(p)

# 2. sample sigma against time, with the covariance and its chi-square band
for P in pts[:8]:
    ser = P.get("series") or {}
    st = ser.get("states") or {}
    if not st:
        continue
    cmp = P.get("covariance")
    keys = [k for k in st][:12]
    nc = min(3, len(keys))
    nr = int(math.ceil(len(keys) / nc))
    fig, axs = plt.subplots(nr, nc, figsize=(4.2 * nc, 2.9 * nr), squeeze=False)
    t = [x / 3600 for x in ser["t_s"]]
    for ax, k in zip(axs.flat, keys):
        v = st[k]
        if "covariance" in v and cmp:
            c = v["covariance"]
            ax.fill_between(t, [x * cmp["ratio_lo"] for x in c], [x * cmp["ratio_hi"] for x in c], color="0.85",
                            label="chi-square band (z = %g)" % cmp["z"])
            ax.plot(t, c, "k-", lw=1, label="covariance sigma")
        ax.plot(t, v["sigma"], "r.", ms=3, label="sample sigma (N = %d)" % P["stored"])
        ax.set_title(k, fontsize=9)
        ax.set_xlabel("time (h)", fontsize=8)
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=7)
    for ax in list(axs.flat)[len(keys):]:
        ax.axis("off")
    axs.flat[0].legend(fontsize=6)
    fig.suptitle("%s, point %s: sample sigma against time" % (S["campaign"], P["name"]), fontsize=10)
    fig.tight_layout()
    p = os.path.join(out, "sigma_vs_time_p%d.png" % P["point"])
    fig.savefig(p, dpi=100)
    plt.close(fig)
    print(p)
