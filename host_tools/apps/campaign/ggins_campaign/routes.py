"""Random routes: a campaign file's [routes] table draws each run's route from its seed.

  [routes]
  lat_deg = [45.0, 62.0]            # region: every waypoint (and every leg) inside this latitude band,
  lon_deg = [-5.0, 25.0]            # and this longitude band; lon_min > lon_max: across the antimeridian
                                    # (e.g. [170.0, -170.0]); each in [-360, 360]
  start_height_m = [3000.0, 9000.0] # the start's height
  height_m = [1000.0, 12000.0]      # every waypoint's height
  legs = [3, 7]                     # number of legs (integers, both included)
  leg_km = [80.0, 400.0]            # each leg's length (great ellipse between the waypoints' footprints)
  heading_change_deg = [20.0, 120.0]  # |turn| at each interior waypoint (sign drawn: left or right)
  climb_m = [1000.0, 5000.0]        # |height change| of a leg that climbs or descends
  level_fraction = 0.3              # the share of legs flown level
  speed_mps = [150.0, 250.0]        # each leg's ground speed
  duration_s = [3600.0, 7200.0]     # flight time to the last waypoint
  climb_rate_mps = [5.0, 15.0]      # each climbing leg's vertical rate
  turn_rate_dps = 3.0               # the route's turn rate, along-track and vertical accelerations
  accel_mps2 = 1.0
  vertical_accel_mps2 = 0.5
  seed_offset = 6                   # the draw's generator: random.Random(S + seed_offset)
  pf_map_spacing_deg = 0.05         # particle filter on [coldatom] gzz_map = "field": its Gamma_zz
  pf_map_margin_deg = 0.1           # tiles along the route (aid_pf.map_from_field; tools.py),
  pf_map_noise_E = 0.001            # their spacing, margin (overlap), database noise and seed
  pf_map_seed = 1
  attempts = 20000                  # draws tried before the seed is refused

Every number drawn is uniform in its range. Construction (a draw that breaks a rule is thrown
away and the next one drawn from the same generator, so the route is a pure function of the
seed and the table):
  1. the flight time T, the number of legs n, the leg speeds and raw leg lengths; the lengths
     scaled so that sum L_k / v_k = T (all must then lie in leg_km);
  2. the start (uniform in the region), its heading (uniform), then each leg's heading the
     arrival track of the leg before plus the turn (|turn| drawn, sign drawn; the other sign
     tried when the leg would leave the region); the leg's end by the direct problem on the
     WGS-84 ellipsoid's great ellipse (the section through the Earth's centre that route3d.hpp
     flies), points along the leg checked against the region;
  3. heights: a leg is level with probability level_fraction, else climbs or descends by |dh|
     in climb_m (the sign that stays in height_m), |dh| cut to what the leg's time allows at its
     climb rate (|dh| / rate + 40 tau_h within 80 % of it); a leg too short for climb_m's least
     change is flown level;
  4. the timing of route3d.hpp (turn curves' path lengths, the speed changes' softplus steps,
     the climbs' time windows) computed here; a route that would not fit is drawn again; the
     time at the last waypoint is the flight time (must lie in duration_s) and
     time.duration_s = that time rounded up to a whole second.

The run's scenario then holds [trajectory] type = "route" with the start and the
[[trajectory.waypoint]] entries (height_m, speed_mps, climb_rate_mps, accel_mps2,
vertical_accel_mps2, turn_rate_dps of each), so the stored scenario alone reproduces the run.
"""
import cmath
import math
import random

# WGS-84
A = 6378137.0
F = 1.0 / 298.257223563
B = A * (1.0 - F)
E2 = F * (2.0 - F)

KNOWN = {"lat_deg", "lon_deg", "start_height_m", "height_m", "legs", "leg_km", "heading_change_deg", "climb_m",
         "level_fraction", "speed_mps", "duration_s", "climb_rate_mps", "turn_rate_dps", "accel_mps2",
         "vertical_accel_mps2", "seed_offset", "attempts", "pf_map_spacing_deg", "pf_map_margin_deg",
         "pf_map_noise_E", "pf_map_seed"}

