"""Campaign files (TOML) and their expansion into runs.

A campaign file:

  [campaign]
  name = "welker-table1-mc"         # default: the file's stem
  command = "run"                   # run | run3d | rw-eq8 | montecarlo3d
  scenario = "welker-table1"        # run, run3d: scenarios/NAME.toml, or a path (relative to this file)
  seeds = 200                       # runs per point
  seed0 = 1000                      # run i of every point uses seed seed0 + i
  args = ["--csv-rate", "1"]        # fixed options of the command
  timeout_s = 7200                  # a run that takes longer fails (default: none)

  [sweep]                           # every combination of these (a product)
  "accel.bias_sigma_mps2" = [1e-12, 2e-12]            # scenario key (dotted), a list ...
  "time.duration_s" = {start = 600.0, stop = 1800.0, step = 600.0}   # ... or a range (stop included)
  "--update" = {start = 30, stop = 180, num = 4}      # command option: "--name"

  [[point]]                         # and/or an explicit list of points (each then x the sweep);
  name = "db"                       # a list or range in a point is swept within that point,
  "--db-noise-e" = [0.01, 0.1]      # {value = [..]} sets an array-valued key as it is

  [routes]                          # run3d: every run flies its own route drawn from its seed
  lat_deg = [45.0, 62.0]            # (routes.py: region, heights, legs, turns, climbs, speeds,
  ...                               #  duration; time.duration_s = the route's flight time)

  [outputs]
  series_dt = 60                    # keep each run's time series every 60 s (0: final values only)
  compare = "covariance"            # run: sample sigma against ggins covariance (chi-square band)
  z = 3                             # band: +-z standard-normal quantiles of chi-square_N

How `seed` reaches each command is the command's own convention (tools.py):
  run          --seed S (and [accel] seed = S in the scenario file)  (as ggins montecarlo: seed0 + i)
  run3d        the scenario's seed keys ([accel] seed = S, [gyro] S + 1, [baro] S + 2, [draw] S + 3,
               [coldatom] S + 4, [aid_pf] S + 5)
  rw-eq8, montecarlo3d   --seed S: one whole Monte Carlo of the command (its --runs) per seed
"""
import hashlib
import itertools
import json
import os
import tomllib

from . import routes as routes_mod
from . import tomlw
from .tools import TOOLS


class SpecError(Exception):
    pass


def _expand_values(key, v):
    if isinstance(v, list):
        if not v:
            raise SpecError("sweep %s: empty list" % key)
        return list(v)
    if isinstance(v, dict):
        if set(v) == {"value"}:  # one array-valued key as it is
            return [v["value"]]
        if "values" in v:
            return list(v["values"])
        if "start" not in v or "stop" not in v:
            raise SpecError("sweep %s: a range needs start and stop (and step or num)" % key)
        a, b = v["start"], v["stop"]
        is_int = all(isinstance(x, int) and not isinstance(x, bool) for x in (a, b, v.get("step", 1)))
        if "num" in v:
            n = int(v["num"])
            if n < 1:
                raise SpecError("sweep %s: num must be >= 1" % key)
            if n == 1:
                return [a]
            vals = [a + (b - a) * k / (n - 1) for k in range(n)]
            if is_int and all(float(x).is_integer() for x in vals):
                return [int(x) for x in vals]
            return [float(x) for x in vals]
        if "step" in v:
            s = v["step"]
            if s == 0 or (b - a) / s < 0:
                raise SpecError("sweep %s: step %r does not go from %r to %r" % (key, s, a, b))
            n = int(round((b - a) / s + 1e-9)) if is_int else int((b - a) / s + 1e-9)
            vals = [a + k * s for k in range(n + 1)]
            return vals if is_int else [float(x) for x in vals]
        raise SpecError("sweep %s: a range needs step or num" % key)
    return [v]


