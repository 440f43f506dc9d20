"""Check a finished campaign against the numbers documented for the command's own loop:
  --table1 OUT   Welker Table I Monte Carlo (campaigns/welker-table1-mc200.toml, 200 seeds):
                 the table of docs/error-analysis.md "Monte Carlo (item 5)" (MC and covariance
                 sigma at 1 h, 6 significant digits, ratio 4 decimals)
  --gao OUT      a mapnav sweep (campaigns/gao-table3-update.toml or mapnav-sweeps.toml): every
                 cell of its rows in docs/map-matching.md "Sweeps (Gao Tables 3-9)"
usage: check_documented.py [<bin dir>] --table1 OUT | --gao OUT   (exit 0: all equal)"""
import json
import math
import os
import re
import sys

import util
from util import Checks

sys.path.insert(0, os.path.join(util.SRC, "host_tools", "apps", "campaign"))
from ggins_campaign.report import GAO_COLS  # noqa: E402

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


KEYS = {"--update": "update", "--meas-noise-e": "meas", "--db-noise-e": "db", "--att0-deg": "att",
        "--vel0": "vel", "--pos0": "pos", "--gyro-bias-dph": "gyro"}


def doc_name(params):
    p = {k: v for k, v in params.items() if not (k == "--update" and v == 60)}
    if not p:
        return "base"
    (k, v), = p.items()
    return "%s-%g" % (KEYS[k], v)


def gao(out):
    text = doc("map-matching.md")
    i = text.index("### Sweeps (Gao Tables 3–9)")
    rows = {}
    for l in text[i:].splitlines():
        if l.startswith("| ") and not l.startswith("| run ") and "---" not in l:
            cells = [c.strip() for c in l.strip().strip("|").split("|")]
            rows[cells[0]] = cells[1:]
        if rows and not l.startswith("|"):
            break
    S = json.load(open(os.path.join(out, "summary.json")))
    n = 0
    for P in S["points"]:
        name = doc_name(P["params"])
        f = P["final"]
        m = {c: f["rms2h_" + c]["mean_abs"] for c in GAO_COLS}
        sd = {c: f["rms2h_" + c]["sd_abs"] for c in GAO_COLS}
        v3 = math.sqrt(m["vE_mps"] ** 2 + m["vN_mps"] ** 2 + m["vU_mps"] ** 2)
        p3 = math.sqrt(m["lat_m"] ** 2 + m["lon_m"] ** 2 + m["h_m"] ** 2)
        cells = ["%.3g ± %.2g" % (m[c], sd[c]) for c in GAO_COLS]
        mine = cells[:6] + ["%.3g" % v3] + cells[6:] + ["%.3g" % p3, "%.1f" % f["nees"]["mean"],
                                                          "%.2f" % f["nis"]["mean"]]
        ref = rows.get(name)
        same = ref is not None and mine == ref
        n += 1
        C.ok(same, "%-10s (%s): %s%s" % (name, P["name"], " | ".join(mine[-4:]),
                                         "" if same else "\n     doc: %s\n     got: %s" % (ref, mine)))
    C.ok(n > 0, "%d points compared" % n)


args = [a for a in sys.argv[1:]]
if args and not args[0].startswith("--"):
    args = args[1:]
for k in range(0, len(args), 2):
    {"--table1": table1, "--gao": gao}[args[k]](args[k + 1])
C.done()
