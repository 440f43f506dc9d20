"""Markdown table (Gao Tables 3-9 style) from scripts/papers/mapnav-sweeps output folders."""
import json, math, pathlib, sys

out = pathlib.Path(sys.argv[1])
fmt = lambda v, f: "-" if v is None else format(v, f)  # a mean over no sample is null
cols = ["pitch_arcmin", "roll_arcmin", "yaw_arcmin", "vE_mps", "vN_mps", "vU_mps", "lat_m", "lon_m", "h_m"]
print("| run | pitch' | roll' | yaw' | vE | vN | vU | v3D | lat m | lon m | h m | p3D m | NEES/15 | NIS/6 |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
order = ["base"] + sorted(p.name for p in out.iterdir() if p.is_dir() and p.name != "base")
for name in order:
    f = out / name / "summary.json"
    if not f.exists():
        continue
    j = json.loads(f.read_text())["ensemble"]["results"]  # the report's mapnav statistics
    r = j["ggan_rms_last2h"]
    m = {c: r[c]["mean_abs"] for c in cols}
    s = {c: r[c]["sd"] for c in cols}
    v3 = math.sqrt(m["vE_mps"] ** 2 + m["vN_mps"] ** 2 + m["vU_mps"] ** 2)
    p3 = math.sqrt(m["lat_m"] ** 2 + m["lon_m"] ** 2 + m["h_m"] ** 2)
    cells = [f"{m[c]:.3g} ± {s[c]:.2g}" for c in cols]
    print(f"| {name} | " + " | ".join(cells[:6]) + f" | {v3:.3g} | " + " | ".join(cells[6:]) +
          f" | {p3:.3g} | {fmt(j['nees_mean'], '.1f')} | {fmt(j['nis_mean'], '.2f')} |")
