"""Random routes ([routes], routes.py) against independent checks: the draw is a pure function
of the seed; every waypoint, every leg (points along its great circle) and every height lies in
the region; leg lengths, turn angles, climbs, speeds and the flight time lie in their ranges,
the geometry recomputed here on a sphere (haversine, spherical bearings: within 0.6 % / 1 deg of
the WGS-84 great ellipse the route is built on); a region across the antimeridian; every drawn
route accepted by ggins-run3d (--print-scenario: route3d.hpp's rules), and flown: the truth at
the computed flight time is at the last waypoint.
usage: test_routes.py <bin dir>"""
import csv
import json
import math
import os
import shutil
import subprocess
import tempfile
import tomllib

import util
from util import Checks

from ggins_campaign import routes, spec, tomlw

C = Checks("campaign.routes")
tmp = tempfile.mkdtemp(prefix="ggins-campaign-routes-")
R_SPHERE = 6371008.8
RUN3D = os.path.join(util.BIN, "ggins-run3d")


def hav(la1, lo1, la2, lo2):
    p1, p2, dl = math.radians(la1), math.radians(la2), math.radians(lo2 - lo1)
    a = math.sin((p2 - p1) / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * R_SPHERE * math.asin(math.sqrt(a))


def bearing(la1, lo1, la2, lo2):
    p1, p2, dl = math.radians(la1), math.radians(la2), math.radians(lo2 - lo1)
    return math.degrees(math.atan2(math.sin(dl) * math.cos(p2),
                                   math.cos(p1) * math.sin(p2) - math.sin(p1) * math.cos(p2) * math.cos(dl)))


def slerp_points(la1, lo1, la2, lo2, n=20):
    def v(la, lo):
        la, lo = math.radians(la), math.radians(lo)
        return (math.cos(la) * math.cos(lo), math.cos(la) * math.sin(lo), math.sin(la))
    a, b = v(la1, lo1), v(la2, lo2)
    om = math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b)))))
    out = []
    for k in range(n + 1):
        t = k / n
        s1, s2 = math.sin((1 - t) * om) / math.sin(om), math.sin(t * om) / math.sin(om)
        p = [s1 * x + s2 * y for x, y in zip(a, b)]
        out.append((math.degrees(math.asin(p[2])), math.degrees(math.atan2(p[1], p[0]))))
    return out


def in_lon(lon, lo, hi):
    """lon in the band from lo eastwards to hi (lo > hi: across the antimeridian), with 0.05 deg slack."""
    w = (hi - lo) % 360.0
    return ((lon - lo + 0.05) % 360.0) <= w + 0.1


