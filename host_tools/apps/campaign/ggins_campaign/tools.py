"""The commands a campaign can fly, and how one run of each is called and read back.

Each run is an ordinary invocation of an existing command (the same command line a user
would type), in a scratch folder on the worker; what is read back is the command's own
output files. "{bin}" is the folder of the built tools, "{out}" the run's output folder,
"{cache}" a per-worker cache (derived data such as the EGM96 grid; same content everywhere),
"{data}" the data folder (EGM96 coefficients).
"""
import math
import os
import subprocess
import tomllib

from . import tomlw

# the six error states of the 2-D system (Welker et al. eq. 7), firmware minus truth,
# with the names of ggins montecarlo / ggins covariance
RUN2D_STATES = {"err_r_x_m": "x_m", "err_r_z_m": "z_m", "err_v_x_mps": "vx_mps", "err_v_z_mps": "vz_mps",
                "err_g_x_mps2": "gx_mps2", "err_g_z_mps2": "gz_mps2"}

RUN3D_STATES = {"err_n_m": "rn_m", "err_e_m": "re_m", "err_d_m": "rd_m", "err_vn_mps": "vn_mps",
                "err_ve_mps": "ve_mps", "err_vd_mps": "vd_mps", "att_err_n_rad": "att_n_rad",
                "att_err_e_rad": "att_e_rad", "att_err_d_rad": "att_d_rad", "err_gn_mps2": "gn_mps2",
                "err_ge_mps2": "ge_mps2", "err_gd_mps2": "gd_mps2", "err_h_m": "h_m"}


class Tool:
    name = ""
    uses_scenario = False
    default_seed0 = 1
    default_series_dt = 0.0
    default_compare = None
    ok_codes = [0]
    # states whose errors are zero-mean draws, summarised as a sample sigma against a prediction
    sigma_states = []

    def task(self, c, scenario, opts, seed):
        raise NotImplementedError

    def derived(self, series):
        """Values of one run derived from its stored series (none by default)."""
        return {}

    def load_scenario(self, c, path):
        """The scenario file as the runs start from (a dict; the campaign sets keys in it)."""
        with open(path, "rb") as f:
            return tomllib.load(f)


class Run2D(Tool):
    """ggins run: the 2-D system over LCM (truth generator -> hal_sim -> firmware)."""
    name = "run"
    uses_scenario = True
    default_seed0 = 1000           # ggins montecarlo's --seed0
    default_series_dt = 10.0
    default_compare = "covariance"
    sigma_states = list(RUN2D_STATES.values())

    def task(self, c, scenario, opts, seed):
        sc = dict(scenario)
        tomlw.set_dotted(sc, "accel.seed", seed)
        argv = ["{bin}/ggins-run", "--scenario", "scenario.toml", "--seed", str(seed), "--no-log", "--no-plots",
                "-q", "--csv-rate", "1", "--out", "{out}"] + c.args + opts
        return {"argv": argv, "files": {"scenario.toml": tomlw.dumps(sc)},
                "parse": [{"csv": "timeseries.csv", "time": "t_s", "columns": RUN2D_STATES}]}


