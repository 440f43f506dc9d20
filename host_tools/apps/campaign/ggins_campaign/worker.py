"""One campaign run, executed on a Dask worker.

This module uses the standard library only and is shipped to the workers by value
(cloudpickle), so a worker needs a Python with the pinned `distributed`, the built
ggins tools and the data files -- not this package.

A task is a plain dict (see tools.py, Run.task()):
  run_id       content hash of everything that determines the run
  argv         the command line; "{bin}", "{out}", "{data}", "{cache}" are substituted here
  files        {name: text} written into the run's scratch folder first (the swept scenario)
  parse        what to read back: a list of {"csv": ...} / {"json": ...} extraction rules
  series_dt    spacing of the stored time series, s (0: final values only)
  bin_dir, data_dir   where the client found the tools and data; a worker that has them
               elsewhere sets GGINS_BIN / GGINS_DATA
  timeout_s    a run that takes longer is killed and counts as failed
  ok_codes     exit codes of a run that counts (default [0])
  data_probe   a file the data folder must hold (default: any)
"""
import csv
import json
import math
import os
import shutil
import socket
import subprocess
import tempfile
import time

LOG_TAIL_CHARS = 20000


def _resolve_dir(preferred, env, probe):
    """The first of (task's path, $env) that holds `probe`."""
    for d in (preferred, os.environ.get(env)):
        if d and os.path.exists(os.path.join(d, probe)):
            return d
    return preferred


def _subst(s, m):
    for k, v in m.items():
        s = s.replace("{" + k + "}", v)
    return s


def _on_grid(t, dt):
    if dt <= 0:
        return False
    k = round(t / dt)
    return abs(t - k * dt) <= 1e-6 * max(1.0, dt)


def _read_csv(path, rule, series_dt):
    """Columns of a CSV: `columns` {csv name: stored name} or `prefix` (every column that
    starts with it, stored without the prefix unless `keep_prefix`). Final = last row;
    series = rows on the series_dt grid (plus the last row)."""
    with open(path, newline="") as f:
        rd = csv.reader(f)
        head = next(rd)
        tcol = rule.get("time", "t_s")
        it = head.index(tcol)
        cols = []
        if "columns" in rule:
            for src, dst in rule["columns"].items():
                cols.append((head.index(src), dst))
        else:
            p = rule["prefix"]
            for i, h in enumerate(head):
                if h.startswith(p) and i != it:
                    cols.append((i, (rule.get("name_prefix", "") + (h if rule.get("keep_prefix") else h[len(p):]))))
        rows = []
        last = None
        need = max([it] + [i for i, _ in cols]) + 1
        for r in rd:
            if len(r) < need:
                continue
            vals = [float(r[it])] + [float(r[i]) for i, _ in cols]
            last = vals
            if _on_grid(vals[0], series_dt):
                rows.append(vals)
    if last is None:
        raise ValueError("%s has no data rows" % path)
    if series_dt > 0 and (not rows or rows[-1][0] != last[0]):
        rows.append(last)
    names = [d for _, d in cols]
    final = {n: last[k + 1] for k, n in enumerate(names)}
    final["t_final_s"] = last[0]
    series = {"t_s": [r[0] for r in rows]}
    for k, n in enumerate(names):
        series[n] = [r[k + 1] for r in rows]
    return final, series


def _walk(obj, path):
    for p in path:
        if isinstance(obj, list):
            obj = obj[int(p)]
        else:
            obj = obj[p]
    return obj


def _leaves(obj, prefix, out):
    """Every numeric leaf under obj, dotted names."""
    if isinstance(obj, bool):
        out[prefix] = float(obj)
    elif isinstance(obj, (int, float)):
        out[prefix] = float(obj)
    elif isinstance(obj, dict):
        for k, v in obj.items():
            _leaves(v, prefix + "." + k if prefix else k, out)


def _read_json(path, rule):
    """`values`: {stored name or prefix: dotted path}; a path ending in ".*" stores every
    numeric leaf below it as <prefix><leaf>; {"path": ..., "names": [...]} stores the elements
    of an array as <prefix><name>; a path starting with "?" is optional (nothing stored when
    the file lacks it or holds null there: a mean over no sample)."""
    with open(path) as f:
        j = json.load(f)
    final = {}
    for name, p in rule["values"].items():
        if isinstance(p, str) and p.startswith("?"):
            p = p[1:]
            try:
                if _walk(j, p.split(".")[:-1] if p.endswith(".*") else p.split(".")) is None:
                    continue
            except (KeyError, IndexError, TypeError):
                continue
        if isinstance(p, dict):  # an array, its elements named: {"path": ..., "names": [...]}
            arr = _walk(j, p["path"].split("."))
            if len(arr) != len(p["names"]):
                raise ValueError("%s: %s has %d values, expected %d" % (path, p["path"], len(arr), len(p["names"])))
            for n, v in zip(p["names"], arr):
                final[name + n] = float(v)
            continue
        parts = p.split(".")
        if parts[-1] == "*":
            sub = {}
            _leaves(_walk(j, parts[:-1]), "", sub)
            for k, v in sub.items():
                final[name + k] = v
        else:
            v = _walk(j, parts)
            if isinstance(v, (dict, list)):
                raise ValueError("%s: %s is not a number" % (path, p))
            final[name] = float(v)
    return final


