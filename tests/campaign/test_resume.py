"""Interrupt and resume: a campaign stopped halfway (SIGINT to `ggins campaign` once some runs
are stored) and started again computes exactly the missing runs; a third start of the finished
campaign computes none; a run whose command fails is retried once, then reported with its
seed and log (and not silently dropped); the results equal an uninterrupted campaign's."""
import os
import shutil
import signal
import subprocess
import tempfile
import time

import util
from util import Checks

SPEC = """
[campaign]
name = "resume-test"
command = "run"
scenario = "welker-table1"
seeds = 5
seed0 = 2000

[sweep]
"time.duration_s" = [200.0, 260.0]

[outputs]
series_dt = 50
"""

C = Checks("campaign.resume")
tmp = tempfile.mkdtemp(prefix="ggins-campaign-resume-")
try:
    spec = util.write(os.path.join(tmp, "c.toml"), SPEC)
    out = os.path.join(tmp, "out")
    ids = util.listed_ids(spec, os.path.join(tmp, "list"))
    p = subprocess.Popen(util.campaign_cmd(spec, out, "--workers", "2"), env=util.env(),
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    runs_dir = os.path.join(out, "runs")
    t0 = time.time()
    while time.time() - t0 < 120 and p.poll() is None:
        n = len([f for f in os.listdir(runs_dir) if f.endswith(".parquet")]) if os.path.isdir(runs_dir) else 0
        if n >= 3:
            p.send_signal(signal.SIGINT)
            break
        time.sleep(0.05)
    so, se = p.communicate(timeout=120)
    first = set(util.stored(out))
    C.ok(p.returncode == 130, "interrupted campaign exits 130 (got %d)" % p.returncode)
    C.ok(0 < len(first) < len(ids), "stopped halfway: %d of %d runs stored" % (len(first), len(ids)))

    r2 = util.run_campaign(spec, out, "--workers", "2")
    jr = util.journal(out)
    s2 = sorted(r["run_id"] for r in jr if r["event"] == "stored" and r["session"] == "2")
    missing = sorted(set(ids) - first)
    C.ok(s2 == missing, "restart computed exactly the %d missing runs (computed %d)" % (len(missing), len(s2)))
    allst = [r["run_id"] for r in jr if r["event"] == "stored"]
    C.ok(sorted(allst) == sorted(ids), "over both sessions every run stored exactly once")

    r3 = util.run_campaign(spec, out, "--workers", "2")
    jr3 = util.journal(out)
    C.ok(len(jr3) == len(jr) and "computed 0, stored before %d" % len(ids) in r3.stderr,
         "a finished campaign is not recomputed (no new journal events)")

    ref = os.path.join(tmp, "ref")
    util.run_campaign(spec, ref, "--workers", "1")
    a, b = util.stored(out), util.stored(ref)
    C.ok(sorted(a) == sorted(b) and all(a[i][0]["final"] == b[i][0]["final"] and a[i][1] == b[i][1] for i in a),
         "interrupted + resumed results identical to an uninterrupted campaign")

    # a failing run: a duration the scenario cannot fly is refused by ggins run
    bad = util.write(os.path.join(tmp, "bad.toml"), SPEC.replace("[200.0, 260.0]", "[200.0, -5.0]")
                     .replace("seeds = 5", "seeds = 2"))
    outb = os.path.join(tmp, "bad")
    rb = util.run_campaign(bad, outb, "--workers", "2", check=False)
    jb = util.journal(outb)
    failed = [r for r in jb if r["event"] == "failed"]
    retried = [r for r in jb if r["event"] == "retry"]
    C.ok(rb.returncode == 1, "campaign with failing runs exits 1 (got %d)" % rb.returncode)
    C.ok(len(failed) == 2 and sorted(r["run_id"] for r in retried) == sorted(r["run_id"] for r in failed),
         "each failing run retried once, then reported (%d failed, %d retries)" % (len(failed), len(retried)))
    C.ok(all(("seed %s" % r["seed"]) in rb.stderr and os.path.getsize(os.path.join(outb, "failed", r["run_id"] + ".log")) > 0
             for r in failed), "failures reported with their seed and a non-empty log")
    C.ok(len(util.stored(outb)) == 2, "the good point's 2 runs stored")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
C.done()
