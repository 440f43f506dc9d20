"""The per-aid report of a random-routes campaign ([routes]): routes.json, routes.md (also at
the end of summary.md) and routes_ratio.png.

Per flight (a stored run), from the fields of its summary.json kept in the run's record
(tools.py: status, degraded_reasons, aids, unaided_reference, errors.position_error_m):
  aided    errors.position_error_m.final (the flight's final |position error|, m)
  unaided  unaided_reference.position_error_m.final (the same frames with every aid off), else
           the norm of unaided_reference.position_error_final_m
  aids     the names in the aids list ("aid_ukf" the map UKF, "aid_pf" the particle filter);
           flights are grouped by the set of aids they flew
  flagged  status == "degraded", or any aid's integrity.flagged is true (the integrity
           monitor); a missing field counts as not flagged
Per aid group:
  better   the share of flights with aided < unaided (flights with both errors known)
  ratio    aided / unaided: quantiles (linear interpolation between order statistics), the
           geometric mean, and the distribution of log10 ratio (routes_ratio.png)
  goal     on every flight the aid is better than unaided OR the flight is flagged; a
           violation is a flight that is worse (aided >= unaided) and not flagged
  NEES/NIS the map UKF's nis_mean (6 dof) and nees.position/velocity/attitude (3 dof): their
           median and mean over the flights and the share of flights inside each flight's own
           95 % band (nis_band95, nees.band95); the particle filter's (err/spread)^2 (1 =
           consistent)
  flagged  every flagged flight: seed, status, reasons, each aid's integrity state and events
"""
import json
import math
import os

QUANTILES = (0.0, 0.05, 0.25, 0.5, 0.75, 0.95, 1.0)


def _get(d, *path):
    for p in path:
        if isinstance(d, dict) and p in d:
            d = d[p]
        elif isinstance(d, list) and isinstance(p, int) and -len(d) <= p < len(d):
            d = d[p]
        else:
            return None
    return d


def _num(v):
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def quantile(sorted_vals, q):
    """Linear interpolation between order statistics (numpy's default, 'linear')."""
    n = len(sorted_vals)
    if n == 0:
        return None
    x = q * (n - 1)
    i = int(math.floor(x))
    if i >= n - 1:
        return sorted_vals[-1]
    return sorted_vals[i] + (sorted_vals[i + 1] - sorted_vals[i]) * (x - i)


def flight_of(meta):
    """One flight's record for the report from a stored run's meta (defensive: missing = None)."""
    s = meta.get("summary") or {}
    fin = meta.get("final") or {}
    aided = _num(_get(s, "position_error_m", "final"))
    if aided is None and all(k in fin for k in ("rn_m", "re_m", "rd_m")):
        aided = math.sqrt(fin["rn_m"] ** 2 + fin["re_m"] ** 2 + fin["rd_m"] ** 2)
    ur = s.get("unaided_reference") if isinstance(s.get("unaided_reference"), dict) else {}
    unaided = _num(_get(ur, "position_error_m", "final"))
    if unaided is None:
        v = [_num(_get(ur, "position_error_final_m", k)) for k in ("n", "e", "d")]
        if all(x is not None for x in v):
            unaided = math.sqrt(sum(x * x for x in v))
    if unaided is None and all(k in fin for k in ("unaided_rn", "unaided_re", "unaided_rd")):
        unaided = math.sqrt(fin["unaided_rn"] ** 2 + fin["unaided_re"] ** 2 + fin["unaided_rd"] ** 2)
    aids = [a for a in (s.get("aids") or []) if isinstance(a, dict)]
    names = [str(a.get("name", "aid%d" % i)) for i, a in enumerate(aids)]
    status = s.get("status") if isinstance(s.get("status"), str) else None
    reasons = [str(x) for x in s.get("degraded_reasons") or []] if isinstance(s.get("degraded_reasons"), list) else []
    integ = {}
    for n, a in zip(names, aids):
        it = a.get("integrity")
        if isinstance(it, dict):
            ev = it.get("events") if isinstance(it.get("events"), list) else []
            integ[n] = {"state_final": it.get("state_final"), "flagged": it.get("flagged") is True,
                        "suspect_s": _num(it.get("suspect_s")), "isolated_s": _num(it.get("isolated_s")),
                        "events": [e for e in ev if isinstance(e, dict)]}
    flagged = status == "degraded" or any(v["flagged"] for v in integ.values())
    ratio = aided / unaided if aided is not None and unaided is not None and unaided > 0 else None
    return {"seed": meta.get("seed"), "run_id": meta.get("run_id"), "point": meta.get("point"),
            "aids": names, "group": "+".join(names) if names else "(no aid)", "aided_m": aided,
            "unaided_m": unaided, "ratio": ratio,
            "better": (aided < unaided) if aided is not None and unaided is not None else None,
            "status": status, "degraded_reasons": reasons, "integrity": integ, "flagged": flagged,
            "aid_blocks": {n: a for n, a in zip(names, aids)}, "route": meta.get("route")}


def _dist(vals):
    v = sorted(x for x in vals if x is not None)
    if not v:
        return {"n": 0}
    return {"n": len(v), "mean": sum(v) / len(v), "median": quantile(v, 0.5), "min": v[0], "max": v[-1]}