def _keep_json(path, keep):
    """`keep`: {stored name: dotted path} of any JSON value (a string, a list, a whole block) kept
    as it is in the run's record; "?" as in _read_json (absent or null: not kept)."""
    with open(path) as f:
        j = json.load(f)
    out = {}
    for name, p in keep.items():
        opt = p.startswith("?")
        try:
            v = _walk(j, p.lstrip("?").split("."))
        except (KeyError, IndexError, TypeError, ValueError):
            if opt:
                continue
            raise ValueError("%s has no %s" % (path, p))
        if v is not None:
            out[name] = v
    return out


def _glob_one(folder, pattern):
    import fnmatch
    hits = sorted(n for n in os.listdir(folder) if fnmatch.fnmatch(n, pattern))
    if len(hits) != 1:
        raise ValueError("expected one file %s in the run folder, found %s" % (pattern, hits))
    return os.path.join(folder, hits[0])


def execute(task):
    """Run one task; never raises for a failed run (the result says ok=False with the log)."""
    t0 = time.time()
    host = socket.gethostname()
    bin_dir = _resolve_dir(task["bin_dir"], "GGINS_BIN", "ggins")
    data_dir = _resolve_dir(task.get("data_dir") or "", "GGINS_DATA", task.get("data_probe") or ".")
    cache_root = os.environ.get("GGINS_CAMPAIGN_CACHE") or os.path.join(tempfile.gettempdir(), "ggins-campaign-cache")
    scratch = tempfile.mkdtemp(prefix="ggins-run-")
    out = os.path.join(scratch, "out")
    res = {"run_id": task["run_id"], "host": host, "pid": os.getpid(), "ok": False}
    try:
        cache = os.path.join(cache_root, task.get("cache_key") or "default")
        os.makedirs(cache, exist_ok=True)
        m = {"bin": bin_dir, "out": out, "data": data_dir or "", "cache": cache, "scratch": scratch}
        for name, text in (task.get("files") or {}).items():
            with open(os.path.join(scratch, name), "w") as f:
                f.write(text)
        argv = [_subst(a, m) for a in task["argv"]]
        res["argv"] = argv
        log_path = os.path.join(scratch, "run.log")
        with open(log_path, "w") as log:
            try:
                p = subprocess.run(argv, cwd=scratch, stdout=log, stderr=subprocess.STDOUT,
                                   timeout=task.get("timeout_s") or None)
                rc = p.returncode
            except subprocess.TimeoutExpired:
                rc = -9
                log.write("\nggins campaign: run killed after %s s (timeout)\n" % task.get("timeout_s"))
            except OSError as e:
                rc = 127
                log.write("\nggins campaign: cannot start %s: %s\n" % (argv[0], e))
        with open(log_path, errors="replace") as f:
            text = f.read()
        res["log"] = text[-LOG_TAIL_CHARS:]
        res["rc"] = rc
        res["run_wall_s"] = time.time() - t0
        if rc not in task.get("ok_codes", [0]):
            return res
        final, series = {}, {}
        for rule in task["parse"]:
            if "csv" in rule:
                f, s = _read_csv(_glob_one(out, rule["csv"]), rule, float(task.get("series_dt", 0)))
                final.update(f)
                if s and len(s.get("t_s", [])) and not series:
                    series = s
                elif s and s.get("t_s") == series.get("t_s"):  # same time grid: one table
                    series.update({k: v for k, v in s.items() if k != "t_s"})
            else:
                jpath = _glob_one(out, rule["json"])
                final.update(_read_json(jpath, rule))
                if rule.get("keep"):
                    res.setdefault("info", {}).update(_keep_json(jpath, rule["keep"]))
        bad = [k for k, v in final.items() if not math.isfinite(v)]
        res["final"] = final
        res["series"] = series
        res["nonfinite"] = bad
        res["ok"] = True
        return res
    except Exception as e:  # parse errors etc.: a failed run with the reason in its log
        res["log"] = (res.get("log") or "") + "\nggins campaign: %s: %s\n" % (type(e).__name__, e)
        res.setdefault("rc", -1)
        res["ok"] = False
        return res
    finally:
        res["wall_s"] = time.time() - t0
        shutil.rmtree(scratch, ignore_errors=True)
