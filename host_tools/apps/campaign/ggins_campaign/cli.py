"""ggins campaign: Monte Carlo sets and parameter sweeps of the ggins commands on Dask."""
import argparse
import json
import os
import sys
import time

HELP = """\
Runs a campaign file: a scenario (or a command's options), the parameters to sweep, the seeds
per point. Every run is an ordinary run of an existing command (ggins run, run3d,
rw-eq8, montecarlo3d), fully determined by its scenario and seed. Results are stored
per run as they arrive (Parquet, <out>/runs/), so an interrupted campaign resumes where it
stopped and a finished one is not recomputed; a failed run is retried once, then reported with
its seed and log (<out>/failed/). At the end: summary.csv, summary.md, summary.json, series.csv
and plots in <out>.

Engine: Dask distributed. With no address a LocalCluster on this machine's cores; with
--scheduler tcp://host:8786 or --scheduler-file an existing cluster (docs/campaigns.md).

Campaign file format: docs/campaigns.md; examples in campaigns/.
"""


def main(argv=None):
    ap = argparse.ArgumentParser(prog="ggins campaign", description=HELP,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("spec", help="campaign file (TOML)")
    ap.add_argument("-o", "--out", help="output folder (default out/campaigns/<name>)")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://host:8786")
    g.add_argument("--scheduler-file", help="scheduler file written by `dask scheduler --scheduler-file`")
    ap.add_argument("-w", "--workers", type=int, help="LocalCluster worker processes (default: all cores)")
    ap.add_argument("--seeds", type=int, help="only the first N seeds of every point (a subset of the same runs)")
    ap.add_argument("--retries", type=int, default=1, help="resubmissions of a failed run (default 1)")
    ap.add_argument("--list", action="store_true", help="list the runs (point, seed, stored?) and exit")
    ap.add_argument("--report", action="store_true", help="only rebuild the summary and plots from stored runs")
    ap.add_argument("--no-plot", action="store_true", help="no PNG plots")
    ap.add_argument("--stop-after", type=int, help="stop after this many new runs are stored (as an interrupt)")
    ap.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    ap.add_argument("--bin", help="folder of the built ggins tools (default: beside this command)")
    ap.add_argument("--data", help="data folder with the EGM96 coefficients (default <source>/data)")
    a = ap.parse_args(argv)

    from .spec import Campaign, SpecError
    try:
        c = Campaign(a.spec, bin_dir=a.bin and os.path.abspath(a.bin), data_dir=a.data and os.path.abspath(a.data))
    except (SpecError, OSError) as e:
        print("ggins campaign: %s" % e, file=sys.stderr)
        return 2
    if a.seeds is not None:
        if a.seeds < 1:
            print("ggins campaign: --seeds must be >= 1", file=sys.stderr)
            return 2
        c.seeds = min(c.seeds, a.seeds)
    runs = c.runs()
    ids = [r.run_id for r in runs]
    if len(set(ids)) != len(ids):
        print("ggins campaign: %s: two runs are identical (same point and seed twice?)" % a.spec, file=sys.stderr)
        return 2
    out = a.out or os.path.join("out", "campaigns", c.name)
    from .store import Store
    store = Store(out)
    if a.list:
        for r in runs:
            print("%s  point %-3d %-40s seed %-6d %s" % (r.run_id, r.point_index, r.point.get("name", ""), r.seed,
                                                       "stored" if store.done(r.run_id) else "-"))
        return 0
    with open(os.path.join(store.out, "campaign.toml"), "w") as f:
        f.write(c.text)
    from . import report
    stats = None
    if not a.report:
        from . import engine
        todo = sum(1 for r in runs if not store.done(r.run_id))
        print("ggins campaign %s: %d points x %d seeds = %d runs of ggins %s; %d stored, %d to compute; out %s"
              % (c.name, len(c.points), c.seeds, len(runs), c.command, len(runs) - todo, todo, store.out),
              file=sys.stderr)
        client = cluster = None
        try:
            if todo:
                client, cluster = engine.connect(a.scheduler, a.scheduler_file, a.workers)
                nw = len(client.scheduler_info().get("workers", {}))
                print("engine: %s, %d workers%s" % ("LocalCluster" if cluster else (a.scheduler or a.scheduler_file), nw,
                                                    "" if nw else " (the runs wait for a worker to join)"),
                      file=sys.stderr)
            stats = engine.run(runs, store, client, retries=a.retries, quiet=a.quiet, stop_after=a.stop_after)
        except KeyboardInterrupt:
            stats = {"interrupted": True}
        finally:
            if client is not None:
                client.close()
            if cluster is not None:
                cluster.close()
        rw = stats.get("run_wall_s") or []
        if rw:
            stats["engine"] = {"runs": len(rw), "wall_s": stats["wall_s"], "sum_run_wall_s": sum(rw),
                               "mean_run_wall_s": sum(rw) / len(rw),
                               "mean_round_trip_s": sum(stats["round_trip_s"]) / len(rw)}
        with open(os.path.join(store.out, "session-%d.json" % store.session), "w") as f:
            json.dump({k: v for k, v in stats.items() if k not in ("run_wall_s", "round_trip_s")}, f, indent=1)
        print("ggins campaign: computed %d, stored before %d, failed %d (retried %d); wall %.1f s"
              % (stats.get("computed", 0), stats.get("stored_before", 0), stats.get("failed", 0),
                 stats.get("retried", 0), stats.get("wall_s", 0.0)), file=sys.stderr)
        if stats.get("interrupted"):
            missing = sum(1 for r in runs if not store.done(r.run_id))
            print("ggins campaign: interrupted; %d runs stored, %d missing: run the same command again to resume"
                  % (len(runs) - missing, missing), file=sys.stderr)
            return 130
    summary, plots = report.summarize(c, store, runs, plot=not a.no_plot, log=sys.stderr)
    with open(os.path.join(store.out, "summary.md")) as f:
        sys.stdout.write(f.read())
    fails = [(P["name"], f) for P in summary["points"] for f in P["failed"]]
    missing = sum(1 for r in runs if not store.done(r.run_id))
    for p in plots:
        print("plot: %s" % p)
    print("report: %s" % store.out)
    if fails:
        print("ggins campaign: %d run(s) failed twice (seed, log):" % len(fails), file=sys.stderr)
        for n, f in fails:
            print("  point %s seed %s rc %s: %s" % (n, f["seed"], f["rc"],
                                                    os.path.join(store.out, "failed", f["run_id"] + ".log")),
                  file=sys.stderr)
        return 1
    if missing:
        print("ggins campaign: %d runs not computed yet" % missing, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
