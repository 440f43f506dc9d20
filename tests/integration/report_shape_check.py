#!/usr/bin/env python3
"""One report shape for every command that flies: summary.json of a short `ggins run`,
`ggins run3d`, `ggins montecarlo` and `ggins montecarlo3d` checked against one schema
(report_schema.json, JSON Schema; the Monte Carlo reports also against its `ensemble`
definition), units in every CSV column, the scenario.toml each writes flying again with the
same command to the same numbers, and the ensemble's numbers against its own runs:
steps summed, errors.final the RMS of the runs' finals, max the largest, the chi-square
band recomputed here (Wilson-Hilferty, independently of truth/stats.cpp). And Ctrl-C
(SIGINT to the process group, as a terminal sends it) during `ggins montecarlo`: no run
starts after it, exit 130, a report marked interrupted whose unflown steps include the
runs never started; the same for `ggins montecarlo3d`, whose runs are threads of one process. Every flight
reports position, velocity and gravity errors.

usage: report_shape_check.py --bin DIR --workdir DIR
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time

FAILS = []
UNIT = re.compile(r"_(m|mps|mps2|rad|radps|radps2|ps2|E|s|hz|ns|ppm|deg|am|1)$")  # am: arcmin
FLAGS = ("health", "health_bits", "seq", "status", "baro_due", "baro_status", "baro_outlier")  # counters, flags, words


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


TYPES = {"object": dict, "array": list, "string": str, "boolean": bool}


def is_type(v, t):
    if t == "number":
        return isinstance(v, (int, float)) and not isinstance(v, bool) or v is None  # NaN is written as null
    if t == "integer":
        return isinstance(v, int) and not isinstance(v, bool)
    return isinstance(v, TYPES[t])


def validate(v, sc, path, errs):
    """The subset of JSON Schema report_schema.json uses (type, enum, required, properties,
    patternProperties, additionalProperties, propertyNames.pattern, items)."""
    if "type" in sc:
        ts = sc["type"] if isinstance(sc["type"], list) else [sc["type"]]
        if not any(is_type(v, t) for t in ts):
            errs.append(f"{path}: {json.dumps(v)[:60]} is not {sc['type']}")
            return
    if "enum" in sc and v not in sc["enum"]:
        errs.append(f"{path}: {v!r} not in {sc['enum']}")
    if isinstance(v, dict):
        for k in sc.get("required", []):
            if k not in v:
                errs.append(f"{path}: missing '{k}'")
        pn = sc.get("propertyNames", {}).get("pattern")
        for k, x in v.items():
            if pn and not re.search(pn, k):
                errs.append(f"{path}.{k}: name does not match {pn} (a unit)")
            matched = False
            if k in sc.get("properties", {}):
                validate(x, sc["properties"][k], f"{path}.{k}", errs)
                matched = True
            for pat, sub in sc.get("patternProperties", {}).items():
                if re.search(pat, k):
                    validate(x, sub, f"{path}.{k}", errs)
                    matched = True
            if not matched and isinstance(sc.get("additionalProperties"), dict):
                validate(x, sc["additionalProperties"], f"{path}.{k}", errs)
    if isinstance(v, list) and "items" in sc:
        for i, x in enumerate(v):
            validate(x, sc["items"], f"{path}[{i}]", errs)


def against_schema(rep, schema, what, ensemble=False):
    errs = []
    validate(rep, schema, "summary", errs)
    if ensemble:
        validate(rep, schema["$defs"]["ensemble"], "summary", errs)
    check(not errs, f"{what}: summary.json has the report's shape" + ("".join("\n     " + e for e in errs[:8])))
    ok = not errs
    try:  # an independent validator too, where installed
        import jsonschema
        s = dict(schema)
        if ensemble:
            s = {"allOf": [schema, {"$ref": "#/$defs/ensemble"}], "$defs": schema["$defs"]}
        jsonschema.validate(rep, s)
        check(True, f"{what}: jsonschema agrees")
    except ImportError:
        pass
    except Exception as e:  # jsonschema.ValidationError
        check(False, f"{what}: jsonschema: {str(e)[:300]}")
        ok = False
    return ok


def csv_units(path, what, allow=()):
    with open(path) as f:
        head = next(csv.reader(f))
    bad = [c for c in head if not UNIT.search(c) and c not in allow]
    check(not bad, f"{what}: every column of {os.path.basename(path)} carries its unit" + (f" (not: {bad})" if bad else ""))


def wilson_hilferty_ratio(n, z):
    """s/sigma band: sqrt(chi2_p / n), chi2_p ~ n (1 - 2/(9n) + z_p sqrt(2/(9n)))^3."""
    a = 2.0 / (9.0 * n)
    return math.sqrt((1 - a - z * math.sqrt(a)) ** 3), math.sqrt((1 - a + z * math.sqrt(a)) ** 3)


def ensemble_numbers(rep, what):
    en = rep["ensemble"]
    pr = en["per_run"]
    check(en["runs_flown"] == len(pr) == en["runs"], f"{what}: every run in per_run ({len(pr)})")
    check(rep["steps_flown"] == sum(r["steps_flown"] for r in pr) and rep["steps_unflown"] == 0,
          f"{what}: steps_flown = the runs' sum ({rep['steps_flown']}), none unflown")
    qs = [k for k, v in rep["errors"].items() if isinstance(v, dict) and "final" in v and "max" in v]
    check("position_error_m" in qs, f"{what}: errors over the runs: {', '.join(qs)}")
    for q in qs:
        fk = q[: q.rfind("_")] + "_final" + q[q.rfind("_"):]
        rms = math.sqrt(sum(r[fk] ** 2 for r in pr) / len(pr))
        got = rep["errors"][q]["final"]
        check(abs(got - rms) <= 1e-12 * max(abs(rms), 1e-300), f"{what}: errors.{q}.final = RMS of the runs' finals ({got:.6g})")
        check(rep["errors"][q]["max"] >= max(r[fk] for r in pr), f"{what}: errors.{q}.max >= every run's final")
    c = en["consistency"]
    lo, hi = wilson_hilferty_ratio(c["dof"], c["z"])
    check(abs(c["ratio_lo"] - lo) < 1e-12 and abs(c["ratio_hi"] - hi) < 1e-12,
          f"{what}: chi-square band [{c['ratio_lo']:.4f}, {c['ratio_hi']:.4f}] for N = {c['dof']} at z = {c['z']}")
    for k, s in c["states"].items():
        r = s["sample_rms"] / s["predicted_sigma"]
        if abs(r - s["ratio"]) > 1e-12 * abs(r) or s["within"] != (lo <= r <= hi):
            check(False, f"{what}: consistency.{k}: ratio and within from sample_rms / predicted_sigma")
            break
    else:
        check(True, f"{what}: every consistency ratio = sample_rms / predicted_sigma, within the band as stated")
    check(c["all_within"] == all(s["within"] for s in c["states"].values()), f"{what}: all_within")


def interrupt_montecarlo(exe, d):
    n = 8
    p = subprocess.Popen([exe, "-s", "welker-table1", "-n", str(n), "-j", "1", "--duration", "600", "--no-plot",
                          "--keep-runs", "-o", d], start_new_session=True, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    t_end = time.time() + 60
    while time.time() < t_end and not os.path.exists(os.path.join(d, "runs", "1", "timeseries.csv")) and p.poll() is None:
        time.sleep(0.05)
    time.sleep(0.3)  # run 1 under way
    started = sorted(int(x) for x in os.listdir(os.path.join(d, "runs")) if x.isdigit()) if os.path.isdir(
        os.path.join(d, "runs")) else []
    os.killpg(p.pid, signal.SIGINT)
    t0 = time.time()
    try:
        _, err = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        _, err = p.communicate()
    dt = time.time() - t0
    check(p.returncode == 130 and dt < 30, f"montecarlo Ctrl-C: exit {p.returncode} after {dt:.1f} s (want 130)")
    after = sorted(int(x) for x in os.listdir(os.path.join(d, "runs")) if x.isdigit())
    check(len(after) <= len(started) + 1 and len(after) < n,
          f"montecarlo Ctrl-C: no run started after it (runs {started} before, {after} after, of {n})")
    p_rep = os.path.join(d, "summary.json")
    if not os.path.exists(p_rep):
        check(False, "montecarlo Ctrl-C: a report is written\n" + err[-800:])
        return
    r = json.load(open(p_rep))
    per = r["steps_expected"] // n
    check(r["status"] == "interrupted" and r["interrupted"] and not r["completed"] and r["frames_lost"] == 0,
          f"montecarlo Ctrl-C: status {r['status']}, frames_lost {r['frames_lost']}")
    check(r["steps_expected"] == n * per and r["steps_flown"] + r["steps_unflown"] == r["steps_expected"] and
          r["steps_unflown"] >= (n - len(after)) * per,
          f"montecarlo Ctrl-C: {r['steps_flown']} flown + {r['steps_unflown']} unflown = {r['steps_expected']} "
          f"= {n} runs x {per} steps, the {n - len(after)} runs never started among the unflown")


def interrupt_montecarlo3d(exe, d):
    """Ctrl-C during `ggins montecarlo3d` (in-process runs on threads): no run starts after it,
    the run in flight stops, exit 130, a partial report marked interrupted with every requested
    run in per_run: the completed ones, the one stopped, the unflown ones counted as such."""
    n, per = 40, 60001  # 600 s at 100 Hz: about a second a run
    p = subprocess.Popen([exe, "-s", "gc3d-stabilized", "-n", str(n), "-j", "1", "--rate-hz", "100", "--duration",
                          "600", "--output-dt", "60", "--no-plot", "-o", d], start_new_session=True,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(4.0)  # the perfect-sensor run and a few of the ensemble flown
    os.killpg(p.pid, signal.SIGINT)
    t0 = time.time()
    try:
        _, err = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        _, err = p.communicate()
    dt = time.time() - t0
    check(p.returncode == 130 and dt < 10, f"montecarlo3d Ctrl-C: exit {p.returncode} after {dt:.1f} s (want 130)")
    p_rep = os.path.join(d, "summary.json")
    if not os.path.exists(p_rep):
        check(False, "montecarlo3d Ctrl-C: a report is written\n" + err[-800:])
        return
    r = json.load(open(p_rep))
    pr = r["ensemble"]["per_run"]
    st = [("completed" if x["status"] == "completed" else "stopped" if x["steps_flown"] > 0 else "unflown")
          for x in pr]
    k = st.count("completed")
    order = st == ["completed"] * k + ["stopped"] * st.count("stopped") + ["unflown"] * st.count("unflown")
    check(r["status"] == "interrupted" and r["interrupted"] and not r["completed"] and r["frames_lost"] == 0 and
          r["error_code"] == 130, f"montecarlo3d Ctrl-C: status {r['status']}, error {r.get('error')!r}")
    check(r["steps_expected"] == n * per and r["steps_flown"] + r["steps_unflown"] == r["steps_expected"] and
          r["steps_flown"] == sum(x["steps_flown"] for x in pr) and
          all(x["steps_flown"] == per for x in pr if x["status"] == "completed"),
          f"montecarlo3d Ctrl-C: {r['steps_flown']} flown + {r['steps_unflown']} unflown = {r['steps_expected']} "
          f"= {n} runs x {per} steps")
    check(len(pr) == n and order and st.count("stopped") <= 1 and st.count("unflown") >= 1 and
          r["ensemble"]["runs_failed"] == n - k and r["ensemble"]["runs_flown"] == k + st.count("stopped"),
          f"montecarlo3d Ctrl-C: {len(pr)} runs listed: {k} completed, {st.count('stopped')} stopped in flight, "
          f"{st.count('unflown')} never started")


def numbers(rep):
    """The summary numbers a flight of the same scenario reproduces (not the wall times)."""
    keys = ("status", "task", "rate_hz", "dt_s", "duration_s", "flown_s", "steps_expected", "steps_flown",
            "steps_rejected", "health_seen", "health_counts", "errors")
    out = {k: rep.get(k) for k in keys}
    if "ensemble" in rep:
        en = rep["ensemble"]
        out["per_run"] = en["per_run"]
        out["consistency"] = en["consistency"]
    return out


def refly(what, cmd, d, w):
    """The written scenario.toml flies again with the same command: the same numbers."""
    p = os.path.join(d, "scenario.toml")
    d2 = os.path.join(w, os.path.basename(d) + "-again")
    c = list(cmd)
    c[c.index("-s") + 1] = p
    for opt in ("--duration", "--rate-hz"):  # in the file now
        if opt in c:
            i = c.index(opt)
            del c[i:i + 2]
    c[c.index("--out" if "--out" in c else "-o") + 1] = d2
    r = subprocess.run(c, capture_output=True, text=True, timeout=600)
    q = os.path.join(d2, "summary.json")
    if not os.path.exists(q):
        check(False, f"{what}: its scenario.toml flies again (exit {r.returncode})\n" + r.stderr[-1500:])
        return
    a, b = numbers(json.load(open(os.path.join(d, "summary.json")))), numbers(json.load(open(q)))
    diff = [k for k in a if a[k] != b[k]]
    check(r.returncode in (0, 1, 3) and not diff and a["steps_flown"] > 0,
          f"{what}: -s <out>/scenario.toml flies again with the same numbers (exit {r.returncode}"
          + (f", differ: {diff}" if diff else "") + ")")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    schema = json.load(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "report_schema.json")))
    w = a.workdir
    shutil.rmtree(w, ignore_errors=True)
    os.makedirs(w)
    b = lambda t: os.path.join(a.bin, t)
    out = {k: os.path.join(w, k) for k in ("run", "run3d", "mc", "mc3d")}
    flights = [
        ("run", [b("ggins-run"), "-s", "welker-table1", "--direct", "--duration", "5", "--no-plots", "-q", "--out", out["run"]]),
        ("run3d", [b("ggins-run3d"), "-s", "3d-stabilized-1h", "--direct", "--duration", "5", "--no-plots", "-q",
                   "--out", out["run3d"]]),
        ("montecarlo", [b("ggins-montecarlo"), "-s", "welker-table1", "-n", "3", "-j", "1", "--duration", "5", "--no-plot",
                        "-o", out["mc"]]),
        ("montecarlo3d", [b("ggins-montecarlo3d"), "-s", "gc3d-stabilized", "-n", "3", "-j", "1", "--rate-hz", "10",
                          "--duration", "20", "--output-dt", "10", "--no-plot", "-o", out["mc3d"]]),
    ]
    navigation = ("run", "run3d", "montecarlo", "montecarlo3d")  # tasks that estimate gravity
    for what, cmd in flights:
        if not os.path.exists(cmd[0]):
            print(f"skip {what} (not built)")
            continue
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        d = out[{"run": "run", "run3d": "run3d", "montecarlo": "mc", "montecarlo3d": "mc3d"}[what]]
        # exit 0, or a Monte Carlo whose few runs fall outside the chi-square band (a result)
        ok_codes = (0,) if what.startswith("run") else (0, 1, 3)
        check(r.returncode in ok_codes, f"{what}: exit {r.returncode}" + ("" if r.returncode in ok_codes else "\n" + r.stderr[-1500:]))
        p = os.path.join(d, "summary.json")
        if not os.path.exists(p):
            check(False, f"{what}: wrote summary.json")
            continue
        rep = json.load(open(p))
        ens = what not in ("run", "run3d")
        if not against_schema(rep, schema, what, ensemble=ens):
            continue  # the checks below read the report's keys
        if what in navigation:
            need = ("position_error_m", "velocity_error_mps", "gravity_error_mps2", "position_error_final_m",
                    "velocity_error_final_mps", "gravity_error_final_mps2")
            miss = [k for k in need if k not in rep["errors"]]
            check(not miss, f"{what}: position, velocity and gravity errors" + (f" (missing {miss})" if miss else ""))
        check(rep["status"] == "completed" and rep["steps_flown"] == rep["steps_expected"] > 0,
              f"{what}: status {rep['status']}, {rep['steps_flown']} of {rep['steps_expected']} steps")
        check(os.path.exists(os.path.join(d, rep["files"]["scenario"])), f"{what}: the scenario as flown is written")
        if what == "run":
            csv_units(os.path.join(d, "timeseries.csv"), what, allow=FLAGS)
        if what == "run3d":
            csv_units(os.path.join(d, "timeseries.csv"), what, allow=FLAGS)
        if what == "montecarlo":
            csv_units(os.path.join(d, "montecarlo.csv"), what)
            csv_units(os.path.join(d, "run_errors.csv"), what, allow=("run",))
            ensemble_numbers(rep, what)
        if what == "montecarlo3d":
            csv_units(os.path.join(d, "montecarlo3d.csv"), what)
            ensemble_numbers(rep, what)
        if what in navigation:
            refly(what, cmd, d, w)
    if os.path.exists(b("ggins-montecarlo")):
        interrupt_montecarlo(b("ggins-montecarlo"), os.path.join(w, "mc-int"))
    if os.path.exists(b("ggins-montecarlo3d")):
        interrupt_montecarlo3d(b("ggins-montecarlo3d"), os.path.join(w, "mc3d-int"))
    print(f"{len(FAILS)} failure(s)")
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
