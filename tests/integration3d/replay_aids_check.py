#!/usr/bin/env python3
"""Replay of 3-D runs whose aids read the computer's map storage, over LCM (ggins run3d ->
hal_sim --map -> ggins replay).

pf:  the cold-atom aid on its storage of Gamma_zz tiles along Phillips' route (~230 tiles
     written by a first 1 s flight with [aid_pf] map_from_field, then given as
     [aid_pf].map_dir: far more than a table of single tiles would hold):
     60 s of scenarios/3d-liverpool-toulouse-pf.toml. The run records the storage as one
     directory source (its tile count, bytes and one BLAKE2b over names and contents); the
     replay reloads it and is bit-exact. A storage that is not the one the run flew is
     refused with exit 2 and the source named: one bit flipped in a tile the flight never
     reads, a tile missing, a tile added; the same tiles moved and named with --map-dir:
     bit-exact. The copy of the scenario as flown names the map directory absolute and flies
     again (5 s, --direct, from another working directory) on the same storage.
all: every aid on at once: the barometer loop, the map UKF (one EGM96 degree-36 tile of the
     whole tensor around Liverpool, `ggins gmap`; the truth field the same degree-36 EGM96,
     exact accelerometers and gyros so that the differenced tensor is the field's) and the
     cold-atom particle filter (its Gamma_zz tiles, written by the runner from the sensor's
     route map: [aid_pf] map_from_field): each aid is served the tiles of its kind (both aids
     update, neither misses a map), and the replay is bit-exact. Needs the EGM96 coefficients (exit 77, skipped,
     without them).

The route map of both: the WGS-84 normal field along the route (scenario gzz_map
"phillips-route-normal"): the storage's bytes are what is tested here, not
the filter's accuracy (docs/cold-atom-pf.md has that).

usage: replay_aids_check.py {pf,all} --ggins-run3d P --ggins-replay P
                            [--ggins-gmap P --egm96 FILE] --workdir DIR
"""
import argparse
import csv
import glob
import json
import os
import shutil
import subprocess
import sys
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
SCEN = os.path.join(HERE, "..", "..", "scenarios", "3d-liverpool-toulouse-pf.toml")