MAX_TURN_DEG = 150.0   # route3d.hpp: |turn| <= 150 deg
TURN_MARGIN_DEG = 2.0  # the drawn turns stay this far below it


class RouteSpecError(Exception):
    pass


def _range(d, key, lo=None, hi=None, default=None, integer=False, allow_swap=False):
    v = d.get(key, default)
    if v is None:
        raise RouteSpecError("[routes] %s is required (a range [min, max])" % key)
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        v = [v, v]
    if not (isinstance(v, list) and len(v) == 2 and all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                         for x in v)):
        raise RouteSpecError("[routes] %s must be a number or a range [min, max], not %r" % (key, v))
    if integer and not all(isinstance(x, int) or float(x).is_integer() for x in v):
        raise RouteSpecError("[routes] %s: integers" % key)
    a, b = (int(v[0]), int(v[1])) if integer else (float(v[0]), float(v[1]))
    if not all(math.isfinite(x) for x in (a, b)):
        raise RouteSpecError("[routes] %s: finite numbers" % key)
    if a > b and not allow_swap:
        raise RouteSpecError("[routes] %s: min %r > max %r" % (key, a, b))
    for x in (a, b):
        if (lo is not None and x < lo) or (hi is not None and x > hi):
            raise RouteSpecError("[routes] %s: %r outside [%r, %r]" % (key, x, lo, hi))
    return a, b


def _wrap180(lon):
    return (lon + 180.0) % 360.0 - 180.0


class RouteSpec:
    """The [routes] table, checked."""

    def __init__(self, d):
        if not isinstance(d, dict):
            raise RouteSpecError("[routes] must be a table")
        extra = set(d) - KNOWN
        if extra:
            raise RouteSpecError("[routes]: unknown key(s) %s (known: %s)" % (sorted(extra), sorted(KNOWN)))
        self.table = dict(d)
        self.lat = _range(d, "lat_deg", -80.0, 80.0)
        lon = _range(d, "lon_deg", -360.0, 360.0, allow_swap=True)
        self.lon_min = _wrap180(lon[0])
        w = (lon[1] - lon[0]) % 360.0
        if lon[1] - lon[0] >= 360.0:
            w = 360.0
        if w == 0.0:
            raise RouteSpecError("[routes] lon_deg: an empty longitude band %r" % (lon,))
        self.lon_width = w
        self.lon_given = lon
        self.height = _range(d, "height_m", -500.0, 30000.0)
        self.start_height = _range(d, "start_height_m", -500.0, 30000.0, default=list(self.height))
        if self.start_height[0] < self.height[0] or self.start_height[1] > self.height[1]:
            raise RouteSpecError("[routes] start_height_m must lie within height_m")
        self.legs = _range(d, "legs", 1, 200, integer=True)
        self.leg_m = tuple(1000.0 * x for x in _range(d, "leg_km", 1.0, 5000.0))
        self.turn = _range(d, "heading_change_deg", 0.0, MAX_TURN_DEG - TURN_MARGIN_DEG, default=[0.0, 90.0])
        self.climb = _range(d, "climb_m", 0.0, 30000.0, default=[0.0, 0.0])
        self.level_fraction = float(d.get("level_fraction", 0.3 if self.climb[1] > 0 else 1.0))
        if not 0.0 <= self.level_fraction <= 1.0:
            raise RouteSpecError("[routes] level_fraction must be in [0, 1]")
        self.speed = _range(d, "speed_mps", 1.0, 3000.0)
        self.duration = _range(d, "duration_s", 1.0, 1e7)
        self.climb_rate = _range(d, "climb_rate_mps", 0.01, 1000.0, default=[5.0, 5.0])
        self.turn_rate_dps = float(d.get("turn_rate_dps", 3.0))
        self.accel = float(d.get("accel_mps2", 1.0))
        self.vaccel = float(d.get("vertical_accel_mps2", 0.5))
        for k, v in (("turn_rate_dps", self.turn_rate_dps), ("accel_mps2", self.accel),
                     ("vertical_accel_mps2", self.vaccel)):
            if not (math.isfinite(v) and v > 0):
                raise RouteSpecError("[routes] %s must be > 0" % k)
        # the particle filter's Gamma_zz tiles along the route ([coldatom] gzz_map = "field"; tools.py)
        self.pf_map_spacing_deg = float(d.get("pf_map_spacing_deg", 0.05))
        self.pf_map_margin_deg = float(d.get("pf_map_margin_deg", 0.1))
        self.pf_map_noise_E = float(d.get("pf_map_noise_E", 0.001))
        self.pf_map_seed = int(d.get("pf_map_seed", 1))
        if not (0.001 <= self.pf_map_spacing_deg <= 1 and 2 * self.pf_map_spacing_deg <= self.pf_map_margin_deg
                < 49 * self.pf_map_spacing_deg - self.pf_map_spacing_deg and self.pf_map_noise_E >= 0):
            raise RouteSpecError("[routes] pf_map_spacing_deg in [0.001, 1], pf_map_margin_deg in "
                                 "[2 spacing, 48 spacing), pf_map_noise_E >= 0")
        self.seed_offset = int(d.get("seed_offset", 6))
        self.attempts = int(d.get("attempts", 20000))
        if self.attempts < 1:
            raise RouteSpecError("[routes] attempts must be >= 1")
        n0, n1 = self.legs
        if n1 * self.leg_m[1] / self.speed[0] < self.duration[0] or n0 * self.leg_m[0] / self.speed[1] > self.duration[1]:
            raise RouteSpecError("[routes]: no route of %d..%d legs of %g..%g km at %g..%g m/s lasts %g..%g s"
                                 % (n0, n1, self.leg_m[0] / 1e3, self.leg_m[1] / 1e3, self.speed[0], self.speed[1],
                                    self.duration[0], self.duration[1]))

    def lon_inside(self, lon):
        return ((lon - self.lon_min) % 360.0) <= self.lon_width + 1e-12

    def inside(self, lat, lon, h=None):
        return (self.lat[0] <= lat <= self.lat[1] and self.lon_inside(lon)
                and (h is None or self.height[0] <= h <= self.height[1]))


