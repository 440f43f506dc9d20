"""The summary of a campaign: one table (per point and output) and the plots.

Statistics over the N stored runs of a point, for every final value e_1..e_N:
  mean, sd (N-1), 95 % confidence interval of the mean (Student t, N-1 dof),
  sample sigma s = sqrt(sum e^2 / N) about zero (the errors of zero-mean random draws through
  a linear error model; N dof), mean |e| and the spread of |e| (population sd).
Against a covariance prediction sigma (run: ggins covariance on the point's scenario, the same
model and code as ggins montecarlo): N s^2 / sigma^2 ~ chi^2_N, so s/sigma lies in
[sqrt(chi2_lo/N), sqrt(chi2_hi/N)] with the two-sided chi-square quantiles at +-z standard
normal quantiles (Wilson-Hilferty, as ggins montecarlo; z = 3: 99.73 % per state).
Filter consistency: NEES and NIS means over the runs against their dof (run3d's aided table
adds the map UKF's NEES per 3-dof block and NIS, and the particle filter's (err/spread)^2).
"""
import csv
import json
import math
import os
import shutil
import subprocess
import tempfile

from . import routes_report, tomlw
from .store import read_run

# Student t, 97.5 % quantiles, dof 1..30
_T975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145,
         2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048,
         2.045, 2.042]


def t975(dof):
    if dof < 1:
        return float("nan")
    if dof <= 30:
        return _T975[dof - 1]
    z = 1.959964
    return z + (z ** 3 + z) / (4 * dof) + (5 * z ** 5 + 16 * z ** 3 + 3 * z) / (96 * dof ** 2)


def chi2_quantile_wh(n, z):
    """Wilson-Hilferty: chi^2_N at the standard-normal quantile z."""
    a = 2.0 / (9.0 * n)
    c = max(0.0, 1.0 - a + z * math.sqrt(a))  # (the approximation goes negative for tiny N, low tail)
    return n * c * c * c


def sigma_band(n, z):
    return math.sqrt(chi2_quantile_wh(n, -z) / n), math.sqrt(chi2_quantile_wh(n, z) / n)


def stats(values):
    n = len(values)
    if n == 0:
        return {"n": 0}
    mean = sum(values) / n
    sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1)) if n > 1 else 0.0
    half = t975(n - 1) * sd / math.sqrt(n) if n > 1 else float("nan")
    ab = [abs(v) for v in values]
    ma = sum(ab) / n
    sd_abs = math.sqrt(max(0.0, sum(a * a for a in ab) / n - ma * ma))
    return {"n": n, "mean": mean, "sd": sd, "ci95_lo": mean - half, "ci95_hi": mean + half,
            "sigma": math.sqrt(sum(v * v for v in values) / n), "mean_abs": ma, "sd_abs": sd_abs,
            "min": min(values), "max": max(values)}


def _python_with_matplotlib():
    for py in (os.environ.get("GGINS_PYTHON"), "/usr/bin/python3", shutil.which("python3")):
        if py and os.path.exists(py):
            if subprocess.run([py, "-c", "import matplotlib"], capture_output=True).returncode == 0:
                return py
    return None


