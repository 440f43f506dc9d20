"""Benchmark of the engine on this machine, side by side in one run (scripts/campaign-bench):
the same N runs (ggins run, welker-table1 cut to --duration s, seeds 1000..)
  1. in a plain loop: worker.execute one after another in this process (the command, its
     output parsing; no Dask, no store)
  2. as a campaign on a LocalCluster of 1 worker
  3. as a campaign on a LocalCluster of 2 workers
in turn, --repeat times (best of each: the machine is shared). Reports the wall of each, the
1-worker / 2-worker wall ratio, and the engine's overhead per run: (campaign wall with 1 worker
- plain loop wall) / N, with and without the cluster's start, and directly: (1-worker engine
loop - the time the worker spent inside the commands) / N.
usage: python -m ggins_campaign.bench [--runs N] [--duration S] [--out DIR]"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time

from . import worker
from .spec import Campaign

SPEC = """
[campaign]
name = "bench"
command = "run"
scenario = "welker-table1"
seeds = %d
seed0 = 1000

[[point]]
name = "bench"
"time.duration_s" = %r

[outputs]
series_dt = 60
compare = "none"
"""


def main(argv=None):
    ap = argparse.ArgumentParser(prog="campaign-bench", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=16)
    ap.add_argument("--duration", type=float, default=600.0, help="flight time of each run, s")
    ap.add_argument("--out", default="out/campaign-bench")
    ap.add_argument("--repeat", type=int, default=2, help="rounds of the three modes (best of each kept)")
    a = ap.parse_args(argv)
    shutil.rmtree(a.out, ignore_errors=True)
    os.makedirs(a.out)
    spec = os.path.join(a.out, "bench.toml")
    with open(spec, "w") as f:
        f.write(SPEC % (a.runs, a.duration))
    c = Campaign(spec)
    runs = c.runs()

    def plain_loop():
        t0 = time.time()
        walls = []
        for r in runs:
            res = worker.execute(r.task())
            if not res["ok"]:
                raise RuntimeError("bench: run failed:\n" + res.get("log", ""))
            walls.append(res["run_wall_s"])
        return time.time() - t0, sum(walls)

    def campaign(nw, k):
        out = os.path.join(a.out, "w%d-%d" % (nw, k))
        t0 = time.time()
        p = subprocess.run([sys.executable, "-m", "ggins_campaign", spec, "--out", out, "--workers", str(nw),
                            "--no-plot", "-q"], capture_output=True, text=True)
        wall = time.time() - t0
        if p.returncode != 0:
            raise RuntimeError("bench: campaign failed:\n" + p.stderr)
        s = json.load(open(os.path.join(out, "session-1.json")))
        return {"wall_s": wall, "engine_loop_s": s["wall_s"], "startup_and_report_s": wall - s["wall_s"],
                "sum_run_wall_s": s["engine"]["sum_run_wall_s"]}

    # the three modes in turn, --repeat times (the machine is shared: the best of each is kept)
    trials = {"plain": [], "w1": [], "w2": []}
    for k in range(a.repeat):
        trials["plain"].append(plain_loop())
        trials["w1"].append(campaign(1, k))
        trials["w2"].append(campaign(2, k))
    plain, plain_cmd = min(trials["plain"])
    w1 = min(trials["w1"], key=lambda w: w["wall_s"])
    w2 = min(trials["w2"], key=lambda w: w["wall_s"])
    res = {"runs": a.runs, "duration_s": a.duration, "repeat": a.repeat, "trials": trials,
           "plain_loop_wall_s": plain, "plain_mean_run_s": plain / a.runs, "w1": w1, "w2": w2}
    res["wall_ratio_1_over_2"] = w1["wall_s"] / w2["wall_s"]
    res["loop_ratio_1_over_2"] = w1["engine_loop_s"] / w2["engine_loop_s"]
    res["overhead_per_run_s"] = (w1["wall_s"] - plain) / a.runs
    res["overhead_per_run_excl_startup_s"] = (w1["engine_loop_s"] - plain) / a.runs
    # direct: 1-worker engine loop minus the time the worker spent in the commands
    res["overhead_per_run_direct_s"] = (w1["engine_loop_s"] - w1["sum_run_wall_s"]) / a.runs
    res["command_mean_s_in_engine"] = w1["sum_run_wall_s"] / a.runs
    with open(os.path.join(a.out, "bench.json"), "w") as f:
        json.dump(res, f, indent=1)
    print("%d runs of ggins run (welker-table1, %.0f s flights), this machine (%d cores), best of %d:"
          % (a.runs, a.duration, os.cpu_count(), a.repeat))
    print("  plain loop (no engine)      %7.2f s  (%.3f s per run)" % (plain, plain / a.runs))
    for nw in (1, 2):
        w = res["w%d" % nw]
        print("  campaign, %d worker%s        %7.2f s  (engine loop %.2f s; cluster start + summary %.2f s)"
              % (nw, " " if nw == 1 else "s", w["wall_s"], w["engine_loop_s"], w["startup_and_report_s"]))
    print("  wall ratio 1 worker / 2 workers: %.2f (engine loops only: %.2f)"
          % (res["wall_ratio_1_over_2"], res["loop_ratio_1_over_2"]))
    print("  engine overhead per run against the plain loop: %.3f s with the cluster start, %.3f s without"
          % (res["overhead_per_run_s"], res["overhead_per_run_excl_startup_s"]))
    print("  engine overhead per run, direct (1-worker loop minus time in the commands): %.4f s = %.2f %% of a %.2f s run"
          % (res["overhead_per_run_direct_s"], 100 * res["overhead_per_run_direct_s"] / res["command_mean_s_in_engine"],
             res["command_mean_s_in_engine"]))
    print("wrote %s" % os.path.join(a.out, "bench.json"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