class Run3D(Tool):
    """ggins run3d: the 3-D system over LCM, or stepped in-process with --direct in args."""
    name = "run3d"
    uses_scenario = True
    default_seed0 = 1
    default_series_dt = 10.0
    sigma_states = list(RUN3D_STATES.values())

    def load_scenario(self, c, path):
        """The scenario as it would fly (ggins-run3d --print-scenario: every key, the files it names
        absolute, so that the copy each run writes into its own folder names the same maps and data)."""
        exe = os.path.join(c.bin_dir, "ggins-run3d")
        try:
            p = subprocess.run([exe, "-s", path, "--print-scenario"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
        except OSError as e:
            raise RuntimeError("%s: cannot run %s to read the scenario (build first): %s" % (c.path, exe, e))
        if p.returncode != 0:
            raise RuntimeError("%s: scenario %s: %s" % (c.path, path, p.stderr.strip()))
        return tomllib.loads(p.stdout)

    def task(self, c, scenario, opts, seed):
        sc = dict(scenario)
        for k, off in (("accel.seed", 0), ("gyro.seed", 1)):
            tomlw.set_dotted(sc, k, seed + off)
        # the optional tables' own draws: the barometer, the Monte Carlo draw of the constant
        # errors, the cold-atom shots and the particle filter's generator
        for table, off in (("baro", 2), ("draw", 3), ("coldatom", 4), ("aid_pf", 5)):
            if isinstance(sc.get(table), dict):
                tomlw.set_dotted(sc, table + ".seed", seed + off)
        argv = ["{bin}/ggins-run3d", "--scenario", "scenario.toml", "--no-log", "--no-plots", "-q",
                "--out", "{out}"] + c.args + opts
        routes = getattr(c, "routes", None)
        pf = sc.get("aid_pf") or {}
        if (routes is not None and pf.get("enabled") and not pf.get("map_from_field")
                and (sc.get("coldatom") or {}).get("gzz_map") == "field"):
            # a drawn route's particle filter on the [gravity] field: its Gamma_zz tiles along this
            # route, in height layers where it climbs, written by ggins run3d before the flight
            # (aid_pf.map_from_field: the map UKF's cut, run3d field_map.hpp)
            pf = {k: v for k, v in pf.items() if k != "map_dir"}
            sc["aid_pf"] = dict(pf, map_from_field=True, map_spacing_deg=routes.pf_map_spacing_deg,
                                map_margin_deg=routes.pf_map_margin_deg, map_noise_E=routes.pf_map_noise_E,
                                map_seed=routes.pf_map_seed)
        # the aids' consistency (summary.json "aids", in the order the scenario switches them on)
        # and the unaided reference's final error (the same frames with every aid off)
        values = {}
        aids = [a for a in ("aid_ukf", "aid_pf") if (sc.get(a) or {}).get("enabled")]
        for i, a in enumerate(aids):
            if a == "aid_ukf":
                values.update({"ukf_nis": "?aids.%d.nis_mean" % i, "ukf_nees_pos": "?aids.%d.nees.position" % i,
                               "ukf_nees_vel": "?aids.%d.nees.velocity" % i,
                               "ukf_nees_att": "?aids.%d.nees.attitude" % i})
            else:
                g = "?aids.%d.gradient_estimates." % i
                values.update({"pf_err_over_spread_sq": "aids.%d.err_over_spread_sq_mean" % i,
                               "pf_estimate_error_m": "aids.%d.estimate_error_mean_m" % i,
                               "pf_shots": "aids.%d.shots" % i, "pf_failed": "aids.%d.failed" % i,
                               "pf_map_miss": "aids.%d.map_miss" % i,
                               "ellipse_fit_err_mean_E": g + "ellipse_fit_err_mean_E",
                               "ellipse_fit_err_std_E": g + "ellipse_fit_err_std_E",
                               "pf_gzz_err_mean_E": g + "pf_err_mean_E", "pf_gzz_err_std_E": g + "pf_err_std_E"})
        values["unaided_r"] = "?unaided_reference.position_error_final_m.*"
        columns = dict(RUN3D_STATES)
        if aids:  # the unaided reference's series beside the aided one (for its flight mean)
            columns.update({"unaided_err_n_m": "unaided_rn_m", "unaided_err_e_m": "unaided_re_m"})
        parse = [{"csv": "timeseries.csv", "time": "t_s", "columns": columns},
                 {"json": "summary.json", "values": values}]
        task = {"argv": argv, "files": {"scenario.toml": tomlw.dumps(sc)}, "parse": parse}
        if routes is not None:
            # the route report's inputs as the flight wrote them (missing fields: absent)
            parse[1]["keep"] = {"status": "?status", "degraded_reasons": "?degraded_reasons", "aids": "?aids",
                                "unaided_reference": "?unaided_reference",
                                "position_error_m": "?errors.position_error_m"}
        return task

    def derived(self, series):
        """Per run, from its stored series (the campaign's series_dt grid): the horizontal position
        error averaged over the flight (Phillips et al.'s mean radial error) and the RMS of each
        position error axis over the last 2 h (Gao et al.'s Tables 3-9; the whole flight if shorter)."""
        t = series.get("t_s") or []
        if not len(t) or not all(k in series for k in ("rn_m", "re_m", "rd_m")):
            return {}
        n = len(t)
        out = {"hmean_m": sum(math.hypot(series["rn_m"][i], series["re_m"][i]) for i in range(n)) / n}
        if "unaided_rn_m" in series and "unaided_re_m" in series:  # the same frames with every aid off
            out["unaided_hmean_m"] = sum(math.hypot(series["unaided_rn_m"][i], series["unaided_re_m"][i])
                                         for i in range(n)) / n
        last = [i for i in range(n) if t[i] >= t[-1] - 7200.0]
        for k in ("rn_m", "re_m", "rd_m"):
            out["rms2h_" + k] = math.sqrt(sum(series[k][i] ** 2 for i in last) / len(last))
        return out



class RwEq8(Tool):
    """ggins rw-eq8: one whole Monte Carlo (its --runs flights) per seed."""
    name = "rw-eq8"
    default_seed0 = 1

    def task(self, c, scenario, opts, seed):
        argv = ["{bin}/ggins-rw-eq8", "--seed", str(seed), "--out", "{out}/rw"] + c.args + opts
        return {"argv": ["sh", "-c", 'mkdir -p "$1" && shift && exec "$@"', "sh", "{out}"] + argv, "files": {},
                "parse": [{"json": "rw.json", "values": {"": "rows.-1.*", "measured_rms_arcsec": "measured_rms_arcsec",
                                                         "all_in_band": "all_in_band_from_s.all_in"}},
                          {"csv": "rw.csv", "time": "t_s", "prefix": ""}]}


class MonteCarlo3D(Tool):
    """ggins montecarlo3d: one whole 3-D Monte Carlo (its --runs runs, seeds S..S+N-1) per seed."""
    name = "montecarlo3d"
    default_seed0 = 1

    def task(self, c, scenario, opts, seed):
        argv = ["{bin}/ggins-montecarlo3d", "--seed", str(seed), "-j", "1", "--no-plot", "--out", "{out}"] + c.args + opts
        return {"argv": argv, "files": {},
                "parse": [{"json": "montecarlo3d.json", "values": {"": "final.*", "all_in_band": "all_in_band",
                                                                   "ratio_min": "ratio_min", "ratio_max": "ratio_max"}}]}


TOOLS = {t.name: t for t in (Run2D(), Run3D(), RwEq8(), MonteCarlo3D())}
