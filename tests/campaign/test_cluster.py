"""A campaign on a real Dask cluster on localhost (`dask scheduler` + two `dask worker`
processes, started here from the pinned environment, without the campaign package on their
path), one worker killed (SIGKILL) while it flies a run: every run is stored exactly once, and
every run's results are identical to the same campaign on the default LocalCluster and to
the plain command (`ggins-run -s welker-table1 --seed S --duration D`) run outside the engine.
"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import util
from util import Checks

import psutil

SPEC = """
[campaign]
name = "cluster-test"
command = "run"
scenario = "welker-table1"
seeds = 4
seed0 = 1000

[sweep]
"time.duration_s" = [240.0, 300.0]

[outputs]
series_dt = 60
"""

C = Checks("campaign.cluster")
tmp = tempfile.mkdtemp(prefix="ggins-campaign-cluster-")
procs = []
try:
    spec = util.write(os.path.join(tmp, "c.toml"), SPEC)
    ids = util.listed_ids(spec, os.path.join(tmp, "list"))
    C.ok(len(ids) == 8 and len(set(ids)) == 8, "8 distinct runs (2 points x 4 seeds)")

    # the cluster: a scheduler and two single-threaded workers, no nanny (a killed worker stays dead)
    wenv = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    wenv["GGINS_BIN"] = util.BIN
    sched_file = os.path.join(tmp, "scheduler.json")
    wd = os.path.join(tmp, "wd")
    os.makedirs(wd)
    dask = os.path.join(util.VENV_BIN, "dask")
    procs.append(subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                                   "--scheduler-file", sched_file], cwd=wd, env=wenv,
                                  stdout=subprocess.DEVNULL, stderr=open(os.path.join(tmp, "scheduler.log"), "w")))
    for k in range(2):
        procs.append(subprocess.Popen([dask, "worker", "--scheduler-file", sched_file, "--nthreads", "1",
                                       "--no-nanny", "--no-dashboard", "--name", "w%d" % k, "--host", "127.0.0.1"],
                                      cwd=wd, env=wenv, stdout=subprocess.DEVNULL,
                                      stderr=open(os.path.join(tmp, "worker%d.log" % k), "w")))
    from distributed import Client
    t0 = time.time()
    while not os.path.exists(sched_file) and time.time() - t0 < 60:
        time.sleep(0.2)
    cl = Client(scheduler_file=sched_file, timeout=60)
    cl.wait_for_workers(2, timeout=60)
    C.ok(len(cl.scheduler_info()["workers"]) == 2, "scheduler has 2 workers")
    cl.close()

    out_c = os.path.join(tmp, "on-cluster")
    camp = subprocess.Popen(util.campaign_cmd(spec, out_c, "--scheduler-file", sched_file), env=util.env(),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # kill worker w0 while it runs a flight (a ggins-run child exists) and runs remain
    victim = psutil.Process(procs[1].pid)

    def flight_children(proc):
        """The worker's running ggins-run children; a child that exits (or is a zombie) while listed is skipped."""
        found = []
        try:
            kids = proc.children(recursive=True) if proc.is_running() else []
        except psutil.Error:
            return found
        for p in kids:
            try:
                if "ggins-run" in " ".join(p.cmdline() or []):
                    found.append(p)
            except psutil.Error:
                pass
        return found
    killed_mid_run = False
    t0 = time.time()
    while time.time() - t0 < 120 and camp.poll() is None:
        n_stored = len(os.listdir(os.path.join(out_c, "runs"))) if os.path.isdir(os.path.join(out_c, "runs")) else 0
        kids = flight_children(victim)
        if n_stored >= 2 and kids:
            procs[1].send_signal(signal.SIGKILL)
            procs[1].wait()
            killed_mid_run = True
            stored_at_kill = n_stored
            break
        time.sleep(0.05)
    so, se = camp.communicate(timeout=300)
    C.ok(killed_mid_run, "worker w0 killed with SIGKILL during a flight (%s runs stored then)"
         % (stored_at_kill if killed_mid_run else "-"))
    C.ok(camp.returncode == 0, "campaign finished on the remaining worker (exit %d)%s"
         % (camp.returncode, "" if camp.returncode == 0 else "\n" + se[-3000:]))

    st = util.stored(out_c)
    jr = util.journal(out_c)
    stored_events = [r["run_id"] for r in jr if r["event"] == "stored"]
    C.ok(sorted(st) == sorted(ids), "every run stored (%d of %d)" % (len(st), len(ids)))
    C.ok(sorted(stored_events) == sorted(ids), "each run stored exactly once (%d store events)" % len(stored_events))
    C.ok(not [r for r in jr if r["event"] == "failed"], "no run reported failed")

    # the same campaign on the default LocalCluster
    out_l = os.path.join(tmp, "local")
    util.run_campaign(spec, out_l, "--workers", "2")
    sl = util.stored(out_l)
    same = sorted(sl) == sorted(st) and all(
        sl[i][0]["final"] == st[i][0]["final"] and sl[i][1] == st[i][1] for i in st)
    C.ok(same, "every run's final values and time series identical to the LocalCluster campaign")

    # and to the plain command, outside the engine, on the unmodified scenario file
    cols = {"err_r_x_m": "x_m", "err_r_z_m": "z_m", "err_v_x_mps": "vx_mps", "err_v_z_mps": "vz_mps", "err_g_x_mps2": "gx_mps2",
            "err_g_z_mps2": "gz_mps2"}
    for meta, _ in list(st.values())[:2]:
        d = os.path.join(tmp, "direct-%d" % meta["seed"])
        subprocess.run([os.path.join(util.BIN, "ggins-run"), "-s", "welker-table1", "--seed", str(meta["seed"]),
                        "--duration", repr(meta["params"]["time.duration_s"]), "--no-log", "--no-plots", "-q",
                        "--csv-rate", "1", "--out", d], check=True, capture_output=True)
        ref = util.last_row(os.path.join(d, "timeseries.csv"), cols)
        C.ok(all(ref[c] == meta["final"][n] for c, n in cols.items()) and ref["err_r_x_m"] != 0,
             "seed %d, %g s: campaign = ggins-run -s welker-table1 --seed %d (dx %.6g m)"
             % (meta["seed"], meta["params"]["time.duration_s"], meta["seed"], ref["err_r_x_m"]))
finally:
    for p in procs:
        if p.poll() is None:
            p.terminate()
    for p in procs:
        try:
            p.wait(timeout=20)
        except subprocess.TimeoutExpired:
            p.kill()
    shutil.rmtree(tmp, ignore_errors=True)
C.done()
