"""Campaign files and statistics against independent truth: sweep expansion (lists, ranges
by step and by num, explicit points), the TOML writer read back by tomllib, run ids (stable,
changed by what determines a run and only by that), each command's seed convention on its
command line, and the statistics against published tables (Student t, chi-square quantiles)."""
import math
import os
import shutil
import tempfile
import tomllib

import util
from util import Checks

from ggins_campaign import report, spec, tomlw, worker

C = Checks("campaign.spec")
tmp = tempfile.mkdtemp(prefix="ggins-campaign-spec-")


def camp(text, name="c.toml"):
    return spec.Campaign(util.write(os.path.join(tmp, name), text), source_dir=util.SRC, bin_dir=util.BIN)


try:
    # ranges
    C.ok(spec._expand_values("k", {"start": 30, "stop": 180, "num": 4}) == [30, 80, 130, 180], "num range, ints")
    C.ok(spec._expand_values("k", {"start": 0.1, "stop": 0.5, "step": 0.2}) == [0.1, 0.30000000000000004, 0.5],
         "step range includes stop")
    C.ok(spec._expand_values("k", {"start": 1, "stop": 10, "step": 3}) == [1, 4, 7, 10], "int step range")
    C.ok(spec._expand_values("k", [3, 1]) == [3, 1], "list kept in order")
    for badv in ({"start": 1}, {"start": 1, "stop": 0, "step": 1}, []):
        try:
            spec._expand_values("k", badv)
            C.ok(False, "bad range %r refused" % (badv,))
        except spec.SpecError:
            C.ok(True, "bad range %r refused" % (badv,))

    # TOML writer: what tomllib reads back is what was written, floats bit for bit
    d = {"name": "a \"quoted\" name", "x": 0.1, "tiny": 2e-12, "big": 3.986004418e14, "n": 7, "flag": True,
         "arr": [1.5, 2.0, -3e-300], "t": {"sub": {"k": "v", "f": 1.0}, "z": -0.0}, "tabs": [{"a": 1}, {"a": 2}]}
    C.ok(tomllib.loads(tomlw.dumps(d)) == d, "TOML writer round trip (tomllib)")

    # a product sweep of a scenario key and a command option, times explicit points
    c = camp("""
[campaign]
command = "run"
scenario = "welker-table1"
seeds = 3
[sweep]
"accel.bias_sigma_mps2" = [1e-12, 2e-12]
"--truth-rate" = [5, 10]
[[point]]
name = "short"
"time.duration_s" = 60.0
[[point]]
name = "long"
"time.duration_s" = 120.0
""")
    runs = c.runs()
    C.ok(len(c.points) == 8 and len(runs) == 24, "2 points x 2 x 2 sweep x 3 seeds = 24 runs")
    C.ok(len({r.run_id for r in runs}) == 24, "24 distinct run ids")
    r0 = runs[0]
    sc = tomllib.loads(r0.task()["files"]["scenario.toml"])
    base = tomllib.load(open(os.path.join(util.SRC, "scenarios", "welker-table1.toml"), "rb"))
    C.ok(sc["accel"]["bias_sigma_mps2"] == 1e-12 and sc["time"]["duration_s"] == 60.0 and sc["accel"]["seed"] == 1000
         and sc["trajectory"] == base["trajectory"] and sc["gravity"] == base["gravity"],
         "swept scenario = the scenario file with the point's keys and the seed set")
    a = r0.task()["argv"]
    C.ok(a[a.index("--seed") + 1] == "1000" and a[a.index("--truth-rate") + 1] == "5", "run: --seed 1000, option swept")
    c2 = camp(open(os.path.join(tmp, "c.toml")).read())
    C.ok([r.run_id for r in c2.runs()] == [r.run_id for r in runs], "run ids stable across loads")
    c3 = camp(open(os.path.join(tmp, "c.toml")).read().replace("seeds = 3", "seeds = 4"), "c3.toml")
    C.ok({r.run_id for r in runs} < {r.run_id for r in c3.runs()}, "more seeds: the old runs keep their ids")
    c4 = camp(open(os.path.join(tmp, "c.toml")).read().replace("120.0", "121.0"), "c4.toml")
    ch = {r.run_id for r in runs} ^ {r.run_id for r in c4.runs()}
    C.ok(len(ch) == 24, "a changed point value changes exactly that point's 12 run ids (24 differ in the union)")

    # each command's seed convention
    m = camp('[campaign]\ncommand = "rw-eq8"\nseeds = 3\nargs = ["--runs", "4"]\n[sweep]\n"--hours" = [1, 2]\n', "m.toml")
    mr = m.runs()
    av = mr[2].task()["argv"]
    C.ok(av[av.index("--seed") + 1] == "3" and "--hours" in av and av[av.index("--runs") + 1] == "4",
         "rw-eq8: seed S = --seed S, the command's own options kept and swept")
    # run3d: the runs start from the scenario as it would fly (every key, the files it names
    # absolute: each run's copy sits in its own folder); every table's seed from S, the map's kept
    util.write(os.path.join(tmp, "s3.toml"), '[time]\nduration_s = 10.0\n[draw]\nposition_ned_m = [1.0, 1.0, 1.0]\n'
               '[coldatom]\nenabled = true\ncache = "cache-here"\n')
    r3 = camp('[campaign]\ncommand = "run3d"\nscenario = "s3.toml"\nseeds = 2\nseed0 = 40\n', "r3.toml").runs()[1]
    s3 = tomllib.loads(r3.task()["files"]["scenario.toml"])
    C.ok(s3["accel"]["seed"] == 41 and s3["gyro"]["seed"] == 42 and s3["baro"]["seed"] == 43 and s3["draw"]["seed"] == 44
         and s3["coldatom"]["seed"] == 45 and s3["aid_pf"]["seed"] == 46 and s3["aid_ukf"]["map_seed"] == 1,
         "run3d: accel S, gyro S+1, baro S+2, draw S+3, coldatom S+4, aid_pf S+5; the map's noise seed kept (one map)")
    C.ok(s3["coldatom"]["cache"] == os.path.join(tmp, "cache-here") and s3["time"]["duration_s"] == 10.0
         and s3["draw"]["position_ned_m"] == [1.0, 1.0, 1.0],
         "run3d: a relative file of the scenario made absolute from the scenario's folder; its keys kept")
    try:
        camp('[campaign]\ncommand = "run3d"\nscenario = "s3.toml"\n[sweep]\n"time.duration_s" = [1.0]\n',
             "r3b.toml").runs()
        util.write(os.path.join(tmp, "s3bad.toml"), '[time]\nduration_s = -1.0\n')
        camp('[campaign]\ncommand = "run3d"\nscenario = "s3bad.toml"\n', "r3c.toml")
        C.ok(False, "run3d: a scenario ggins-run3d refuses is refused when the campaign is read")
    except spec.SpecError as e:
        C.ok("time.duration_s" in str(e), "run3d: a scenario ggins-run3d refuses is refused when the campaign is read: %s" % e)
    # run3d's values derived from a run's series, against hand values: a 3-4-5 horizontal error
    # for 3 h then 0 (mean over the 4 samples 3.75 m); the last 2 h hold t = 3600, 7200, 10800 (t >= t_end - 7200):
    # RMS north sqrt((9 + 9 + 0) / 3), down sqrt((1 + 4 + 4) / 3)
    ser = {"t_s": [0.0, 3600.0, 7200.0, 10800.0], "rn_m": [3.0, 3.0, 3.0, 0.0], "re_m": [4.0, 4.0, 4.0, 0.0],
           "rd_m": [1.0, 1.0, 2.0, 2.0]}
    dv = r3.campaign.tool.derived(ser)
    C.ok(abs(dv["hmean_m"] - 3.75) < 1e-12 and abs(dv["rms2h_rn_m"] - math.sqrt(6.0)) < 1e-12
         and abs(dv["rms2h_rd_m"] - math.sqrt(3.0)) < 1e-12, "run3d: flight-mean horizontal error 3.75 m, RMS over the last 2 h")
    C.ok("unaided_hmean_m" not in dv, "run3d: no unaided flight mean without the unaided reference's series")
    # the unaided reference's series (5-12-13 for 2 samples, 8-15-17 for 2): mean 15 m
    dv = r3.campaign.tool.derived(dict(ser, unaided_rn_m=[5.0, 5.0, 8.0, 8.0], unaided_re_m=[12.0, 12.0, 15.0, 15.0]))
    C.ok(abs(dv["unaided_hmean_m"] - 15.0) < 1e-12 and abs(dv["hmean_m"] - 3.75) < 1e-12,
         "run3d: the unaided reference's flight-mean horizontal error 15 m beside the aided 3.75 m")
    jp = util.write(os.path.join(tmp, "s.json"), '{"aids": [{"nis_mean": 6.5}, {"nis_mean": null}], "u": {"n": 1, "e": 2}}')
    jv = worker._read_json(jp, {"values": {"nis": "aids.0.nis_mean", "nees": "?aids.0.nees.position",
                                           "nis1": "?aids.1.nis_mean", "u_": "?u.*", "w_": "?w.*"}})
    C.ok(jv == {"nis": 6.5, "u_n": 1.0, "u_e": 2.0},
         "optional json paths (\"?\"): stored when present, skipped when absent or null (a mean over no sample)")
    C.ok(spec._expand_values("k", {"value": [1.0, 2.0]}) == [[1.0, 2.0]], "{value = [..]} in a sweep: one array value")
    try:
        camp('[campaign]\ncommand = "rw-eq8"\n[sweep]\n"time.duration_s" = [1.0]\n', "bad.toml")
        C.ok(False, "scenario key refused for a command without a scenario")
    except spec.SpecError:
        C.ok(True, "scenario key refused for a command without a scenario")

    # statistics against published tables
    for dof, t in ((1, 12.706), (5, 2.571), (40, 2.021), (60, 2.000), (120, 1.980)):
        C.ok(abs(report.t975(dof) - t) < 2e-3, "t_0.975(%d) = %.3f (table %.3f)" % (dof, report.t975(dof), t))
    # chi-square quantiles (tables): chi2_0.975(10) = 20.483, chi2_0.025(10) = 3.247,
    # chi2_0.99865(200) ~ 265.4 (z = 3), chi2_0.995(100) = 140.169
    for n, z, q in ((10, 1.959964, 20.483), (10, -1.959964, 3.247), (100, 2.575829, 140.169)):
        got = report.chi2_quantile_wh(n, z)
        C.ok(abs(got / q - 1) < 0.01, "Wilson-Hilferty chi2(%d) at z = %.2f: %.3f (table %.3f)" % (n, z, got, q))
    s = report.stats([1.0, -2.0, 3.0, -4.0])
    C.ok(abs(s["mean"] + 0.5) < 1e-15 and abs(s["sd"] - math.sqrt(29 / 3)) < 1e-12 and
         abs(s["sigma"] - math.sqrt(30 / 4)) < 1e-12 and abs(s["mean_abs"] - 2.5) < 1e-15 and
         abs(s["sd_abs"] - math.sqrt(7.5 - 6.25)) < 1e-12, "stats of (1, -2, 3, -4) by hand")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
C.done()
