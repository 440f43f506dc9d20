"""Compare a `run` campaign with `ggins montecarlo --keep-runs` on the same seeds, run by run
(the last row of flight i's timeseries.csv in the montecarlo folder against the campaign's run
with seed seed0 + i), and the final sample sigma and covariance of montecarlo.json against the
campaign's summary.json.
usage: compare_montecarlo.py <bin dir> <campaign out> <montecarlo out>   (exit 0: all equal)
Used by test_montecarlo.py; by hand for the Table I subsets (docs/campaigns.md)."""
import json
import os
import sys

import util

COLS = {"err_r_x_m": "x_m", "err_r_z_m": "z_m", "err_v_x_mps": "vx_mps", "err_v_z_mps": "vz_mps", "err_g_x_mps2": "gx_mps2",
        "err_g_z_mps2": "gz_mps2"}


def compare(camp_out, mc_out, C, rel_cov=1e-9):
    mc = json.load(open(os.path.join(mc_out, "montecarlo.json")))
    st = util.stored(camp_out)
    by_seed = {m["seed"]: m for m, _ in st.values()}
    n = mc["runs"]
    same = 0
    worst = None
    for i in range(n):
        ref = util.last_row(os.path.join(mc_out, "runs", str(i), "timeseries.csv"), COLS)
        m = by_seed.get(mc["seed0"] + i)
        if m and all(ref[c] == m["final"][k] for c, k in COLS.items()):
            same += 1
        elif worst is None:
            worst = (i, ref, m and m["final"])
    C.ok(same == n, "%d of %d flights identical to ggins montecarlo's (seeds %d..%d)%s"
         % (same, n, mc["seed0"], mc["seed0"] + n - 1, "" if worst is None else "; first differing: %r" % (worst,)))
    summ = json.load(open(os.path.join(camp_out, "summary.json")))
    cmp = summ["points"][0]["covariance"]
    for k, v in mc["final"].items():
        c = cmp["states"][k]
        ok_mc = abs(c["montecarlo"] / v["montecarlo"] - 1) < 1e-12
        ok_cov = abs(c["covariance"] / v["covariance"] - 1) < rel_cov
        C.ok(ok_mc and ok_cov and c["within"] == v["within"],
             "%-8s sample sigma %.6g (montecarlo %.6g), covariance %.6g (montecarlo %.6g), ratio %.4f"
             % (k, c["montecarlo"], v["montecarlo"], c["covariance"], v["covariance"], c["ratio"]))
    C.ok(abs(cmp["ratio_lo"] - mc["tolerance"]["ratio_lo"]) < 1e-12 and
         abs(cmp["ratio_hi"] - mc["tolerance"]["ratio_hi"]) < 1e-12,
         "band [%.4f, %.4f] = ggins montecarlo's" % (cmp["ratio_lo"], cmp["ratio_hi"]))


if __name__ == "__main__":
    C = util.Checks("compare_montecarlo")
    compare(sys.argv[2], sys.argv[3], C)
    C.done()