def _in_band(x, band):
    if x is None or not isinstance(band, list) or len(band) != 2:
        return None
    lo, hi = _num(band[0]), _num(band[1])
    if lo is None or hi is None:
        return None
    return lo <= x <= hi


def _share(flags):
    f = [x for x in flags if x is not None]
    return {"n": len(f), "in": sum(1 for x in f if x), "share": (sum(1 for x in f if x) / len(f)) if f else None}


def aggregate(flights):
    """routes.json's content from the flights (flight_of)."""
    groups = {}
    for f in flights:
        groups.setdefault(f["group"], []).append(f)
    out = {"flights": len(flights), "groups": {}}
    for g, fs in sorted(groups.items()):
        known = [f for f in fs if f["better"] is not None]
        better = [f for f in known if f["better"]]
        flagged = [f for f in fs if f["flagged"]]
        viol = [f for f in known if not f["better"] and not f["flagged"]]
        ratios = sorted(f["ratio"] for f in fs if f["ratio"] is not None)
        lr = [math.log10(r) for r in ratios if r > 0]
        G = {"flights": len(fs), "known": len(known), "unknown": len(fs) - len(known),
             "better": len(better), "better_share": len(better) / len(known) if known else None,
             "flagged": len(flagged), "worse_flagged": sum(1 for f in known if not f["better"] and f["flagged"]),
             "violations": len(viol),
             "goal_met": len(viol) == 0 and len(known) == len(fs),
             "ratio_quantiles": {("q%g" % (100 * q)): quantile(ratios, q) for q in QUANTILES} if ratios else {},
             "ratio_geomean": 10 ** (sum(lr) / len(lr)) if lr else None,
             "log10_ratio": lr,
             "aided_m": _dist(f["aided_m"] for f in fs), "unaided_m": _dist(f["unaided_m"] for f in fs),
             "violation_list": [_brief(f) for f in sorted(viol, key=lambda f: -(f["ratio"] or 0))],
             "flagged_list": [_brief(f) for f in sorted(flagged, key=lambda f: f["seed"] or 0)],
             "unknown_list": [_brief(f) for f in fs if f["better"] is None],
             "consistency": {}}
        for name in sorted({n for f in fs for n in f["aids"]}):
            blocks = [f["aid_blocks"].get(name) or {} for f in fs]
            c = {}
            if name == "aid_ukf":
                nis = [_num(b.get("nis_mean")) for b in blocks]
                c["nis_mean"] = _dist(nis)
                c["nis_in_band95"] = _share(_in_band(x, b.get("nis_band95")) for x, b in zip(nis, blocks))
                for k in ("position", "velocity", "attitude"):
                    v = [_num(_get(b, "nees", k)) for b in blocks]
                    c["nees_" + k] = _dist(v)
                    c["nees_%s_in_band95" % k] = _share(_in_band(x, _get(b, "nees", "band95")) for x, b in zip(v, blocks))
            elif name == "aid_pf":
                c["err_over_spread_sq"] = _dist(_num(b.get("err_over_spread_sq_mean")) for b in blocks)
                c["estimate_error_mean_m"] = _dist(_num(b.get("estimate_error_mean_m")) for b in blocks)
                c["map_miss"] = _dist(_num(b.get("map_miss")) for b in blocks)
            st = {}
            for f in fs:
                s = (f["integrity"].get(name) or {}).get("state_final") or "unknown"
                st[s] = st.get(s, 0) + 1
            c["integrity_state_final"] = st
            G["consistency"][name] = c
        out["groups"][g] = G
    return out


def _brief(f):
    r = f.get("route") or {}
    return {"seed": f["seed"], "run_id": f["run_id"], "group": f["group"], "aided_m": f["aided_m"], "unaided_m": f["unaided_m"],
            "ratio": f["ratio"], "better": f["better"], "flagged": f["flagged"], "status": f["status"],
            "degraded_reasons": f["degraded_reasons"],
            "integrity": {n: {k: v for k, v in it.items() if k != "events"} | {
                "events": len(it["events"]), "first": (it["events"][0] if it["events"] else None)}
                for n, it in f["integrity"].items()},
            "flight_time_s": r.get("flight_time_s"), "legs": r.get("legs")}


def _f(x, fmt="%.3g"):
    return fmt % x if isinstance(x, (int, float)) and not isinstance(x, bool) else "–"