def covariance_prediction(campaign, point, dt):
    """run: (t list, {state: sigma list}) from ggins covariance on the point's scenario."""
    sc = campaign.point_scenario(point)
    d = tempfile.mkdtemp(prefix="ggins-cov-")
    try:
        path = os.path.join(d, "scenario.toml")
        with open(path, "w") as f:
            f.write(tomlw.dumps(sc))
        noise = (sc.get("accel") or {}).get("noise_sigma_mps2", 0.0)
        noisy = any(x != 0 for x in (noise if isinstance(noise, list) else [noise]))
        argv = [os.path.join(campaign.bin_dir, "ggins-covariance"), "--scenario", path, "--dt", "1",
                "--output-dt", repr(float(dt if dt > 0 else sc.get("time", {}).get("duration_s", 3600.0))),
                "--no-plot", "--out", os.path.join(d, "cov")]
        if noisy:
            argv += ["--method", "lyapunov"]
        p = subprocess.run(argv, capture_output=True, text=True)
        if p.returncode != 0:
            raise RuntimeError("ggins covariance failed (%s): %s" % (" ".join(argv), p.stderr[-2000:]))
        with open(os.path.join(d, "cov", "covariance.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        t = [float(r["t_s"]) for r in rows]
        out = {}
        for k in rows[0]:
            if k in ("x_m", "z_m", "vx_mps", "vz_mps", "gx_mps2", "gz_mps2"):
                out[k] = [float(r[k]) for r in rows]
        return t, out
    finally:
        shutil.rmtree(d, ignore_errors=True)


def _interp_at(t, ts, ys):
    """ys at time t (nearest sample within 1e-6 s, else linear)."""
    lo, hi = 0, len(ts) - 1
    if t <= ts[0]:
        return ys[0]
    if t >= ts[-1]:
        return ys[-1]
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if ts[mid] <= t:
            lo = mid
        else:
            hi = mid
    if abs(ts[lo] - t) < 1e-6:
        return ys[lo]
    w = (t - ts[lo]) / (ts[hi] - ts[lo])
    return ys[lo] * (1 - w) + ys[hi] * w


def summarize(campaign, store, runs, plot=True, log=None):
    out = store.out
    by_point = {}
    for r in runs:
        by_point.setdefault(r.point_index, []).append(r)
    points = []
    series_rows = []
    all_metas = []
    for pi, prs in sorted(by_point.items()):
        point = campaign.points[pi]
        metas, series = [], []
        for r in sorted(prs, key=lambda x: x.seed_index):
            if store.done(r.run_id):
                m, s = read_run(store.run_path(r.run_id))
                m["final"].update(campaign.tool.derived(s))
                metas.append(m)
                series.append(s)
        all_metas += metas
        failed = store.failures([r.run_id for r in prs])
        names = []
        for m in metas:
            for k in m["final"]:
                if k not in names:
                    names.append(k)
        fin = {k: stats([m["final"][k] for m in metas if k in m["final"]]) for k in names}
        P = {"point": pi, "name": point.get("name", ""), "params": {k: v for k, v in point.items() if k != "name"},
             "runs": len(prs), "stored": len(metas), "failed": [{"seed": f["seed"], "run_id": f["run_id"],
                                                                  "rc": f.get("rc")} for f in failed],
             "seeds": [m["seed"] for m in metas], "final": fin}
        # time series: per-time statistics across the runs (same time grid in every run)
        ser = {}
        if series and len(series[0].get("t_s", [])):
            nt = min(len(s["t_s"]) for s in series)
            t = series[0]["t_s"][:nt]
            for k in series[0]:
                if k == "t_s" or not all(k in s for s in series):
                    continue
                rms = [math.sqrt(sum(s[k][i] ** 2 for s in series) / len(series)) for i in range(nt)]
                mean = [sum(s[k][i] for s in series) / len(series) for i in range(nt)]
                ser[k] = {"sigma": rms, "mean": mean}
            ser = {"t_s": t, "states": ser}
        P["series"] = ser
        # covariance prediction and chi-square band
        if campaign.compare == "covariance" and campaign.command == "run" and metas:
            n = len(metas)
            lo, hi = sigma_band(n, campaign.z)
            tc, cov = covariance_prediction(campaign, point, campaign.series_dt)
            cmp = {"n": n, "z": campaign.z, "ratio_lo": lo, "ratio_hi": hi, "states": {}}
            tf = min(m["final"].get("t_final_s", tc[-1]) for m in metas)
            allin = True
            for k, sig in cov.items():
                if k not in fin:
                    continue
                c = _interp_at(tf, tc, sig)
                ratio = fin[k]["sigma"] / c if c > 0 else float("nan")
                ok = lo <= ratio <= hi
                allin = allin and ok
                cmp["states"][k] = {"montecarlo": fin[k]["sigma"], "covariance": c, "ratio": ratio, "within": ok}
                if ser and k in ser["states"]:
                    ser["states"][k]["covariance"] = [_interp_at(x, tc, sig) for x in ser["t_s"]]
            cmp["t_s"] = tf
            cmp["all_within"] = allin
            P["covariance"] = cmp
        if "nees" in fin and "nees_dof" in fin:
            P["consistency"] = {"nees_mean": fin["nees"]["mean"], "nees_dof": fin["nees_dof"]["mean"],
                                "nis_mean": fin.get("nis", {}).get("mean"), "nis_dof": fin.get("nis_dof", {}).get("mean")}
        points.append(P)
        if ser:
            for k, v in ser["states"].items():
                for i, t in enumerate(ser["t_s"]):
                    row = {"point": pi, "t_s": t, "output": k, "sigma": v["sigma"][i], "mean": v["mean"][i]}
                    if "covariance" in v:
                        row["covariance"] = v["covariance"][i]
                    series_rows.append(row)
    summary = {"campaign": campaign.name, "command": campaign.command, "scenario": campaign.scenario_name,
               "description": campaign.description, "seeds_per_point": campaign.seeds, "seed0": campaign.seed0,
               "sweep_keys": campaign.sweep_keys, "param_keys": campaign.param_keys, "points": points}
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    routes_md = None
    if getattr(campaign, "routes", None) is not None:  # random routes: the per-aid report (routes_report.py)
        R, routes_md = routes_report.write(out, all_metas)
        summary["routes"] = {g: {k: v for k, v in G.items() if not k.endswith("_list") and k != "log10_ratio"}
                             for g, G in R["groups"].items()}
    _write_table(summary, campaign, out, routes_md)
    if series_rows:
        keys = ["point", "t_s", "output", "sigma", "mean", "covariance"]
        with open(os.path.join(out, "series.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys)
            w.writeheader()
            for row in series_rows:
                w.writerow(row)
    plots = []
    if plot:
        py = _python_with_matplotlib()
        if py:
            script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "plot.py")
            p = subprocess.run([py, script, out], capture_output=True, text=True)
            if p.returncode != 0 and log:
                log.write("ggins campaign: plot failed: %s\n" % p.stderr[-2000:])
            plots = [l.strip() for l in p.stdout.splitlines() if l.strip().endswith(".png")]
            if routes_md is not None:
                p = subprocess.run([py, os.path.join(os.path.dirname(script), "plot_routes.py"), out],
                                   capture_output=True, text=True)
                if p.returncode != 0 and log:
                    log.write("ggins campaign: routes plot failed: %s\n" % p.stderr[-2000:])
                plots += [l.strip() for l in p.stdout.splitlines() if l.strip().endswith(".png")]
        elif log:
            log.write("ggins campaign: no python with matplotlib (GGINS_PYTHON); no plots\n")
    return summary, plots


def _g(x):
    return "%.6g" % x if isinstance(x, float) else str(x)


def _write_table(summary, campaign, out, routes_md=None):
    keys = campaign.param_keys
    cols = ["point", "name"] + keys + ["output", "n", "failed", "mean", "sd", "ci95_lo", "ci95_hi", "sigma",
                                      "mean_abs", "sd_abs", "covariance", "ratio", "band_lo", "band_hi", "within"]
    rows = []
    for P in summary["points"]:
        cmp = P.get("covariance", {})
        for k, s in P["final"].items():
            if s.get("n", 0) == 0:
                continue
            row = {"point": P["point"], "name": P["name"], "output": k, "failed": len(P["failed"])}
            row.update({kk: P["params"].get(kk, "") for kk in keys})
            row.update({kk: s[kk] for kk in ("n", "mean", "sd", "ci95_lo", "ci95_hi", "sigma", "mean_abs", "sd_abs")})
            c = cmp.get("states", {}).get(k)
            if c:
                row.update({"covariance": c["covariance"], "ratio": c["ratio"], "band_lo": cmp["ratio_lo"],
                            "band_hi": cmp["ratio_hi"], "within": c["within"]})
            rows.append(row)
    with open(os.path.join(out, "summary.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for row in rows:
            w.writerow(row)
    # markdown: one line per point and output
    md = ["# campaign %s (%s)" % (summary["campaign"], summary["command"]), ""]
    if summary["description"]:
        md += [summary["description"], ""]
    head = ["point"] + keys + ["output", "N", "mean ± 95 % CI", "sigma", "mean |e| ± sd"]
    has_cov = any("covariance" in P for P in summary["points"])
    if has_cov:
        head += ["covariance", "ratio", "band", "in band"]
    md.append("| " + " | ".join(head) + " |")
    md.append("|" + "---|" * len(head))
    for row in rows:
        if row["output"] == "t_final_s" or row["output"].endswith("_dof"):
            continue
        half = (row["ci95_hi"] - row["ci95_lo"]) / 2
        cells = [row["name"]] + [_g(row[k]) for k in keys] + [row["output"], str(row["n"]),
                                                               "%.4g ± %.2g" % (row["mean"], half) if half == half else "%.4g" % row["mean"],
                                                               "%.6g" % row["sigma"],
                                                               "%.3g ± %.2g" % (row["mean_abs"], row["sd_abs"])]
        if has_cov:
            if "ratio" in row:
                cells += ["%.6g" % row["covariance"], "%.4f" % row["ratio"],
                          "[%.4f, %.4f]" % (row["band_lo"], row["band_hi"]), "yes" if row["within"] else "NO"]
            else:
                cells += ["", "", "", ""]
        md.append("| " + " | ".join(cells) + " |")
    if campaign.command == "run3d":
        md += [""] + aided3d_table(summary)
    if routes_md:
        md += [""] + routes_md
    fails = [(P["name"], f) for P in summary["points"] for f in P["failed"]]
    if fails:
        md += ["", "Failed runs (twice; logs in failed/):", ""]
        md += ["- point %s, seed %s: rc %s, failed/%s.log" % (n, f["seed"], f["rc"], f["run_id"]) for n, f in fails]
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("\n".join(md) + "\n")


def aided3d_table(summary):
    """run3d: per point the statistics of the aided papers: mean over the runs of |error| at the end
    per axis (Gao et al.'s Table 2), the mean of each run's RMS over the last 2 h (Tables 3-9),
    the mean horizontal error over the flight (Phillips et al.), the same flights unaided at the
    end, and the aids' consistency (NEES per 3-dof block and NIS of the map UKF; (err/spread)^2
    of the particle filter, 1 = consistent)."""
    def cell(f, k, fmt="%.3g"):
        return fmt % f[k]["mean_abs"] if k in f and f[k].get("n") else ""

    def mean(f, k, fmt="%.3g"):
        return fmt % f[k]["mean"] if k in f and f[k].get("n") else ""

    md = ["Aided flights: mean over runs of |error| at the end (N / E / D, m), of each run's RMS over the last "
          "2 h, and of the horizontal error averaged over the flight; unaided: the same frames with every aid off", "",
          "| point | N | end N | end E | end D | RMS2h N | RMS2h E | RMS2h D | mean horiz. | unaided end N | "
          "unaided end E | unaided end D | unaided mean horiz. | NEES pos/vel/att (3) | NIS (6) | PF (err/spread)^2 |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for P in summary["points"]:
        f = P["final"]
        if "rms2h_rn_m" not in f:
            continue
        nees = "/".join(mean(f, k, "%.2f") for k in ("ukf_nees_pos", "ukf_nees_vel", "ukf_nees_att")) \
            if "ukf_nees_pos" in f else ""
        md.append("| %s | %d | %s |" % (P["name"] or str(P["point"]), P["stored"], " | ".join([
            cell(f, "rn_m"), cell(f, "re_m"), cell(f, "rd_m"), cell(f, "rms2h_rn_m"), cell(f, "rms2h_re_m"),
            cell(f, "rms2h_rd_m"), cell(f, "hmean_m"), cell(f, "unaided_rn"), cell(f, "unaided_re"),
            cell(f, "unaided_rd"), cell(f, "unaided_hmean_m"), nees, mean(f, "ukf_nis", "%.2f"), mean(f, "pf_err_over_spread_sq", "%.2f")])))
    return md
