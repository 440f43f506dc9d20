"""The random-routes report (routes_report.py) on synthetic summary.json files: what a run
keeps of its summary.json (the worker's "keep" rule of a route campaign), per aid the share of
flights better than unaided, the ratio's quantiles and geometric mean by hand, NIS/NEES in
their bands, the flights flagged by the integrity monitor (status degraded, an aid's
integrity.flagged; missing fields: not flagged), the violations (worse and not flagged), and
the whole path through the store to summary.md / routes.md / routes.json.
usage: test_routes_report.py <bin dir>"""
import json
import math
import os
import shutil
import tempfile

import util
from util import Checks

from ggins_campaign import report, routes_report, spec, store, worker

C = Checks("campaign.routes_report")
tmp = tempfile.mkdtemp(prefix="ggins-campaign-routes-report-")


def ukf(nis, nees_pos, integ=None):
    a = {"name": "aid_ukf", "nis_mean": nis, "nis_band95": [5.0, 7.0], "nis_dof": 6,
         "nees": {"position": nees_pos, "velocity": 3.0, "attitude": 3.0, "band95": [2.0, 4.0], "dof": 3}}
    if integ is not None:
        a["integrity"] = integ
    return a


def pf(eos, integ=None):
    a = {"name": "aid_pf", "err_over_spread_sq_mean": eos, "estimate_error_mean_m": 100.0, "map_miss": 3}
    if integ is not None:
        a["integrity"] = integ
    return a


def summary(aided, unaided, aids, status="completed", reasons=None, unaided_form="norm"):
    s = {"status": status, "degraded_reasons": reasons or [], "aids": aids,
         "errors": {"position_error_m": {"final": aided, "max": 2 * aided}}}
    if unaided_form == "norm":
        s["unaided_reference"] = {"position_error_m": {"final": unaided, "max": unaided},
                                  "position_error_final_m": {"n": unaided, "e": 0.0, "d": 0.0}}
    elif unaided_form == "axes":  # only the per-axis final error: its norm
        s["unaided_reference"] = {"position_error_final_m": {"n": 0.6 * unaided, "e": 0.8 * unaided, "d": 0.0}}
    if status is None:
        del s["status"]
    return s


FLAG = {"state_final": "isolated", "flagged": True, "suspect_s": 30.0, "isolated_s": 120.0,
        "events": [{"t_s": 1800.0, "state": "suspect", "why": "nis above gate"},
                   {"t_s": 1830.0, "state": "isolated", "why": "persistent"}]}
OKI = {"state_final": "ok", "flagged": False, "suspect_s": 0.0, "isolated_s": 0.0, "events": []}

# the map UKF: ratios 0.5, 0.25, 2.0 (worse, not flagged: a violation), 1.5 (worse, degraded),
# 0.8 (integrity flagged though better), 3.0 (worse, aid flagged), unknown (no unaided),
# 0.4 (no integrity block, no status: not flagged)
UKF = [(1, summary(50.0, 100.0, [ukf(6.0, 3.0, OKI)])),
       (2, summary(25.0, 100.0, [ukf(8.0, 1.0, OKI)], unaided_form="axes")),
       (3, summary(200.0, 100.0, [ukf(6.5, 10.0, OKI)])),
       (4, summary(150.0, 100.0, [ukf(5.5, 3.5)], status="degraded", reasons=["aid_ukf: isolated"])),
       (5, summary(80.0, 100.0, [ukf(4.0, 2.5, FLAG)])),
       (6, summary(300.0, 100.0, [ukf(20.0, 50.0, FLAG)])),
       (7, summary(10.0, None, [ukf(6.0, 3.0)], unaided_form=None)),
       (8, summary(40.0, 100.0, [ukf(6.0, 3.0)], status=None))]
# the particle filter: 0.1, 10 (violation), 0.01
PF = [(11, summary(10.0, 100.0, [pf(0.5, OKI)])), (12, summary(1000.0, 100.0, [pf(20.0, OKI)])),
      (13, summary(1.0, 100.0, [pf(1.0)]))]