def check_route(r, t, lat_rng, lon_rng, tag, lv_tol):
    """Every constraint of table t on route r, recomputed independently; returns the failures."""
    bad = []
    pts = [(r.start["lat_deg"], r.start["lon_deg"])] + [(w["lat_deg"], w["lon_deg"]) for w in r.waypoints]
    hs = [r.start["height_m"]] + [w["height_m"] for w in r.waypoints]
    n = len(r.waypoints)
    if not t["legs"][0] <= n <= t["legs"][1]:
        bad.append("legs %d" % n)
    for k, (la, lo) in enumerate(pts):
        if not (lat_rng[0] - 1e-9 <= la <= lat_rng[1] + 1e-9 and in_lon(lo, *lon_rng) and abs(lo) <= 360.0):
            bad.append("waypoint %d outside (%.3f, %.3f)" % (k, la, lo))
    for k in range(n):
        for la, lo in slerp_points(*pts[k], *pts[k + 1]):
            if not (lat_rng[0] - 0.05 <= la <= lat_rng[1] + 0.05 and in_lon(lo, *lon_rng)):
                bad.append("leg %d leaves the region at (%.3f, %.3f)" % (k + 1, la, lo))
                break
        L = hav(*pts[k], *pts[k + 1])
        if not 0.994 * 1e3 * t["leg_km"][0] <= L <= 1.006 * 1e3 * t["leg_km"][1]:
            bad.append("leg %d: %.1f km" % (k + 1, L / 1e3))
        if abs(L - r.timing["leg_length_m"][k]) > 0.006 * L:
            bad.append("leg %d: sphere %.1f km, ellipse %.1f km" % (k + 1, L / 1e3, r.timing["leg_length_m"][k] / 1e3))
        v = r.waypoints[k]["speed_mps"]
        if not t["speed_mps"][0] <= v <= t["speed_mps"][1]:
            bad.append("leg %d speed %.1f" % (k + 1, v))
    for k in range(1, n):
        arr = bearing(*pts[k], *pts[k - 1]) + 180.0  # the arrival track: the reverse of the bearing back
        dep = bearing(*pts[k], *pts[k + 1])
        turn = (dep - arr + 180.0) % 360.0 - 180.0
        if not t["heading_change_deg"][0] - 1.0 <= abs(turn) <= t["heading_change_deg"][1] + 1.0:
            bad.append("turn %d: %.2f deg" % (k, turn))
        if abs(abs(turn) - abs(r.timing["turn_deg"][k])) > 1.0:
            bad.append("turn %d: sphere %.2f, ellipse %.2f" % (k, turn, r.timing["turn_deg"][k]))
    if not t["start_height_m"][0] <= hs[0] <= t["start_height_m"][1]:
        bad.append("start height %.0f" % hs[0])
    for k in range(n):
        if not t["height_m"][0] <= hs[k + 1] <= t["height_m"][1]:
            bad.append("height %d %.0f" % (k + 1, hs[k + 1]))
        dh = abs(hs[k + 1] - hs[k])
        if dh != 0 and not t["climb_m"][0] - 1e-6 <= dh <= t["climb_m"][1] + 1e-6:
            bad.append("climb %d %.0f m" % (k + 1, dh))
    T = r.flight_time_s
    if not t["duration_s"][0] <= T <= t["duration_s"][1] or r.duration_s != math.ceil(T):
        bad.append("flight time %.1f s, duration %.1f s" % (T, r.duration_s))
    est = sum(hav(*pts[k], *pts[k + 1]) / r.waypoints[k]["speed_mps"] for k in range(n))
    if lv_tol is not None and abs(est - T) > lv_tol * T:  # (sum L/v leaves out the turns' corner cuts and the speed steps' lag)
        bad.append("flight time %.0f s against sum L/v %.0f s" % (T, est))
    return bad


TABLE = {"lat_deg": [45.0, 62.0], "lon_deg": [-5.0, 25.0], "start_height_m": [3000.0, 9000.0],
         "height_m": [1000.0, 12000.0], "legs": [3, 7], "leg_km": [80.0, 400.0], "heading_change_deg": [20.0, 120.0],
         "climb_m": [1000.0, 5000.0], "climb_rate_mps": [5.0, 15.0], "speed_mps": [150.0, 250.0],
         "duration_s": [3600.0, 7200.0]}
# tight turns on short legs with speed changes: route3d's rules near their limits
STRESS = {"lat_deg": [60.0, 70.0], "lon_deg": [100.0, 130.0], "height_m": [500.0, 12000.0], "legs": [4, 9],
          "leg_km": [20.0, 80.0], "heading_change_deg": [90.0, 148.0], "climb_m": [300.0, 3000.0],
          "climb_rate_mps": [10.0, 30.0], "speed_mps": [80.0, 300.0], "duration_s": [900.0, 1800.0],
          "accel_mps2": 2.0, "vertical_accel_mps2": 2.0, "turn_rate_dps": 3.0, "level_fraction": 0.2}
# across the antimeridian: 170 E eastwards to 170 W
DATELINE = {"lat_deg": [50.0, 60.0], "lon_deg": [170.0, -170.0], "height_m": [2000.0, 10000.0], "legs": [2, 5],
            "leg_km": [50.0, 200.0], "heading_change_deg": [10.0, 90.0], "climb_m": [1000.0, 3000.0],
            "climb_rate_mps": [10.0, 20.0], "speed_mps": [150.0, 250.0], "duration_s": [1800.0, 3600.0]}


def print_ok(sc):
    path = os.path.join(tmp, "s.toml")
    with open(path, "w") as f:
        f.write(tomlw.dumps(sc))
    p = subprocess.run([RUN3D, "-s", path, "--print-scenario"], capture_output=True, text=True)
    return p.returncode == 0, p.stderr.strip()[-400:]


