"""A `run` campaign against `ggins montecarlo` (its own loop over ggins-run, its own
statistics and covariance in C++): 4 flights of welker-table1 cut to 600 s, seeds 1000..1003.
Run by run identical errors; the same sample sigma, covariance sigma and chi-square band."""
import os
import shutil
import subprocess
import tempfile

import util
from compare_montecarlo import compare

SPEC = """
[campaign]
name = "mc-check"
command = "run"
scenario = "welker-table1"
seeds = 4
seed0 = 1000

[[point]]
name = "600s"
"time.duration_s" = 600.0

[outputs]
series_dt = 60
compare = "covariance"
"""

C = util.Checks("campaign.montecarlo")
tmp = tempfile.mkdtemp(prefix="ggins-campaign-mc-")
try:
    spec = util.write(os.path.join(tmp, "c.toml"), SPEC)
    util.run_campaign(spec, os.path.join(tmp, "camp"), "--workers", "2")
    p = subprocess.run([os.path.join(util.BIN, "ggins-montecarlo"), "--scenario", "welker-table1", "--runs", "4",
                        "--seed0", "1000", "--duration", "600", "--keep-runs", "--no-plot", "--jobs", "2",
                        "--out", os.path.join(tmp, "mc")], capture_output=True, text=True)
    C.ok(p.returncode in (0, 1) and os.path.exists(os.path.join(tmp, "mc", "montecarlo.json")),
         "ggins montecarlo ran (exit %d)" % p.returncode)
    compare(os.path.join(tmp, "camp"), os.path.join(tmp, "mc"), C)
finally:
    shutil.rmtree(tmp, ignore_errors=True)
C.done()