try:
    # what a run keeps: the keep rule of a route campaign's run3d task, read back by the worker
    c = spec.Campaign(os.path.join(util.SRC, "campaigns", "random-routes-mm.toml"), source_dir=util.SRC,
                      bin_dir=util.BIN)
    keep = c.runs()[0].task()["parse"][1]["keep"]
    metas = []
    for seed, s in UKF + PF:
        p = util.write(os.path.join(tmp, "summary-%d.json" % seed), json.dumps(s))
        metas.append({"seed": seed, "run_id": "r%d" % seed, "final": {}, "summary": worker._keep_json(p, keep),
                      "route": {"legs": 4, "flight_time_s": 4000.0}})
    C.ok(metas[0]["summary"]["status"] == "completed" and "unaided_reference" in metas[0]["summary"]
         and "status" not in metas[7]["summary"] and "unaided_reference" not in metas[6]["summary"],
         "keep: the summary.json fields as they are, absent ones left out")

    R = routes_report.aggregate([routes_report.flight_of(m) for m in metas])
    G, P = R["groups"]["aid_ukf"], R["groups"]["aid_pf"]
    C.ok(G["flights"] == 8 and G["known"] == 7 and G["unknown"] == 1, "UKF: 8 flights, 7 with both errors, 1 unknown")
    C.ok(G["better"] == 4 and abs(G["better_share"] - 4 / 7) < 1e-15, "UKF: better than unaided on 4 of 7")
    C.ok(G["flagged"] == 3 and [f["seed"] for f in G["flagged_list"]] == [4, 5, 6],
         "UKF: flagged 4 (status degraded), 5 and 6 (integrity.flagged); 8 (no fields) not flagged")
    C.ok(G["violations"] == 1 and G["violation_list"][0]["seed"] == 3 and G["worse_flagged"] == 2 and not G["goal_met"],
         "UKF: one violation (seed 3: worse, not flagged); 2 worse but flagged")
    rs = sorted([0.5, 0.25, 2.0, 1.5, 0.8, 3.0, 0.4])  # 0.25 0.4 0.5 0.8 1.5 2.0 3.0
    q = G["ratio_quantiles"]
    # linear interpolation: q25 at 1.5 -> 0.4 + 0.5 (0.5 - 0.4); q95 at 5.7 -> 2.0 + 0.7 (3.0 - 2.0)
    C.ok(abs(q["q0"] - 0.25) < 1e-12 and abs(q["q50"] - 0.8) < 1e-12 and abs(q["q25"] - 0.45) < 1e-12
         and abs(q["q95"] - 2.7) < 1e-12 and abs(q["q100"] - 3.0) < 1e-12,
         "UKF: ratio quantiles by hand (0.25, q25 0.45, median 0.8, q95 2.7, 3.0)")
    gm = math.exp(sum(math.log(x) for x in rs) / len(rs))
    C.ok(abs(G["ratio_geomean"] - gm) < 1e-12 and len(G["log10_ratio"]) == 7, "UKF: geometric mean %.4f" % gm)
    C.ok(abs(routes_report.flight_of(metas[1])["unaided_m"] - 100.0) < 1e-12,
         "unaided from position_error_final_m's norm when position_error_m is absent")
    k = G["consistency"]["aid_ukf"]
    # NIS band [5, 7]: 6.0 6.5 5.5 6.0 6.0 in, 8.0 4.0 20.0 out; NEES pos band [2, 4]: 3 3.5 2.5 3 3 in
    C.ok(k["nis_in_band95"] == {"n": 8, "in": 5, "share": 5 / 8} and k["nees_position_in_band95"]["in"] == 5
         and abs(k["nis_mean"]["median"] - 6.0) < 1e-12 and k["nees_velocity_in_band95"]["in"] == 8,
         "UKF: NIS 5 of 8 in band (median 6.0), NEES position 5 of 8, velocity 8 of 8")
    C.ok(k["integrity_state_final"] == {"ok": 3, "isolated": 2, "unknown": 3}, "UKF: integrity states at the end")
    C.ok(P["flights"] == 3 and P["better"] == 2 and P["violations"] == 1 and P["flagged"] == 0
         and abs(P["ratio_quantiles"]["q50"] - 0.1) < 1e-12
         and abs(P["consistency"]["aid_pf"]["err_over_spread_sq"]["median"] - 1.0) < 1e-12,
         "PF: 2 of 3 better, one violation, median ratio 0.1, (err/spread)^2 median 1.0")
    md = "\n".join(routes_report.markdown(R))
    C.ok("| aid_ukf | 8 | **1** |" in md and "| aid_pf | 3 | **1** |" in md
         and "flights flagged by the integrity monitor: 3" in md and "nis above gate" in md,
         "markdown: violations in bold per aid, the flagged flights with their first event")
    # a flight with nothing: unknown, not flagged; no aids: its own group
    f0 = routes_report.flight_of({"seed": 99, "run_id": "x", "final": {}})
    C.ok(f0["flagged"] is False and f0["better"] is None and f0["group"] == "(no aid)",
         "an empty record: unknown, not flagged")
    # both aids on one flight: one group aid_ukf+aid_pf
    f2 = routes_report.flight_of({"seed": 5, "summary": summary(1.0, 2.0, [ukf(6.0, 3.0), pf(1.0, FLAG)])})
    C.ok(f2["group"] == "aid_ukf+aid_pf" and f2["flagged"], "two aids: group aid_ukf+aid_pf, flagged by either")

    # the whole path: stored runs of the campaign (results made up) -> summary.md, routes.md/json
    c.seeds = 4
    runs = c.runs()
    st = store.Store(os.path.join(tmp, "out"))
    for r, (seed, s) in zip(runs, UKF[:4]):
        st.write_run(r, {"final": {"rn_m": 1.0, "re_m": 1.0, "rd_m": 0.0}, "series": {}, "rc": 0,
                         "info": {"status": s["status"], "aids": s["aids"], "unaided_reference": s["unaided_reference"],
                                  "position_error_m": s["errors"]["position_error_m"],
                                  "degraded_reasons": s["degraded_reasons"]}}, 1)
    m0 = store.read_meta(st.run_path(runs[0].run_id))
    C.ok(m0["route"]["seed"] == runs[0].seed and m0["scenario_toml"] == runs[0].task()["files"]["scenario.toml"]
         and m0["summary"]["status"] == "completed",
         "a stored run holds its route, its scenario and the kept summary.json fields")
    S, _ = report.summarize(c, st, runs, plot=False)
    text = open(os.path.join(st.out, "summary.md")).read()
    RJ = json.load(open(os.path.join(st.out, "routes.json")))
    C.ok("Random routes: per aid" in text and "| aid_ukf | 4 | **1** |" in text and RJ["groups"]["aid_ukf"]["better"] == 2
         and S["routes"]["aid_ukf"]["violations"] == 1 and os.path.exists(os.path.join(st.out, "routes.md")),
         "summary.md ends with the per-aid table (4 flights, 1 violation); routes.json, routes.md written")
    py = report._python_with_matplotlib()
    if py:
        import subprocess
        p = subprocess.run([py, os.path.join(util.SRC, "host_tools", "apps", "campaign", "ggins_campaign",
                                             "plot_routes.py"), st.out], capture_output=True, text=True)
        C.ok(p.returncode == 0 and os.path.exists(os.path.join(st.out, "routes_ratio.png")),
             "routes_ratio.png drawn%s" % ("" if p.returncode == 0 else ": " + p.stderr[-300:]))
finally:
    shutil.rmtree(tmp, ignore_errors=True)
C.done()
