"""The aided/unaided ratio of a random-routes campaign (routes.json, routes_report.py):
  routes_ratio.png   per aid group: histogram of log10(aided / unaided final |position error|)
                     (flagged flights stacked apart) and its empirical CDF; left of 0: the aid
                     is better than unaided
usage: plot_routes.py <campaign output folder>"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1]
R = json.load(open(os.path.join(out, "routes.json")))
groups = [(g, G) for g, G in R["groups"].items() if G.get("log10_ratio")]
if groups:
    fig, axs = plt.subplots(len(groups), 2, figsize=(10, 3.4 * len(groups)), squeeze=False)
    for (g, G), (ah, ac) in zip(groups, axs):
        mine = [f for f in R.get("flight_list", []) if f.get("group") == g and f.get("ratio") and f["ratio"] > 0]
        lr_ok = [math.log10(f["ratio"]) for f in mine if not f["flagged"]]
        lr_fl = [math.log10(f["ratio"]) for f in mine if f["flagged"]]
        lr = G["log10_ratio"]
        lo, hi = min(lr + [0.0]) - 0.05, max(lr + [0.0]) + 0.05
        bins = max(5, min(40, int(math.sqrt(len(lr)) * 2)))
        ah.hist([lr_ok, lr_fl], bins=bins, range=(lo, hi), stacked=True, color=["tab:blue", "tab:orange"],
                label=["not flagged", "flagged"])
        ah.axvline(0.0, color="k", lw=1)
        ah.set_xlabel("log10(aided / unaided), final |position error|", fontsize=8)
        ah.set_ylabel("flights", fontsize=8)
        ah.set_title("%s: %d flights, %d better, %d flagged, %d violations"
                     % (g, G["flights"], G["better"], G["flagged"], G["violations"]), fontsize=9)
        ah.legend(fontsize=7)
        xs = sorted(lr)
        ac.step(xs, [(i + 1) / len(xs) for i in range(len(xs))], where="post", color="tab:blue")
        ac.axvline(0.0, color="k", lw=1)
        ac.set_ylim(0, 1)
        ac.set_xlabel("log10(aided / unaided)", fontsize=8)
        ac.set_ylabel("share of flights", fontsize=8)
        ac.set_title("%s: empirical CDF (median ratio %.3g)" % (g, G["ratio_quantiles"].get("q50", float("nan"))),
                     fontsize=9)
        for a in (ah, ac):
            a.grid(alpha=0.3)
            a.tick_params(labelsize=7)
    fig.tight_layout()
    p = os.path.join(out, "routes_ratio.png")
    fig.savefig(p, dpi=100)
    plt.close(fig)
    print(p)