def sub(text, old, new):
    if old not in text:
        raise SystemExit("scenario text changed: %r not found" % old)
    return text.replace(old, new, 1)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=["pf", "all"])
    for k in ("--ggins-run3d", "--ggins-replay", "--workdir"):
        ap.add_argument(k, required=True)
    ap.add_argument("--ggins-gmap")
    ap.add_argument("--ggins-profile")
    ap.add_argument("--egm96")
    a = ap.parse_args()
    if a.mode == "all" and not (a.egm96 and os.path.exists(a.egm96)):
        print("no EGM96 coefficients at %s: skipped" % a.egm96)
        return 77
    w = os.path.abspath(a.workdir)
    shutil.rmtree(w, ignore_errors=True)
    os.makedirs(w)
    text = open(SCEN).read()
    text = sub(text, 'gzz_map = "phillips-route"', 'gzz_map = "phillips-route-normal"')
    text = sub(text, 'cache = "../out/coldatom/cache"', 'cache = "cache"')
    if a.mode == "pf":
        # the tiles of the route map, written by a first flight of one second (map_from_field),
        # then served to the flight from their own directory (map_dir)
        sc0 = os.path.join(w, "tiles.toml")
        open(sc0, "w").write(text)
        subprocess.run([a.ggins_run3d, "-s", sc0, "-o", os.path.join(w, "tiles-run"), "--direct", "--duration", "1",
                        "--no-plots", "--no-reference", "-q"], check=True, stdout=subprocess.DEVNULL)
        tiles = os.path.join(w, "tiles")
        shutil.move(os.path.join(w, "tiles-run", "maps", "aid_pf"), tiles)
        names = sorted(glob.glob(os.path.join(tiles, "*.gmap")))
        text = sub(text, "map_from_field = true", 'map_dir = "tiles"\n#')
    if a.mode == "all":
        ukf_tile = os.path.join(w, "ukf", "tile_liverpool.bin")
        os.makedirs(os.path.dirname(ukf_tile))
        subprocess.run([a.ggins_gmap, "--lat-min", "52.92", "--lat-max", "53.9", "--lon-min", "-3.46",
                        "--lon-max", "-2.48", "--spacing", "0.02", "--alt", "3000", "--h-range", "500",
                        "--degree", "36", "--noise-e", "0.001", "--egm96", a.egm96, "--threads", "1",
                        "--out", ukf_tile], check=True, stdout=subprocess.DEVNULL)
        text = sub(text, 'model = "wgs84-normal"',
                   'model = "egm96"\n[gravity.sh]\npath = "%s"\nnmax = 36' % a.egm96)
        text = sub(text, "noise_sigma_mps2 = 1.0e-6", "noise_sigma_mps2 = 0.0")
        text = sub(text, "noise_sigma_radps = 2.0e-5   # 2 urad/s/sqrt(Hz) at 100 Hz", "noise_sigma_radps = 0.0")
        text = sub(text, "bias_sigma_radps = 5.0e-8    # 0.05 urad/s (0.01 deg/h)", "bias_sigma_radps = 0.0")
        text += ('\n[aid_ukf]\nenabled = true\nmap = "ukf/tile_liverpool.bin"\nupdate_period_s = 5.0\n'
                 'average_s = 2.0\nmax_passes = 3\nsigma_meas_E = 0.01\nsigma_db_E = 0.01\nsig0_pos_m = 20.0\n')
    sc = os.path.join(w, "flight.toml")
    open(sc, "w").write(text)
    out = os.path.join(w, "run")
    p = subprocess.run([a.ggins_run3d, "-s", sc, "-o", out, "--duration", "60", "--no-plots", "-q"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode == 3:
        print("multicast on loopback unavailable: skipped")
        return 77
    if a.mode == "all":
        names = sorted(glob.glob(os.path.join(out, "maps", "aid_pf", "*.gmap")))
    fails = []

    def check(cond, what):
        print(("ok   " if cond else "FAIL ") + what)
        if not cond:
            fails.append(what)

    check(p.returncode == 0, "run3d completed (exit %d)%s" % (p.returncode, "" if p.returncode == 0 else "\n" + p.stdout))
    s = json.load(open(os.path.join(out, "summary.json")))
    aids = {x.get("name"): x for x in s.get("aids", [])}
    pf = aids.get("aid_pf", {})
    check(pf.get("shots", 0) >= 55 and pf.get("updates", 0) >= 1 and pf.get("no_map", 1) == 0,
          "the cold-atom aid took its shots from its tiles (%s shots, %s updates, %s without a tile)" %
          (pf.get("shots"), pf.get("updates"), pf.get("no_map")))
    check(s.get("baro_loop") is True, "the barometer loop on")
    ms = s.get("map_storage", [])
    src = [x for x in ms if x.get("kind") == "directory"]
    check(len(names) > 16 and len(src) == 1 and src[0]["tiles"] == len(names),
          "the storage recorded whole: one directory of %d tiles (%s)" % (len(names), src[0]["tiles"] if src else None))
    if a.mode == "all":  # the runner's tiles of the route map, recorded as the storage's directory
        check(bool(src) and src[0].get("path", "").endswith(os.path.join("maps", "aid_pf")),
              "map_from_field: the runner wrote %d tiles into <out>/maps/aid_pf and recorded that directory"
              % len(names))
    if a.mode == "all":
        ukf = aids.get("aid_ukf", {})
        check(ukf.get("updates", 0) >= 8 and ukf.get("no_map", 1) == 0 and ukf.get("rejected", 1) == 0,
              "the map UKF updated from its tensor tile (%s updates, %s rejected, %s without a tile)" %
              (ukf.get("updates"), ukf.get("rejected"), ukf.get("no_map")))
        # its innovations those of the field's tensor: mean NIS below 3 x its 6 degrees of freedom (handed a
        # Gamma_zz tile, whose five other components are zero, the innovations are the field's ~1e3 E)
        check(ukf.get("nis_mean", 1e99) < 18.0, "the map UKF's mean NIS %.3g < 18 (6 dof)" % ukf.get("nis_mean", 1e99))
        check(len(ms) == 2 and ms[0].get("kind") == "file" and ms[0].get("tiles") == 1,
              "the UKF's tile recorded as a file source before the directory")
        # the unaided reference of the flight (the task with its aids off, stepped in run3d on the
        # same frames) against a separate flight of the same scenario with --no-aids: equal
        ref = s.get("unaided_reference", {})
        un = os.path.join(w, "unaided")
        r = subprocess.run([a.ggins_run3d, "-s", sc, "-o", un, "--duration", "60", "--direct", "--no-aids",
                            "--no-plots", "-q"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        su = json.load(open(os.path.join(un, "summary.json"))) if os.path.exists(
            os.path.join(un, "summary.json")) else {}
        eu = su.get("errors", {})
        col = lambda f, k: [row[k] for row in csv.DictReader(open(f))]
        same_csv = os.path.exists(os.path.join(un, "timeseries.csv")) and col(
            os.path.join(out, "timeseries.csv"), "unaided_err_r_m") == col(os.path.join(un, "timeseries.csv"), "err_r_m")
        check(r.returncode == 0 and "unaided_reference" not in su and ref.get("steps") == s.get("steps_flown") and
              ref.get("position_error_m") == eu.get("position_error_m") and
              ref.get("position_error_final_m") == eu.get("position_error_final_m") and
              ref.get("gravity_error_mps2") == eu.get("gravity_error_mps2") and same_csv,
              "the unaided reference equals a separate --no-aids flight: final |dr| %s vs %s m, CSV column "
              "unaided_err_r_m = its err_r_m: %s" % (ref.get("position_error_m", {}).get("final"),
                                                     eu.get("position_error_m", {}).get("final"), same_csv))
        if a.ggins_profile:  # the profile of the same flight: a row of step time for each aid of the task
            flown = os.path.join(out, "scenario.toml")
            r = subprocess.run([a.ggins_profile, "-s", flown, "--task", "3d", "--duration", "20", "--no-filters"],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            rows = {ln.split()[0]: ln.split()[1:] for ln in r.stdout.splitlines() if len(ln.split()) == 4}
            have = all(m in rows and all(x.isdigit() for x in rows[m]) and int(rows[m][2]) > 0
                       for m in ("diff", "mech", "aid_mm", "aid_pf", "total"))
            check(r.returncode == 0 and have and int(rows["total"][2]) >= int(rows["aid_mm"][2]),
                  "ggins profile --task 3d: rows diff, mech, aid_mm, aid_pf, total, the aids inside the total "
                  "(exit %d)\n%s" % (r.returncode, r.stdout))
    if a.mode == "pf":  # the copy as flown names its map directory absolute: it flies again from the output folder
        flown = os.path.join(out, "scenario.toml")
        md = tomllib.load(open(flown, "rb")).get("aid_pf", {}).get("map_dir")
        check(md == tiles, "scenario.toml as flown names the map directory absolute: %s" % md)
        again = os.path.join(w, "again")
        r = subprocess.run([a.ggins_run3d, "-s", flown, "-o", again, "--duration", "5", "--direct", "--no-plots", "-q"],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd="/")
        s2 = json.load(open(os.path.join(again, "summary.json"))) if os.path.exists(
            os.path.join(again, "summary.json")) else {}
        check(r.returncode == 0 and s2.get("map_storage") == ms,
              "the copy as flown flies again from another working directory on the same storage (exit %d)%s" %
              (r.returncode, "" if r.returncode == 0 else "\n" + r.stdout))
    log = os.path.join(out, "run.lcmlog")
    rj = os.path.join(w, "r.json")

    def replay(*extra):
        if os.path.exists(rj):
            os.remove(rj)
        r = subprocess.run([a.ggins_replay, log, "--json", rj] + list(extra), stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True)
        j = json.load(open(rj)) if os.path.exists(rj) else {}
        return r.returncode, r.stdout, j

    n_all = len(names) + (1 if a.mode == "all" else 0)
    rc, txt, j = replay()
    compared = j.get("outputs", {}).get("compared", 0)
    check(rc == 0 and j.get("bit_exact") is True and compared >= 6000,
          "replay with the recorded storage: bit-exact (exit %d, %s outputs compared)" % (rc, compared))
    check(len(j.get("map_tiles", [])) == n_all, "the replay loaded the %d tiles of the storage" % n_all)
    if a.mode == "pf":
        far = names[-1]  # the tile at Toulouse: a 60 s flight never reads it
        good = open(far, "rb").read()
        bad = bytearray(good)
        bad[500] ^= 0x01
        open(far, "wb").write(bytes(bad))
        rc, txt, j = replay()
        check(rc == 2 and "not the one the run flew" in txt and tiles in txt,
              "one bit flipped in a tile the flight never read: refused, the directory named (exit %d)" % rc)
        open(far, "wb").write(good)
        mid = names[len(names) // 2]
        os.rename(mid, mid + ".away")
        rc, txt, j = replay()
        check(rc == 2 and "not the one the run flew" in txt, "a tile missing: refused (exit %d)" % rc)
        os.rename(mid + ".away", mid)
        extra = os.path.join(tiles, "tile_9999.gmap")
        shutil.copy(names[0], extra)
        rc, txt, j = replay()
        check(rc == 2 and "not the one the run flew" in txt, "a tile added: refused (exit %d)" % rc)
        os.remove(extra)
        moved = os.path.join(w, "moved")
        os.makedirs(moved)
        shutil.move(tiles, os.path.join(moved, "tiles"))
        rc, txt, j = replay()
        check(rc == 2 and "cannot be read" in txt, "the storage gone: refused (exit %d)" % rc)
        rc, txt, j = replay("--map-dir", moved)
        check(rc == 0 and j.get("bit_exact") is True, "--map-dir with the moved storage: bit-exact (exit %d)" % rc)
    print("%d checks failed" % len(fails) if fails else "all checks passed")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