try:
    base = tomllib.loads(subprocess.run([RUN3D, "-s", os.path.join(util.SRC, "scenarios", "3d-route-45n.toml"),
                                         "--print-scenario"], capture_output=True, text=True, check=True).stdout)

    # determinism: a pure function of the seed (and the table)
    s = routes.RouteSpec(TABLE)
    a, b = routes.draw(s, 7), routes.draw(routes.RouteSpec(dict(TABLE)), 7)
    C.ok(a.info() == b.info() and a.waypoints == b.waypoints, "the same seed draws the same route")
    C.ok(routes.draw(s, 8).waypoints != a.waypoints, "another seed draws another route")
    sa = tomlw.dumps(a.apply(json.loads(json.dumps(base))))
    C.ok(sa == tomlw.dumps(b.apply(json.loads(json.dumps(base)))), "the same scenario text from the same seed")
    C.ok(routes.draw(routes.RouteSpec(dict(TABLE, seed_offset=7)), 7).waypoints != a.waypoints,
         "seed_offset changes the draw")
    sc = tomllib.loads(sa)
    C.ok(sc["trajectory"]["type"] == "route" and len(sc["trajectory"]["waypoint"]) == len(a.waypoints)
         and sc["time"]["duration_s"] == a.duration_s and sc["trajectory"]["lat_deg"] == a.start["lat_deg"],
         "the scenario: type route, the start, the waypoints and time.duration_s = the flight time")

    # the constraints, recomputed on a sphere, and route3d's acceptance
    for name, t, seeds, lv_tol in (("europe", TABLE, range(1, 61), 0.05), ("stress", STRESS, range(1, 41), None),
                                   ("antimeridian", DATELINE, range(1, 41), 0.15)):
        st = routes.RouteSpec(t)
        full = dict(t)
        full.setdefault("start_height_m", t["height_m"])
        full.setdefault("climb_m", [0.0, 0.0])
        bad, refused, crossed = [], [], 0
        for seed in seeds:
            r = routes.draw(st, seed)
            bad += ["seed %d: %s" % (seed, x) for x in check_route(r, full, t["lat_deg"], t["lon_deg"], name, lv_tol)]
            ok, err = print_ok(r.apply(json.loads(json.dumps(base))))
            if not ok:
                refused.append("seed %d: %s" % (seed, err))
            lons = [r.start["lon_deg"]] + [w["lon_deg"] for w in r.waypoints]
            crossed += any(abs(x) > 180.0 for x in lons) or (min(lons) < 0 < max(lons) and max(lons) > 90)
        C.ok(not bad, "%s: %d routes within every range (region, legs, turns, heights, climbs, speeds, duration)%s"
             % (name, len(seeds), "" if not bad else ": " + "; ".join(bad[:5])))
        C.ok(not refused, "%s: ggins-run3d accepts all %d routes%s" % (name, len(seeds),
                                                                          "" if not refused else ": " + "; ".join(refused[:3])))
        if name == "antimeridian":
            C.ok(crossed > 0, "antimeridian: %d of %d routes cross 180 deg" % (crossed, len(seeds)))
    # longitudes given in [-360, 360]: [-190, -170] is the band 170 E .. 170 W
    s1, s2 = routes.RouteSpec(dict(DATELINE, lon_deg=[-190.0, -170.0])), routes.RouteSpec(DATELINE)
    C.ok(abs(s1.lon_min - s2.lon_min) < 1e-12 and abs(s1.lon_width - s2.lon_width) < 1e-12 and s2.lon_width == 20.0,
         "lon_deg [-190, -170] = [170, -170]: 20 deg from 170 E")
    for badt, what in ((dict(TABLE, legs=[1, 1], leg_km=[10.0, 20.0]), "no route lasts the duration"),
                       (dict(TABLE, heading_change_deg=[0.0, 170.0]), "turns beyond 148 deg"),
                       (dict(TABLE, lon_deg=[10.0, 10.0]), "an empty longitude band"),
                       (dict(TABLE, bogus=1), "an unknown key")):
        try:
            routes.RouteSpec(badt)
            C.ok(False, "refused: %s" % what)
        except routes.RouteSpecError as e:
            C.ok(True, "refused: %s (%s)" % (what, e))

    # flown: the truth at the computed flight time is at the last waypoint (route3d's timing:
    # turn curves, speed changes), normal gravity at 10 Hz for speed; the stress table's routes
    # whose flight time is farthest from sum L / v (tight turns cutting corners, speed steps)
    for seed in (1, 11, 13, 34):
        r = routes.draw(routes.RouteSpec(STRESS), seed)
        sc = r.apply(json.loads(json.dumps(base)))
        sc["gravity"]["model"] = "wgs84-normal"
        sc["time"]["rate_hz"] = 10.0
        sc["time"]["duration_s"] = r.duration_s + 10.0
        path = os.path.join(tmp, "fly.toml")
        with open(path, "w") as f:
            f.write(tomlw.dumps(sc))
        out = os.path.join(tmp, "fly")
        subprocess.run([RUN3D, "-s", path, "--direct", "--no-log", "--no-plots", "-q", "--csv-rate", "10", "--out", out],
                       check=True, capture_output=True)
        rows = [(float(q["t_s"]), float(q["lat_deg"]), float(q["lon_deg"]), float(q["h_m"]))
                for q in csv.DictReader(open(os.path.join(out, "timeseries.csv")))]
        T = r.flight_time_s
        i = max(k for k in range(len(rows)) if rows[k][0] <= T)
        w = (T - rows[i][0]) / (rows[i + 1][0] - rows[i][0])
        p = [rows[i][j] * (1 - w) + rows[i + 1][j] * w for j in (1, 2, 3)]
        last = r.waypoints[-1]
        d = math.dist(routes.ecef(*p), routes.ecef(last["lat_deg"], last["lon_deg"], last["height_m"]))
        C.ok(d < 2.0, "seed %d: flown, the truth at the flight time %.2f s is %.2f m from the last waypoint "
             "(%d legs, turns %s deg)" % (seed, T, d, len(r.waypoints), [round(x) for x in r.timing["turn_deg"][1:-1]]))

    # the campaign files: 50 seeds each, their routes recorded in the runs, run3d accepts them
    for cf in ("random-routes-mm.toml", "random-routes-pf.toml"):
        c = spec.Campaign(os.path.join(util.SRC, "campaigns", cf), source_dir=util.SRC, bin_dir=util.BIN)
        rs = c.runs()
        C.ok(c.seeds >= 50 and len(rs) == c.seeds, "%s: %d flights" % (cf, len(rs)))
        refused, outside = [], []
        for r in rs:
            text = r.task()["files"]["scenario.toml"]
            info = r.info()
            if info.get("scenario_toml") != text or info["route"]["seed"] != r.seed:
                outside.append("seed %d: route not recorded" % r.seed)
            t = r.route.info()
            if not 3600.0 <= t["flight_time_s"] <= 7200.0:
                outside.append("seed %d: %.0f s" % (r.seed, t["flight_time_s"]))
            path = os.path.join(tmp, "c.toml")
            with open(path, "w") as f:
                f.write(text)
            p = subprocess.run([RUN3D, "-s", path, "--print-scenario"], capture_output=True, text=True)
            if p.returncode != 0:
                refused.append("seed %d: %s" % (r.seed, p.stderr.strip()[-300:]))
        C.ok(not refused and not outside, "%s: every flight 1-2 h, recorded in its run, accepted by ggins-run3d%s"
             % (cf, "" if not (refused or outside) else ": " + "; ".join((refused + outside)[:3])))
        C.ok([r.run_id for r in spec.Campaign(os.path.join(util.SRC, "campaigns", cf), source_dir=util.SRC,
                                              bin_dir=util.BIN).runs()] == [r.run_id for r in rs],
             "%s: run ids stable across loads (the routes drawn again the same)" % cf)
        if cf.endswith("-pf.toml"):
            sc0 = tomllib.loads(rs[0].task()["files"]["scenario.toml"])
            C.ok(sc0["aid_pf"].get("map_from_field") is True and "map_dir" not in sc0["aid_pf"]
                 and sc0["aid_pf"]["map_margin_deg"] == spec.Campaign(
                     os.path.join(util.SRC, "campaigns", cf), source_dir=util.SRC, bin_dir=util.BIN).routes.pf_map_margin_deg,
                 "%s: the Gamma_zz tiles along the route built by the flight from the field "
                 "(aid_pf.map_from_field, the [routes] pf_map_* settings)" % cf)
    try:
        util.write(os.path.join(tmp, "r2d.toml"), '[campaign]\ncommand = "rw-eq8"\n[routes]\nlat_deg = [1.0, 2.0]\n')
        spec.Campaign(os.path.join(tmp, "r2d.toml"), source_dir=util.SRC, bin_dir=util.BIN)
        C.ok(False, "[routes] refused for a command other than run3d")
    except spec.SpecError:
        C.ok(True, "[routes] refused for a command other than run3d")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
C.done()