def markdown(R):
    md = ["## Random routes: per aid against the unaided solution", ""]
    if not R["groups"]:
        return md + ["(no stored flight)"]
    md += ["Goal: on every flight the aid is better than unaided (final |position error|) **or** the "
           "flight is flagged by the integrity monitor (status degraded, or an aid's integrity.flagged).", ""]
    md += ["| aid | flights | **violations** (worse, not flagged) | better than unaided | flagged | worse but flagged "
           "| unknown | ratio aided/unaided: min / 5 % / 25 % / median / 75 % / 95 % / max | geometric mean |",
           "|---|---|---|---|---|---|---|---|---|"]
    for g, G in R["groups"].items():
        q = G["ratio_quantiles"]
        qs = " / ".join(_f(q.get("q%g" % (100 * x))) for x in QUANTILES) if q else "–"
        md.append("| %s | %d | **%d**%s | %d of %d (%s) | %d | %d | %d | %s | %s |" % (
            g, G["flights"], G["violations"], " (goal met)" if G["goal_met"] else "", G["better"], G["known"],
            _f(100 * G["better_share"], "%.0f %%") if G["better_share"] is not None else "–", G["flagged"],
            G["worse_flagged"], G["unknown"], qs, _f(G["ratio_geomean"])))
    md += ["", "Final |position error| over the flights (m): aided / unaided median (mean)", ""]
    for g, G in R["groups"].items():
        md.append("- %s: aided %s (%s), unaided %s (%s)" % (g, _f(G["aided_m"].get("median")), _f(G["aided_m"].get("mean")),
                                                           _f(G["unaided_m"].get("median")), _f(G["unaided_m"].get("mean"))))
    md += ["", "Consistency (over the flights: median (mean); in band: flights inside their own 95 % band)", ""]
    for g, G in R["groups"].items():
        for name, c in G["consistency"].items():
            if name == "aid_ukf":
                parts = ["NIS (6 dof) %s (%s), in band %s/%s" % (_f(c["nis_mean"].get("median")), _f(c["nis_mean"].get("mean")),
                                                                 c["nis_in_band95"]["in"], c["nis_in_band95"]["n"])]
                for k in ("position", "velocity", "attitude"):
                    d, b = c["nees_" + k], c["nees_%s_in_band95" % k]
                    parts.append("NEES %s (3) %s (%s), in band %s/%s" % (k, _f(d.get("median")), _f(d.get("mean")), b["in"], b["n"]))
            elif name == "aid_pf":
                parts = ["(err/spread)^2 %s (%s) (1 = consistent)" % (_f(c["err_over_spread_sq"].get("median")),
                                                                      _f(c["err_over_spread_sq"].get("mean"))),
                         "estimate error %s m (%s)" % (_f(c["estimate_error_mean_m"].get("median")),
                                                       _f(c["estimate_error_mean_m"].get("mean"))),
                         "map misses %s (%s)" % (_f(c["map_miss"].get("median")), _f(c["map_miss"].get("mean")))]
            else:
                parts = []
            st = ", ".join("%s %d" % kv for kv in sorted(c["integrity_state_final"].items()))
            md.append("- %s: %s; integrity state at the end: %s" % (g if g == name else "%s, %s" % (g, name),
                                                                   "; ".join(parts) or "–", st))
    for g, G in R["groups"].items():
        md += ["", "### %s: violations (worse than unaided, not flagged): %d" % (g, G["violations"]), ""]
        if G["violation_list"]:
            md += ["| seed | aided m | unaided m | ratio | flight s | legs | run |", "|---|---|---|---|---|---|---|"]
            for f in G["violation_list"]:
                md.append("| %s | %s | %s | %s | %s | %s | %s |" % (f["seed"], _f(f["aided_m"]), _f(f["unaided_m"]),
                                                                   _f(f["ratio"]), _f(f["flight_time_s"], "%.0f"),
                                                                   f["legs"], f["run_id"]))
        md += ["", "### %s: flights flagged by the integrity monitor: %d" % (g, G["flagged"]), ""]
        if G["flagged_list"]:
            md += ["| seed | status | reasons | aid: state at end, suspect s, isolated s, events (first) | aided m | "
                   "unaided m | ratio | run |", "|---|---|---|---|---|---|---|---|"]
            for f in G["flagged_list"]:
                it = "; ".join("%s: %s, %s, %s, %d%s" % (
                    n, v.get("state_final"), _f(v.get("suspect_s"), "%.0f"), _f(v.get("isolated_s"), "%.0f"), v["events"],
                    (" (t %s %s: %s)" % (_f(_get(v, "first", "t_s"), "%.0f"), _get(v, "first", "state"),
                                         _get(v, "first", "why"))) if v.get("first") else "")
                    for n, v in f["integrity"].items()) or "–"
                md.append("| %s | %s | %s | %s | %s | %s | %s | %s |" % (
                    f["seed"], f["status"] or "–", ", ".join(f["degraded_reasons"]) or "–", it, _f(f["aided_m"]),
                    _f(f["unaided_m"]), _f(f["ratio"]), f["run_id"]))
        if G["unknown_list"]:
            md += ["", "%s: %d flight(s) without both errors (summary.json fields missing): seeds %s"
                   % (g, len(G["unknown_list"]), ", ".join(str(f["seed"]) for f in G["unknown_list"]))]
    return md


def write(out, metas):
    """routes.json and routes.md in `out` from the stored runs' metas; returns (report, markdown lines)."""
    flights = [flight_of(m) for m in metas]
    R = aggregate(flights)
    R["flight_list"] = [_brief(f) for f in flights]
    with open(os.path.join(out, "routes.json"), "w") as f:
        json.dump(R, f, indent=1)
    md = markdown(R)
    with open(os.path.join(out, "routes.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    return R, md
