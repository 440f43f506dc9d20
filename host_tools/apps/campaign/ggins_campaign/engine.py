"""The Dask engine: every run not stored yet is one task; results are stored as they arrive.

With no address a LocalCluster of this machine's cores is started (one single-threaded worker
process per core: a run is one process of the command, so a worker runs one at a time). With an
address (tcp://host:8786) or a scheduler file the runs go to that cluster.

A worker that dies mid-run loses only that run: the scheduler gives the task to another worker
(Dask reschedules the tasks of a lost worker). A run whose command fails (non-zero exit,
unreadable output, timeout) is submitted once more; a second failure is stored under failed/
with its seed, command line and log, and reported at the end. Results are keyed by run id, so
each run is stored exactly once whatever the scheduler did.
"""
import logging
import os
import signal
import sys
import time
import traceback

import cloudpickle
from distributed import Client, LocalCluster, as_completed

from . import worker

# The run function travels by value: the scheduler unpickles task graphs with plain pickle,
# so the task is builtins.eval of a one-line trampoline over a cloudpickle blob of
# worker.execute (stdlib only): no ggins package on the scheduler or the workers.
cloudpickle.register_pickle_by_value(worker)
_EXECUTE_BLOB = cloudpickle.dumps(worker.execute)
_TRAMPOLINE = "__import__('cloudpickle').loads(blob)(task)"


def _fmt_dt(s):
    if s is None or s != s or s == float("inf"):
        return "?"
    s = int(round(s))
    if s >= 3600:
        return "%dh%02dm" % (s // 3600, (s % 3600) // 60)
    if s >= 60:
        return "%dm%02ds" % (s // 60, s % 60)
    return "%ds" % s


class Progress:
    def __init__(self, total, before, quiet=False, stream=sys.stderr):
        self.total, self.before, self.quiet, self.stream = total, before, quiet, stream
        self.tty = stream.isatty()
        self.done = self.failed = self.retrying = 0
        self.t0 = time.time()
        self.last_draw = 0.0
        self.last_frac = -1.0

    def line(self):
        fin = self.before + self.done
        remaining = self.total - fin - self.failed
        el = time.time() - self.t0
        todo_session = self.total - self.before
        finished = self.done + self.failed
        eta = el / finished * (todo_session - finished) if finished else None
        w = 30
        k = int(w * (fin + self.failed) / max(1, self.total))
        bar = "#" * k + "." * (w - k)
        extra = (" (%d stored before)" % self.before) if self.before else ""
        retr = (", %d retrying" % self.retrying) if self.retrying else ""
        return ("[%s] %d/%d runs done%s, %d failed, %d remaining%s; %s elapsed, ETA %s"
                % (bar, fin, self.total, extra, self.failed, remaining, retr, _fmt_dt(el), _fmt_dt(eta)))

    def draw(self, force=False):
        if self.quiet:
            return
        now = time.time()
        if self.tty:
            if force or now - self.last_draw > 0.5:
                self.stream.write("\r" + self.line() + "\x1b[K")
                self.stream.flush()
                self.last_draw = now
        else:
            frac = (self.before + self.done + self.failed) / max(1, self.total)
            if force or frac - self.last_frac >= 0.1 or now - self.last_draw > 30:
                self.stream.write(self.line() + "\n")
                self.stream.flush()
                self.last_draw, self.last_frac = now, frac

    def close(self):
        self.draw(force=True)
        if self.tty and not self.quiet:
            self.stream.write("\n")


def connect(scheduler=None, scheduler_file=None, workers=None):
    """(client, cluster or None)."""
    if scheduler or scheduler_file:
        client = Client(scheduler_file=scheduler_file) if scheduler_file else Client(scheduler)
        return client, None
    n = workers or os.cpu_count() or 1
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=logging.ERROR)
    return Client(cluster), cluster


class Interrupted(Exception):
    pass


def run(runs, store, client, retries=1, quiet=False, stop_after=None, log=sys.stderr):
    """Compute the runs that are not stored. Returns a dict of counts and the engine timings."""
    todo = [r for r in runs if not store.done(r.run_id)]
    before = len(runs) - len(todo)
    prog = Progress(len(runs), before, quiet=quiet)
    stats = {"total": len(runs), "stored_before": before, "computed": 0, "failed": 0, "retried": 0,
             "run_wall_s": [], "round_trip_s": [], "session": store.session}
    if not todo:
        prog.close()
        stats["wall_s"] = 0.0
        return stats
    for r in todo:
        store.clear_failure(r.run_id)

    def _sig(signum, frame):
        raise Interrupted()

    old = signal.signal(signal.SIGTERM, _sig)
    t0 = time.time()
    futures = {}
    live = {}
    submitted = {}
    ac = as_completed()

    def submit(r, attempt):
        key = "ggins-run-%s-s%d-a%d" % (r.run_id, store.session, attempt)
        f = client.submit(eval, _TRAMPOLINE, {"blob": _EXECUTE_BLOB, "task": r.task()}, key=key, pure=False)
        futures[f.key] = (r, attempt)
        live[f.key] = f
        submitted[f.key] = time.time()
        ac.add(f)

    stored = set()
    try:
        for r in todo:
            submit(r, 1)
        prog.draw(force=True)
        for f in ac:
            r, attempt = futures.pop(f.key)
            live.pop(f.key, None)
            try:
                res = f.result()
            except Exception as e:  # e.g. KilledWorker: the task took down several workers
                res = {"ok": False, "rc": None, "host": None,
                       "log": "ggins campaign: the engine lost this run: %s\n%s" % (e, traceback.format_exc())}
            f.release()
            if r.run_id in stored or store.done(r.run_id):
                continue
            if res.get("ok"):
                store.write_run(r, res, attempt)
                stored.add(r.run_id)
                stats["computed"] += 1
                stats["run_wall_s"].append(res.get("run_wall_s") or 0.0)
                stats["round_trip_s"].append(time.time() - submitted.pop(f.key, t0))
                prog.done += 1
                if attempt > 1:
                    prog.retrying -= 1
            elif attempt <= retries:
                store.note_retry(r, res)
                stats["retried"] += 1
                prog.retrying += 1
                if not quiet:
                    log.write("\nggins campaign: run %s (point %d, seed %d) failed (rc %s on %s); retrying\n"
                              % (r.run_id, r.point_index, r.seed, res.get("rc"), res.get("host")))
                submit(r, attempt + 1)
            else:
                store.write_failure(r, res, attempt)
                stats["failed"] += 1
                prog.failed += 1
                if attempt > 1:
                    prog.retrying -= 1
            prog.draw()
            if stop_after is not None and stats["computed"] >= stop_after:
                raise Interrupted()
    except (KeyboardInterrupt, Interrupted):
        try:
            client.cancel(list(live.values()), force=True)
        except Exception:
            pass
        prog.close()
        stats["interrupted"] = True
        stats["wall_s"] = time.time() - t0
        signal.signal(signal.SIGTERM, old)
        return stats
    signal.signal(signal.SIGTERM, old)
    prog.close()
    stats["wall_s"] = time.time() - t0
    return stats
