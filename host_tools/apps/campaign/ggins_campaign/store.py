"""Results on disk, one file per run, written as they arrive.

  <out>/campaign.toml          the campaign file as run
  <out>/runs/<run_id>.parquet  one finished run: its time series (columns t_s, states...);
                               the schema metadata "ggins" holds the run (point, seed, final
                               values, argv, host, wall time) as JSON; a route campaign's
                               run also its route, its scenario.toml and summary.json's status,
                               degraded_reasons, aids, unaided_reference (meta "summary")
  <out>/failed/<run_id>.json   a run that failed twice: seed, point, rc, argv; .log: its log
  <out>/journal.csv            every event (stored / retry / failed), with the session number

A run counts as done when its Parquet file exists (written to a temporary name, then renamed:
an interrupted write leaves no half file). Run ids are content hashes of the command line and
the scenario, so a changed campaign file computes only the runs it changed.
"""
import csv
import json
import os
import time

import pyarrow as pa
import pyarrow.parquet as pq


class Store:
    def __init__(self, out):
        self.out = os.path.abspath(out)
        self.runs_dir = os.path.join(self.out, "runs")
        self.failed_dir = os.path.join(self.out, "failed")
        os.makedirs(self.runs_dir, exist_ok=True)
        os.makedirs(self.failed_dir, exist_ok=True)
        self.journal = os.path.join(self.out, "journal.csv")
        self.session = 1
        if os.path.exists(self.journal):
            with open(self.journal, newline="") as f:
                rows = list(csv.DictReader(f))
            if rows:
                self.session = max(int(r["session"]) for r in rows) + 1

    def run_path(self, run_id):
        return os.path.join(self.runs_dir, run_id + ".parquet")

    def done(self, run_id):
        return os.path.exists(self.run_path(run_id))

    def _journal(self, event, run, extra=""):
        new = not os.path.exists(self.journal)
        with open(self.journal, "a", newline="") as f:
            w = csv.writer(f)
            if new:
                w.writerow(["time", "session", "event", "run_id", "point", "seed", "detail"])
            w.writerow(["%.3f" % time.time(), self.session, event, run.run_id, run.point_index, run.seed, extra])

    def write_run(self, run, res, attempts):
        series = res.get("series") or {}
        cols = {k: pa.array(v, type=pa.float64()) for k, v in series.items()}
        if "t_s" not in cols:
            cols = {"t_s": pa.array([], type=pa.float64())}
        meta = run.info()
        meta.update({"final": res["final"], "argv": res.get("argv"), "host": res.get("host"),
                     "run_wall_s": res.get("run_wall_s"), "wall_s": res.get("wall_s"), "attempts": attempts,
                     "nonfinite": res.get("nonfinite", []), "session": self.session})
        if res.get("info"):  # JSON kept as it is (a route campaign's summary.json fields)
            meta["summary"] = res["info"]
        meta["rc"] = res.get("rc")
        table = pa.table(cols).replace_schema_metadata({"ggins": json.dumps(meta)})
        path = self.run_path(run.run_id)
        tmp = path + ".tmp%d" % os.getpid()
        pq.write_table(table, tmp)
        os.replace(tmp, path)
        self._journal("stored", run, "host=%s attempts=%d run_wall_s=%.3f" % (res.get("host"), attempts,
                                                                             res.get("run_wall_s") or 0))

    def note_retry(self, run, res):
        self._journal("retry", run, "rc=%s host=%s" % (res.get("rc"), res.get("host")))

    def write_failure(self, run, res, attempts):
        info = run.info()
        info.update({"rc": res.get("rc"), "argv": res.get("argv"), "host": res.get("host"), "attempts": attempts,
                     "session": self.session})
        with open(os.path.join(self.failed_dir, run.run_id + ".json"), "w") as f:
            json.dump(info, f, indent=2)
        with open(os.path.join(self.failed_dir, run.run_id + ".log"), "w") as f:
            f.write(res.get("log") or "")
        self._journal("failed", run, "rc=%s" % res.get("rc"))

    def clear_failure(self, run_id):
        for ext in (".json", ".log"):
            p = os.path.join(self.failed_dir, run_id + ext)
            if os.path.exists(p):
                os.remove(p)

    def failures(self, run_ids):
        out = []
        for rid in run_ids:
            p = os.path.join(self.failed_dir, rid + ".json")
            if os.path.exists(p) and not self.done(rid):
                with open(p) as f:
                    out.append(json.load(f))
        return out


def read_meta(path):
    md = pq.read_schema(path).metadata
    return json.loads(md[b"ggins"])


def read_run(path):
    """(meta, series dict of lists)."""
    t = pq.read_table(path)
    meta = json.loads(t.schema.metadata[b"ggins"])
    return meta, {n: t.column(n).to_pylist() for n in t.column_names}
