"""Check a finished campaign against the numbers documented for the command's own loop:
  --table1 OUT   Welker Table I Monte Carlo (campaigns/welker-table1-mc200.toml, 200 seeds):
                 the table of docs/error-analysis.md "Monte Carlo (item 5)" (MC and covariance
                 sigma at 1 h, 6 significant digits, ratio 4 decimals)
  --gao OUT      Gao's benchmark through ggins run3d (campaigns/gao-run3d.toml, 10 runs): the
                 per-run table and the means of docs/map-matching.md "Gao's benchmark through
                 the navigation computer"
usage: check_documented.py [<bin dir>] --table1 OUT | --gao OUT   (exit 0: all equal)"""
import json
import math
import os
import re
import sys

import util
from util import Checks

C = Checks("check_documented")


def doc(name):
    return open(os.path.join(util.SRC, "docs", name), encoding="utf-8").read()


def table1(out):
    text = doc("error-analysis.md")
    i = text.index("| one sigma at 1 h | Monte Carlo (N = 200)")
    rows = [l for l in text[i:].splitlines()[2:8]]
    names = {"δx": ("x_m", 1.0), "δz": ("z_m", 1.0), "δv_x": ("vx_mps", 100.0), "δv_z": ("vz_mps", 100.0),
             "δG_x": ("gx_mps2", 1000.0), "δG_z": ("gz_mps2", 1000.0)}
    S = json.load(open(os.path.join(out, "summary.json")))
    cmp = S["points"][0]["covariance"]
    C.ok(cmp["n"] == 200, "N = %d" % cmp["n"])
    for l in rows:
        cells = [c.strip() for c in l.strip("|").split("|")]
        k, f = names[cells[0]]
        mc_doc = float(cells[1].split()[0])
        cov_doc = float(cells[2].split()[0])
        ratio_doc = float(cells[3])
        c = cmp["states"][k]
        mc, cov = float("%.6g" % (c["montecarlo"] * f)), float("%.6g" % (c["covariance"] * f))
        C.ok(mc == mc_doc and cov == cov_doc and round(c["ratio"], 4) == ratio_doc,
             "%-5s MC %.6g (doc %s), covariance %.6g (doc %s), ratio %.4f (doc %s)"
             % (cells[0], mc, cells[1], cov, cells[2], c["ratio"], cells[3]))


def gao(out):
    """run3d: the per-run table and the means of docs/map-matching.md "Gao's benchmark through the
    navigation computer" from the stored runs (seed, end error N / E / D to 0.1 m, NIS and the
    three NEES blocks to 0.01; mean |error| +- population sd to 0.1 m)."""
    text = doc("map-matching.md")
    i = text.index("### Gao's benchmark through the navigation computer")
    rows = {}
    for l in text[i:].splitlines():
        m = re.match(r"\| (\d+) \| (.+) \| ([\d.]+) \| (.+) \|$", l)
        if m:
            rows[int(m.group(1))] = [m.group(2), m.group(3), m.group(4)]
        if l.startswith("| **mean"):
            mean_row = [c.strip().strip("*") for c in l.strip().strip("|").split("|")][-3:]
            break
    S = json.load(open(os.path.join(out, "summary.json")))
    P = S["points"][0]
    runs = util.stored(out)
    C.ok(len(runs) == len(rows) > 0, "%d stored runs, %d documented" % (len(runs), len(rows)))
    for meta, _ in runs.values():
        f = meta["final"]

        def g(x):
            return ("%.1f" % x).replace("-", "−")
        mine = [" / ".join(g(f[k]) for k in ("rn_m", "re_m", "rd_m")), "%.2f" % f["ukf_nis"],
                " / ".join("%.2f" % f["ukf_nees_" + k] for k in ("pos", "vel", "att"))]
        ref = rows.get(meta["seed"])
        C.ok(mine == ref, "seed %d: %s%s" % (meta["seed"], " | ".join(mine), "" if mine == ref else "  (doc: %s)" % ref))
    fin = P["final"]
    mine = ["%.1f ± %.1f m" % (fin[k]["mean_abs"], fin[k]["sd_abs"]) for k in ("rn_m", "re_m", "rd_m")]
    C.ok(mine == mean_row, "mean |error| at the end: %s%s" % (" / ".join(mine), "" if mine == mean_row else "  (doc: %s)" % mean_row))


args = [a for a in sys.argv[1:]]
if args and not args[0].startswith("--"):
    args = args[1:]
for k in range(0, len(args), 2):
    {"--table1": table1, "--gao": gao}[args[k]](args[k + 1])
C.done()
