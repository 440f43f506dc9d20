"""Driver of scripts/papers/rw-compare (see there)."""
import argparse, csv, datetime, json, math, os, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# (key, label, scenario file, survey overrides or None)
RUNS = [
    ("a", "(a) conventional, normal model", "rw-compare-model", None),
    ("b", "(b) conventional + survey grid (2 km, 1 mGal / 0.5\")", "rw-compare-survey", None),
    ("b0", "(b') survey grid without noise (2 km)", "rw-compare-survey",
     {"noise_gravity_mgal": 0.0, "noise_deflection_arcsec": 0.0}),
    ("b5", "(b'') survey grid 5 km, 1 mGal / 0.5\"", "rw-compare-survey", {"spacing_m": 5000.0}),
    ("c", "(c) gradiometer", "rw-compare-gradiometer", None),
]


def scenario_text(name, overrides):
    text = open(os.path.join(ROOT, "scenarios", name + ".toml")).read()
    if not overrides:
        return text
    out = []
    in_survey = False
    for line in text.splitlines():
        s = line.strip()
        if s.startswith("["):
            in_survey = s == "[navigation.survey]"
        key = s.split("=")[0].strip() if "=" in s else None
        if in_survey and key in overrides:
            line = "%s = %r" % (key, overrides[key])
        out.append(line)
    return "\n".join(out) + "\n"


def metrics(folder):
    rows = list(csv.DictReader(open(os.path.join(folder, "timeseries.csv"))))
    f = lambda r, k: float(r[k])
    last = rows[-1]
    vert = [abs(f(r, "err_h_m")) for r in rows if f(r, "t_s") >= 600.0]
    gpl = [math.hypot(f(r, "err_g_x_mps2"), f(r, "err_g_z_mps2")) for r in rows]
    summ = json.load(open(os.path.join(folder, "summary.json")))
    return {
        "along_track_final_m": f(last, "err_along_m"),
        "along_track_max_abs_m": max(abs(f(r, "err_along_m")) for r in rows),
        "vertical_max_abs_after_600s_m": max(vert),
        "gravitation_in_plane_final_mps2": gpl[-1],
        "gravitation_in_plane_rms_mps2": math.sqrt(sum(x * x for x in gpl) / len(gpl)),
        "position_error_final_m": summ["errors"]["position_error_m"]["final"],
        "survey_grid": summ.get("survey_grid"),
        "t": [f(r, "t_s") for r in rows],
        "along": [f(r, "err_along_m") for r in rows],
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "bin"))
    ap.add_argument("--out", default=None)
    ap.add_argument("--only", default="a,b,b0,b5,c")
    ap.add_argument("--survey-seeds", type=int, default=5,
                    help="fly (b) with this many survey-noise seeds (11, 12, ...) for its spread")
    ap.add_argument("--reuse", action="store_true", help="do not re-fly runs whose folder already has a summary.json")
    a = ap.parse_args()
    out = a.out or os.path.join("out", "rw-compare-" + datetime.datetime.utcnow().strftime("%Y%m%dT%H%M%SZ"))
    os.makedirs(out, exist_ok=True)
    keys = a.only.split(",")
    res = {}
    runs = list(RUNS)
    if "b" in keys:
        for seed in range(12, 11 + a.survey_seeds):
            runs.append(("b_s%d" % seed, "(b) survey-noise seed %d" % seed, "rw-compare-survey", {"seed": seed}))
            keys.append("b_s%d" % seed)
    for key, label, scen, ov in runs:
        if key not in keys:
            continue
        folder = os.path.join(out, key)
        toml = os.path.join(out, key + ".toml")
        open(toml, "w").write(scenario_text(scen, ov))
        cmd = [os.path.join(a.bin, "ggins"), "run", "-s", toml, "--no-log", "-o", folder]
        rc = 0
        if not (a.reuse and os.path.exists(os.path.join(folder, "summary.json"))):
            print("rw-compare:", " ".join(cmd), flush=True)
            with open(os.path.join(out, key + ".log"), "w") as log:
                rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT)
        if rc != 0:
            sys.exit("rw-compare: run %s failed (rc %d), see %s.log" % (key, rc, os.path.join(out, key)))
        m = metrics(folder)
        m["label"] = label
        m["scenario"] = scen
        m["overrides"] = ov
        res[key] = m
    seeds = {k: m for k, m in res.items() if k == "b" or k.startswith("b_s")}
    res = {k: m for k, m in res.items() if not k.startswith("b_s")}
    lines = ["| at 1 h | " + " | ".join(res[k]["label"] for k in res) + " |",
             "|---|" + "---|" * len(res)]
    def row(name, k, fmt):
        lines.append("| %s | " % name + " | ".join(fmt % abs(res[x][k]) for x in res) + " |")
    row("along-track position error, final (m)", "along_track_final_m", "%.2f")
    row("along-track position error, max over the hour (m)", "along_track_max_abs_m", "%.2f")
    row("vertical error, max after 600 s (m)", "vertical_max_abs_after_600s_m", "%.2f")
    row("in-plane gravitation error, final (m/s^2)", "gravitation_in_plane_final_mps2", "%.2e")
    row("in-plane gravitation error, rms over the hour (m/s^2)", "gravitation_in_plane_rms_mps2", "%.2e")
    table = "\n".join(lines) + "\n"
    if len(seeds) > 1:
        fin = [m["along_track_final_m"] for m in seeds.values()]
        mx = [m["along_track_max_abs_m"] for m in seeds.values()]
        rms = lambda v: math.sqrt(sum(x * x for x in v) / len(v))
        table += ("\n(b) over %d survey-noise seeds (%s): along-track error at 1 h rms %.2f m (values %s m); "
                  "max over the hour rms %.2f m\n" % (len(fin), ", ".join(str(11 + i) for i in range(len(fin))), rms(fin),
                                                       ", ".join("%.2f" % x for x in fin), rms(mx)))
        res_seeds = {"finals_m": fin, "max_m": mx, "rms_final_m": rms(fin), "rms_max_m": rms(mx)}
    else:
        res_seeds = None
    open(os.path.join(out, "table.md"), "w").write(table)
    tj = {k: {x: v for x, v in m.items() if x not in ("t", "along")} for k, m in res.items()}
    tj["b_survey_seeds"] = res_seeds
    json.dump(tj, open(os.path.join(out, "table.json"), "w"), indent=2)
    print(table)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(11, 4.8))
        for k, m in res.items():
            ax.semilogy([t / 60 for t in m["t"]], [max(abs(x), 1e-3) for x in m["along"]], label=m["label"])
        ax.set_xlabel("time (min)")
        ax.set_ylabel("|along-track position error| (m)")
        ax.set_title("Rubenstein & Winter anomaly field, 100 m/s at 3 km, perfect accelerometers")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        fig.tight_layout()
        fig.savefig(os.path.join(out, "comparison.png"), dpi=110)
    except ImportError:
        print("rw-compare: matplotlib missing, no plot")
    print("rw-compare: report in", out)


if __name__ == "__main__":
    main()
