"""Shared by the campaign tests: where the tools are, running `ggins campaign`, reading a store.
usage of every test: <test>.py <bin dir> (the venv's python runs it)."""
import csv
import glob
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(SRC, "host_tools", "apps", "campaign"))

import pyarrow.parquet as pq  # noqa: E402

BIN = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else os.path.join(SRC, "build", "bin")
VENV_BIN = os.path.dirname(sys.executable)


def env():
    e = dict(os.environ)
    e["GGINS_BIN"] = BIN
    e["GGINS_SOURCE_DIR"] = SRC
    e["PYTHONPATH"] = os.path.join(SRC, "host_tools", "apps", "campaign")
    return e


def campaign_cmd(spec, out, *extra):
    return [sys.executable, "-m", "ggins_campaign", spec, "--out", out, "--no-plot", "-q"] + list(extra)


def run_campaign(spec, out, *extra, check=True):
    p = subprocess.run(campaign_cmd(spec, out, *extra), env=env(), capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError("ggins campaign failed (%d):\n%s\n%s" % (p.returncode, p.stdout, p.stderr))
    return p


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


def stored(out):
    """{run_id: (meta, table as dict of lists)} of a campaign folder."""
    res = {}
    for p in glob.glob(os.path.join(out, "runs", "*.parquet")):
        t = pq.read_table(p)
        meta = json.loads(t.schema.metadata[b"ggins"])
        res[meta["run_id"]] = (meta, {n: t.column(n).to_pylist() for n in t.column_names})
    return res


def journal(out):
    with open(os.path.join(out, "journal.csv"), newline="") as f:
        return list(csv.DictReader(f))


def listed_ids(spec, out):
    p = subprocess.run([sys.executable, "-m", "ggins_campaign", spec, "--out", out, "--list"], env=env(),
                       capture_output=True, text=True, check=True)
    return [l.split()[0] for l in p.stdout.splitlines() if l.strip()]


def last_row(csv_path, cols):
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {c: float(rows[-1][c]) for c in cols}


class Checks:
    def __init__(self, name):
        self.name, self.n, self.bad = name, 0, 0

    def ok(self, cond, what):
        self.n += 1
        if not cond:
            self.bad += 1
        print("%s %s" % ("ok  " if cond else "FAIL", what))
        sys.stdout.flush()

    def done(self):
        print("%s: %d passed, %d failed" % (self.name, self.n - self.bad, self.bad))
        sys.exit(1 if self.bad else 0)