# ---- WGS-84 geometry: the great ellipse of route3d.hpp

def ecef(lat_deg, lon_deg, h=0.0):
    la, lo = math.radians(lat_deg), math.radians(lon_deg)
    N = A / math.sqrt(1.0 - E2 * math.sin(la) ** 2)
    return ((N + h) * math.cos(la) * math.cos(lo), (N + h) * math.cos(la) * math.sin(lo),
            (N * (1.0 - E2) + h) * math.sin(la))


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _unit(a):
    n = math.sqrt(_dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def _ned_axes(lat_deg, lon_deg):
    la, lo = math.radians(lat_deg), math.radians(lon_deg)
    n = (-math.sin(la) * math.cos(lo), -math.sin(la) * math.sin(lo), math.cos(la))
    e = (-math.sin(lo), math.cos(lo), 0.0)
    up = (math.cos(la) * math.cos(lo), math.cos(la) * math.sin(lo), math.sin(la))
    return n, e, up


def geodetic_of_surface(p):
    """(lat, lon) in deg of a point on (or near) the ellipsoid's surface, by its normal."""
    x, y, z = p
    lon = math.degrees(math.atan2(y, x))
    r = math.hypot(x, y)
    lat = math.atan2(z, r * (1.0 - E2))
    for _ in range(5):  # (exact on the surface; a few iterations for h != 0)
        N = A / math.sqrt(1.0 - E2 * math.sin(lat) ** 2)
        h = r / math.cos(lat) - N if abs(lat) < 1.4 else z / math.sin(lat) - N * (1.0 - E2)
        lat = math.atan2(z, r * (1.0 - E2 * N / (N + h)))
    return math.degrees(lat), lon


def to_surface(x):
    q = (x[0] ** 2 + x[1] ** 2) / (A * A) + x[2] ** 2 / (B * B)
    s = 1.0 / math.sqrt(q)
    return (x[0] * s, x[1] * s, x[2] * s)


class Ellipse:
    """The section of the ellipsoid by the plane through the centre and both footprints."""

    def __init__(self, p0, p1):
        cr = _cross(p0, p1)
        if math.sqrt(_dot(cr, cr)) < 1e-6 * math.sqrt(_dot(p0, p0) * _dot(p1, p1)):
            raise ValueError("coincident or antipodal points")
        self.p = _unit(cr)
        zc = _cross((0.0, 0.0, 1.0), self.p)
        self.e1 = _unit(zc) if math.sqrt(_dot(zc, zc)) > 1e-12 else _unit((p0[0], p0[1], 0.0))
        self.e2 = _cross(self.p, self.e1)
        sz = self.e2[2]
        self.b = 1.0 / math.sqrt((1.0 - sz * sz) / (A * A) + sz * sz / (B * B))
        self.beta0 = self.beta(p0)
        b1 = self.beta(p1)
        while b1 <= self.beta0:
            b1 += 2.0 * math.pi
        self.beta1 = b1

    def beta(self, q):
        return math.atan2(_dot(q, self.e2) / self.b, _dot(q, self.e1) / A)

    def point(self, beta):
        ca, sb = A * math.cos(beta), self.b * math.sin(beta)
        return tuple(ca * self.e1[i] + sb * self.e2[i] for i in range(3))

    def arc(self, b0, b1, n=64):
        """Arc length from beta b0 to b1 (Gauss-Legendre, 8 points on n panels: exact to rounding)."""
        xs = (0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363)
        ws = (0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763)
        h = (b1 - b0) / n
        s = 0.0
        for k in range(n):
            c = b0 + (k + 0.5) * h
            for x, w in zip(xs, ws):
                for sg in (-1.0, 1.0):
                    t = c + sg * x * h / 2
                    s += w * math.hypot(A * math.sin(t), self.b * math.cos(t))
        return s * h / 2

    def length(self):
        return self.arc(self.beta0, self.beta1)

    def track(self, q_deg, beta):
        """Unit track direction (N, E) at the point of parameter beta, in the NE plane at q_deg (lat, lon)."""
        d = tuple(-A * math.sin(beta) * self.e1[i] + self.b * math.cos(beta) * self.e2[i] for i in range(3))
        n, e, _ = _ned_axes(*q_deg)
        dn, de = _dot(d, n), _dot(d, e)
        hn = math.hypot(dn, de)
        return dn / hn, de / hn


def _sphere_direct(lat, lon, az_deg, dist, R=6371008.8):
    la, lo, az, d = math.radians(lat), math.radians(lon), math.radians(az_deg), dist / R
    la2 = math.asin(math.sin(la) * math.cos(d) + math.cos(la) * math.sin(d) * math.cos(az))
    lo2 = lo + math.atan2(math.sin(az) * math.sin(d) * math.cos(la), math.cos(d) - math.sin(la) * math.sin(la2))
    return math.degrees(la2), math.degrees(lo2)


def direct(lat, lon, az_deg, dist):
    """The footprint at great-ellipse distance `dist` from (lat, lon) leaving at azimuth az (deg):
    the sphere's direct problem, its distance corrected until the great ellipse (route3d.hpp's
    leg) is `dist` long to 1e-9."""
    p0 = ecef(lat, lon)
    d = dist
    for _ in range(8):
        la2, lo2 = _sphere_direct(lat, lon, az_deg, d)
        L = Ellipse(p0, ecef(la2, lo2)).length()
        if abs(L - dist) < 1e-9 * dist:
            break
        d *= dist / L
    return la2, lo2


def _unwrap(lon, ref):
    return ref + _wrap180(lon - ref)


# ---- route3d.hpp's timing

def _softplus(x):
    return x + math.log1p(math.exp(-x)) if x > 0 else math.log1p(math.exp(x))


def _logistic(x):
    return 1.0 / (1.0 + math.exp(-x)) if x >= 0 else math.exp(x) / (1.0 + math.exp(x))


def _turn_shifts(dpsi, lam):
    """(c1, c2) of a fly-by turn of angle dpsi (rad) and length scale lam (route3d.cpp)."""
    ia = 1j * dpsi
    eia = cmath.exp(ia)
    f = [0j] * 50
    term = 1 + 0j
    for j in range(1, 50):
        term *= ia / j
        f[j] = term
    f[1] -= eia - 1
    q = 0j
    g1 = 0j
    for m in range(48):
        q += f[m + 1]
        g1 += q / (m + 1)
    emia = eia.conjugate()
    sd = math.sin(dpsi)
    alpha = lam * (emia * g1).imag / sd if abs(sd) > 1e-15 else 0.0
    return alpha, alpha * math.cos(dpsi) + lam * (emia * g1).real


class Timing:
    def __init__(self, v0):
        self.v0 = v0
        self.dv = []  # (t, dv, tau)

    def s(self, t):
        s = self.v0 * t
        for tj, dv, tau in self.dv:
            s += dv * tau * (_softplus((t - tj) / tau) - _softplus(-tj / tau))
        return s

    def v(self, t):
        return self.v0 + sum(dv * _logistic((t - tj) / tau) for tj, dv, tau in self.dv)

    def t_of(self, s):
        t = s / self.v0
        for _ in range(200):
            dt = (self.s(t) - s) / self.v(t)
            t -= dt
            if abs(dt) < 1e-12 * (1 + abs(t)):
                break
        return t


def route_timing(wps, turn_rate_dps):
    """route3d.hpp's design quantities of waypoints [{lat_deg, lon_deg, height_m, speed_mps, climb_rate_mps,
    accel_mps2, vertical_accel_mps2, turn_rate_dps}] (waypoint 0: the start): per leg its length and
    time window, per turn its angle; raises ValueError with route3d's reason when it cannot be flown."""
    n = len(wps) - 1
    P = [ecef(w["lat_deg"], w["lon_deg"]) for w in wps]
    legs = [Ellipse(P[k], P[k + 1]) for k in range(n)]
    L = [g.length() for g in legs]
    turns = [None] * (n + 1)  # (dpsi, lam, c1, c2)
    for k in range(1, n):
        q = (wps[k]["lat_deg"], wps[k]["lon_deg"])
        d1 = legs[k - 1].track(q, legs[k - 1].beta1)
        d2 = legs[k].track(q, legs[k].beta0)
        dpsi = math.atan2(d1[0] * d2[1] - d1[1] * d2[0], d1[0] * d2[0] + d1[1] * d2[1])
        if abs(dpsi) > math.radians(MAX_TURN_DEG):
            raise ValueError("waypoint %d: turn of %.1f deg" % (k, math.degrees(dpsi)))
        rate = math.radians(wps[k].get("turn_rate_dps", turn_rate_dps))
        lam = max(1.0, wps[k]["speed_mps"] * abs(dpsi) / (4.0 * rate))
        c1, c2 = _turn_shifts(dpsi, lam)
        turns[k] = (dpsi, lam, c1, c2)
    lam = [t[1] if t else 0.0 for t in turns]
    s_wp = [0.0] * (n + 1)
    for k in range(1, n + 1):
        c2 = turns[k - 1][3] if turns[k - 1] else 0.0
        c1 = turns[k][2] if turns[k] else 0.0
        s_wp[k] = s_wp[k - 1] - c2 + c1 + L[k - 1]
        if not s_wp[k] - s_wp[k - 1] > 4.0 * (lam[k - 1] + lam[k]):
            raise ValueError("waypoint %d: leg too short for its turns" % k)
    tm = Timing(wps[1]["speed_mps"])
    cur = tm.v0
    for k in range(n):
        target = wps[k + 1]["speed_mps"]
        if target == cur:
            continue
        dv = target - cur
        tau = abs(dv) / (4.0 * wps[k + 1]["accel_mps2"])
        t = tm.t_of(s_wp[k] + 6.0 * lam[k]) + 10.0 * tau
        tm.dv.append((t, dv, tau))
        cur = target
        if k + 1 < n and not tm.t_of(s_wp[k + 1] - 6.0 * lam[k + 1]) > t + 10.0 * tau:
            raise ValueError("waypoint %d: speed change does not fit" % (k + 1))
    t_wp = [tm.t_of(s) for s in s_wp]
    t_wp[0] = 0.0
    climbs = []
    for k in range(n):
        dh = wps[k + 1]["height_m"] - wps[k]["height_m"]
        if dh == 0:
            climbs.append(None)
            continue
        rate = wps[k + 1]["climb_rate_mps"]
        tau_h = rate / (4.0 * wps[k + 1]["vertical_accel_mps2"])
        need = abs(dh) / rate + 40.0 * tau_h
        if not need <= t_wp[k + 1] - t_wp[k]:
            raise ValueError("waypoint %d: climb of %.0f m needs %.0f s, leg lasts %.0f s"
                             % (k + 1, dh, need, t_wp[k + 1] - t_wp[k]))
        climbs.append((t_wp[k] + 20 * tau_h, t_wp[k] + 20 * tau_h + abs(dh) / rate))
    return {"leg_length_m": L, "s_wp": s_wp, "t_wp": t_wp, "turn_deg": [math.degrees(t[0]) if t else 0.0 for t in turns],
            "turn_lambda_m": lam, "climbs": climbs}


# ---- the draw

class Route:
    def __init__(self, start, waypoints, timing, seed, attempts):
        self.start = start            # {lat_deg, lon_deg, height_m}
        self.waypoints = waypoints    # [{lat_deg, lon_deg, height_m, speed_mps, ...}]
        self.timing = timing
        self.seed = seed
        self.attempts = attempts
        self.flight_time_s = timing["t_wp"][-1]
        self.duration_s = float(math.ceil(self.flight_time_s))

    def info(self):
        """What a run records of its route (beside its scenario)."""
        return {"seed": self.seed, "attempts": self.attempts, "legs": len(self.waypoints),
                "flight_time_s": self.flight_time_s, "duration_s": self.duration_s,
                "leg_km": [x / 1e3 for x in self.timing["leg_length_m"]],
                "turn_deg": self.timing["turn_deg"][1:-1],
                "heights_m": [self.start["height_m"]] + [w["height_m"] for w in self.waypoints],
                "speeds_mps": [w["speed_mps"] for w in self.waypoints],
                "start": [self.start["lat_deg"], self.start["lon_deg"]]}

    def apply(self, sc):
        """Set the route in a scenario dict (in place): [trajectory] and time.duration_s."""
        t = sc.setdefault("trajectory", {})
        t["type"] = "route"
        for k in ("lat_deg", "lon_deg", "height_m"):
            t[k] = self.start[k]
        t["speed_mps"] = self.waypoints[0]["speed_mps"]
        t.pop("initial_speed_mps", None)
        t["waypoint"] = [dict(w) for w in self.waypoints]
        sc.setdefault("time", {})["duration_s"] = self.duration_s
        an = (sc.get("gravity") or {}).get("anomaly")
        if isinstance(an, dict):  # the anomaly region centred on the start (the parser's default)
            an["lat_deg"], an["lon_deg"], an["ref_height_m"] = self.start["lat_deg"], self.start["lon_deg"], self.start["height_m"]
        return sc


def _u(rng, r):
    return r[0] if r[0] == r[1] else rng.uniform(r[0], r[1])


def _leg_inside(spec, lat0, lon0, lat1, lon1, h=None):
    """The leg's footprint (16 points along its great ellipse) inside the region."""
    e = Ellipse(ecef(lat0, lon0), ecef(lat1, lon1))
    for k in range(1, 17):
        la, lo = geodetic_of_surface(e.point(e.beta0 + (e.beta1 - e.beta0) * k / 16))
        if not spec.inside(la, lo):
            return False
    return True


def _try(spec, rng):
    T = _u(rng, spec.duration)
    n = rng.randint(spec.legs[0], spec.legs[1])
    v = [_u(rng, spec.speed) for _ in range(n)]
    raw = [_u(rng, spec.leg_m) for _ in range(n)]
    scale = T / sum(l / s for l, s in zip(raw, v))
    L = [l * scale for l in raw]
    if any(not (spec.leg_m[0] <= l <= spec.leg_m[1]) for l in L):
        return None, "leg length"
    lat = _u(rng, spec.lat)
    lon = _wrap180(spec.lon_min + rng.uniform(0.0, spec.lon_width))
    h0 = _u(rng, spec.start_height)
    start = {"lat_deg": lat, "lon_deg": lon, "height_m": h0}
    az = rng.uniform(0.0, 360.0)
    pts = [(lat, lon)]
    for k in range(n):
        if k > 0:
            # arrival track of the leg before, as azimuth at its end
            la0, lo0 = pts[-2]
            la1, lo1 = pts[-1]
            e = Ellipse(ecef(la0, lo0), ecef(la1, lo1))
            dn, de = e.track((la1, lo1), e.beta1)
            arr = math.degrees(math.atan2(de, dn))
            mag = _u(rng, spec.turn)
            sg = 1.0 if rng.random() < 0.5 else -1.0
            cands = [arr + sg * mag, arr - sg * mag]
        else:
            cands = [az]
        for a in cands:
            la2, lo2 = direct(pts[-1][0], pts[-1][1], a, L[k])
            lo2 = _unwrap(lo2, pts[-1][1])
            if spec.inside(la2, lo2) and _leg_inside(spec, pts[-1][0], pts[-1][1], la2, lo2):
                pts.append((la2, lo2))
                break
        else:
            return None, "region"
    # heights: level or a climb/descent that fits the leg's time at its rate
    wps = []
    h = h0
    for k in range(n):
        w = {"lat_deg": pts[k + 1][0], "lon_deg": pts[k + 1][1], "speed_mps": v[k], "turn_rate_dps": spec.turn_rate_dps,
             "accel_mps2": spec.accel, "vertical_accel_mps2": spec.vaccel}
        rate = _u(rng, spec.climb_rate)
        w["climb_rate_mps"] = rate
        if spec.climb[1] > 0 and rng.random() >= spec.level_fraction:
            mag = _u(rng, spec.climb)
            sg = 1.0 if rng.random() < 0.5 else -1.0
            if not spec.height[0] <= h + sg * mag <= spec.height[1]:
                sg = -sg
            if not spec.height[0] <= h + sg * mag <= spec.height[1]:
                return None, "height"
            # the climb within the leg's time (estimated at its speed; turns and speed steps in the
            # check below): |dh| / rate + 40 tau_h at most 80 % of it; |dh| cut to what fits, a leg
            # too short for climb_m's least change flown level
            tau_h = rate / (4.0 * spec.vaccel)
            fit = rate * (0.8 * L[k] / v[k] - 40.0 * tau_h)
            if fit >= spec.climb[0]:
                h = h + sg * min(mag, fit)
        w["height_m"] = h
        wps.append(w)
    try:
        tim = route_timing([dict(start, speed_mps=v[0])] + wps, spec.turn_rate_dps)
    except ValueError as e:
        return None, "timing: %s" % e
    if not spec.duration[0] <= tim["t_wp"][-1] <= spec.duration[1]:
        return None, "duration"
    # longitudes in [-360, 360] (unwrapped along the route from the start in [-180, 180))
    if any(abs(w["lon_deg"]) > 360.0 for w in wps):
        return None, "longitude"
    return (start, wps, tim), None


def draw(spec, seed):
    """The route of seed `seed` (a Route); RouteSpecError when no draw fits within spec.attempts."""
    rng = random.Random(seed + spec.seed_offset)
    why = {}
    for i in range(spec.attempts):
        got, reason = _try(spec, rng)
        if got:
            start, wps, tim = got
            return Route(start, wps, tim, seed, i + 1)
        why[reason.split(":")[0]] = why.get(reason.split(":")[0], 0) + 1
    raise RouteSpecError("[routes]: no route fits for seed %d in %d draws (rejected: %s)" % (seed, spec.attempts, why))