class Run:
    """One run: a point of the sweep and a seed; everything that determines it is in task()."""

    def __init__(self, campaign, point_index, point, seed_index, seed, task, route=None):
        self.campaign = campaign
        self.route = route          # the drawn route (routes.Route) of a [routes] campaign
        self.point_index = point_index
        self.point = point          # {"name":..., key: value}
        self.seed_index = seed_index
        self.seed = seed
        self._task = task
        blob = json.dumps({k: task[k] for k in ("argv", "files", "parse", "series_dt", "ok_codes")},
                          sort_keys=True, separators=(",", ":"))
        self.run_id = hashlib.sha256(blob.encode()).hexdigest()[:20]
        self._task["run_id"] = self.run_id

    def task(self):
        return dict(self._task)

    def info(self):
        d = {"run_id": self.run_id, "point": self.point_index, "point_name": self.point.get("name", ""),
             "params": {k: v for k, v in self.point.items() if k != "name"},
             "seed_index": self.seed_index, "seed": self.seed}
        if self.route is not None:  # the route and the whole scenario the run flew: it reproduces the run
            d["route"] = self.route.info()
            d["scenario_toml"] = (self._task.get("files") or {}).get("scenario.toml")
            d["argv_template"] = self._task.get("argv")
        return d


class Campaign:
    def __init__(self, path, text=None, source_dir=None, bin_dir=None, data_dir=None):
        self.path = os.path.abspath(path)
        self.text = text if text is not None else open(path).read()
        try:
            d = tomllib.loads(self.text)
        except tomllib.TOMLDecodeError as e:
            raise SpecError("%s: %s" % (path, e))
        c = d.get("campaign")
        if not isinstance(c, dict):
            raise SpecError("%s: no [campaign] table" % path)
        known = {"campaign", "sweep", "point", "outputs", "routes"}
        extra = set(d) - known
        if extra:
            raise SpecError("%s: unknown table(s) %s (known: %s)" % (path, sorted(extra), sorted(known)))
        self.name = c.get("name") or os.path.splitext(os.path.basename(path))[0]
        self.description = c.get("description", "")
        self.command = c.get("command")
        if self.command not in TOOLS:
            raise SpecError("%s: command %r is not one of %s" % (path, self.command, sorted(TOOLS)))
        self.tool = TOOLS[self.command]
        self.seeds = int(c.get("seeds", 1))
        if self.seeds < 1:
            raise SpecError("%s: seeds must be >= 1" % path)
        self.seed0 = int(c.get("seed0", self.tool.default_seed0))
        self.args = [str(a) for a in c.get("args", [])]
        self.timeout_s = c.get("timeout_s")
        self.source_dir = source_dir or os.environ.get("GGINS_SOURCE_DIR") or _guess_source_dir()
        self.bin_dir = os.path.abspath(bin_dir or os.environ.get("GGINS_BIN") or
                                       os.path.join(self.source_dir, "build", "bin"))
        self.data_dir = os.path.abspath(data_dir or os.environ.get("GGINS_DATA") or os.path.join(self.source_dir, "data"))
        self.scenario_name = c.get("scenario")
        self.scenario = None
        if self.tool.uses_scenario:
            if not self.scenario_name:
                raise SpecError("%s: command %s needs [campaign] scenario" % (path, self.command))
            self.scenario_path = self._find_scenario(self.scenario_name)
            try:
                self.scenario = self.tool.load_scenario(self, self.scenario_path)
            except (OSError, RuntimeError, tomllib.TOMLDecodeError) as e:
                raise SpecError(str(e))
        elif self.scenario_name:
            raise SpecError("%s: command %s takes no scenario file (sweep its options)" % (path, self.command))
        self.routes = None
        if "routes" in d:
            if self.command != "run3d":
                raise SpecError("%s: [routes] is for command run3d (a route per run), not %s" % (path, self.command))
            try:
                self.routes = routes_mod.RouteSpec(d["routes"])
            except routes_mod.RouteSpecError as e:
                raise SpecError("%s: %s" % (path, e))
        o = d.get("outputs", {})
        self.series_dt = float(o.get("series_dt", self.tool.default_series_dt))
        self.compare = o.get("compare", self.tool.default_compare)
        self.z = float(o.get("z", 3.0))
        sweep = d.get("sweep", {})
        points = d.get("point", [{}])
        if isinstance(points, dict):
            points = [points]
        keys = list(sweep)
        for k in keys:
            self._check_key(k)
        grids = [_expand_values(k, sweep[k]) for k in keys]
        self.sweep_keys = keys
        self.points = []
        for p in points:
            # in a point, a list or a range is swept too (a product within the point);
            # {value = X} sets X as it is (an array-valued scenario key)
            fixed, pkeys, pgrids = {}, [], []
            for k, v in p.items():
                if k == "name":
                    continue
                self._check_key(k)
                if isinstance(v, dict) and set(v) == {"value"}:
                    fixed[k] = v["value"]
                elif isinstance(v, (list, dict)):
                    pkeys.append(k)
                    pgrids.append(_expand_values(k, v))
                else:
                    fixed[k] = v
            allkeys = pkeys + keys
            for combo in itertools.product(*(pgrids + grids)):
                q = dict(fixed)
                q.update(dict(zip(allkeys, combo)))
                # the name tags the swept keys (a key with one value is common to every point)
                tag = ",".join("%s=%s" % (k.lstrip("-"), v) for k, v, g in zip(allkeys, combo, pgrids + grids)
                               if len(g) > 1)
                if "name" in p:
                    q["name"] = p["name"] + ("," + tag if tag else "")
                else:
                    q["name"] = tag or ",".join("%s=%s" % (k.lstrip("-"), v) for k, v in fixed.items()) or "base"
                self.points.append(q)
        self.param_keys = []
        for q in self.points:
            for k in q:
                if k != "name" and k not in self.param_keys:
                    self.param_keys.append(k)

    def _check_key(self, k):
        if k.startswith("--"):
            return
        if not self.tool.uses_scenario:
            raise SpecError("%s: %r: command %s has no scenario file; sweep its options (\"--name\")"
                            % (self.path, k, self.command))

    def _find_scenario(self, name):
        base = os.path.dirname(self.path)
        for cand in (os.path.join(base, name), name,
                     os.path.join(self.source_dir, "scenarios", name + ".toml"),
                     os.path.join(self.source_dir, "scenarios", name)):
            if os.path.isfile(cand):
                return os.path.abspath(cand)
        raise SpecError("%s: scenario %r not found (a path, or scenarios/NAME.toml)" % (self.path, name))

    def point_scenario(self, point):
        """The scenario of a point (seed not applied), or None for option-only tools."""
        if self.scenario is None:
            return None
        sc = json.loads(json.dumps(self.scenario))
        for k, v in point.items():
            if k != "name" and not k.startswith("--"):
                tomlw.set_dotted(sc, k, v)
        return sc

    def point_options(self, point):
        opts = []
        for k, v in point.items():
            if k.startswith("--"):
                if isinstance(v, bool):
                    if v:
                        opts.append(k)
                else:
                    opts += [k, _fmt(v)]
        return opts

    def runs(self):
        out = []
        for pi, p in enumerate(self.points):
            sc = self.point_scenario(p)
            opts = self.point_options(p)
            for si in range(self.seeds):
                seed = self.seed0 + si
                route = None
                sc_run = sc
                if self.routes is not None:
                    try:
                        route = routes_mod.draw(self.routes, seed)
                    except routes_mod.RouteSpecError as e:
                        raise SpecError("%s: %s" % (self.path, e))
                    sc_run = route.apply(json.loads(json.dumps(sc)))
                task = self.tool.task(self, sc_run, opts, seed)
                # a route campaign stores its degraded flights (exit 4: the integrity monitor's
                # flags are what its report lists), the others count them as failed
                ok = self.tool.ok_codes + ([4] if self.routes is not None and self.command == "run3d" else [])
                task.update({"series_dt": self.series_dt, "bin_dir": self.bin_dir, "data_dir": self.data_dir,
                             "timeout_s": self.timeout_s, "ok_codes": ok})
                out.append(Run(self, pi, p, si, seed, task, route))
        return out


def _fmt(v):
    if isinstance(v, float):
        return repr(v)
    return str(v)


def _guess_source_dir():
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.abspath(os.path.join(here, "..", "..", ".."))
