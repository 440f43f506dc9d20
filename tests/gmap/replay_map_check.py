#!/usr/bin/env python3
"""gmap.replay_map: a 3-D run with the gradient-map aid on, over LCM (ggins run3d ->
hal_sim --map), replays bit for bit with the tiles the run recorded in its
configuration message (path, size, BLAKE2b-256); a replay given a tile whose bytes
differ, or none, is refused (exit 2, the tile named), and --map-dir finds a moved
tile by file name.

The tile: `ggins gmap` around the start of scenarios/3d-egm96-1h.toml (45 N 10 E,
5000 m), degree 36 (the EGM96 coefficient file is needed: exit 77, skipped, without
it). The flight: 60 s of that scenario with perfect sensors and an epoch every 5 s
averaged over 2 s (the aid's whole schedule, several times).

usage: replay_map_check.py --ggins-gmap P --ggins-run3d P --ggins-replay P --egm96 FILE --workdir DIR
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SCEN = os.path.join(HERE, "..", "..", "scenarios", "3d-egm96-1h.toml")


def main():
    ap = argparse.ArgumentParser()
    for k in ("--ggins-gmap", "--ggins-run3d", "--ggins-replay", "--egm96", "--workdir"):
        ap.add_argument(k, required=True)
    a = ap.parse_args()
    if not os.path.exists(a.egm96):
        print("no EGM96 coefficients at %s: skipped" % a.egm96)
        return 77
    w = a.workdir
    shutil.rmtree(w, ignore_errors=True)
    os.makedirs(os.path.join(w, "tiles"))
    tile = os.path.join(w, "tiles", "tile_45n10e.bin")
    subprocess.run([a.ggins_gmap, "--lat-min", "44.8", "--lat-max", "45.78", "--lon-min", "9.51", "--lon-max",
                    "10.49", "--spacing", "0.02", "--alt", "5000", "--h-range", "3000", "--degree", "36",
                    "--noise-e", "0.001", "--egm96", a.egm96, "--threads", "1", "--out", tile], check=True,
                   stdout=subprocess.DEVNULL)
    text = open(SCEN).read()
    sc = os.path.join(w, "aided.toml")
    with open(sc, "w") as f:
        f.write(text.replace('model = "egm96"', 'model = "egm96"\n[gravity.sh]\npath = "%s"' % a.egm96, 1))
        f.write('\n[aid_ukf]\nenabled = true\nmap = "tiles/tile_45n10e.bin"\nupdate_period_s = 5.0\n'
                'average_s = 2.0\nmax_passes = 3\nsigma_meas_E = 0.01\nsigma_db_E = 0.01\nsig0_pos_m = 20.0\n')
    out = os.path.join(w, "run")
    p = subprocess.run([a.ggins_run3d, "-s", sc, "-o", out, "--duration", "60", "--no-plots", "-q"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode == 3:
        print("multicast on loopback unavailable: skipped")
        return 77
    fails = []

    def check(cond, what):
        print(("ok   " if cond else "FAIL ") + what)
        if not cond:
            fails.append(what)

    # the tile is of degree 36, the field of degree 360: its innovations are far outside their
    # chi-square band, so the integrity monitor de-weights, then isolates the aid, and the flight
    # ends degraded; the replay below covers updates and isolated epochs both (the tile's height
    # band is wide, so that the wrong map's pull on the height does not end its epochs first)
    s = json.load(open(os.path.join(out, "summary.json")))
    check(p.returncode == 4 and s.get("status") == "degraded" and
          any(r.startswith("map aid inconsistent") for r in s.get("degraded_reasons", [])),
          "a degree-36 map in a degree-360 field: degraded, the map aid named (exit %d, %r)"
          % (p.returncode, s.get("degraded_reasons")))
    aid = [x for x in s.get("aids", []) if x.get("name") == "aid_ukf"]
    check(len(aid) == 1 and aid[0]["updates"] >= 2 and aid[0]["integrity"]["isolated_epochs"] >= 1 and
          aid[0]["integrity"]["state_final"] == "ISOLATED",
          "the aid updated, then was isolated (updates %s, isolated epochs %s)"
          % (aid[0]["updates"] if aid else "-", aid[0]["integrity"]["isolated_epochs"] if aid else "-"))
    check(os.path.exists(os.path.join(out, "aid_epochs.csv")), "aid_epochs.csv written")
    # a flight that ends before the aid's first epoch (5 s): no NIS sample, so no mean (null, not 0)
    out3 = os.path.join(w, "run-short")
    p = subprocess.run([a.ggins_run3d, "-s", sc, "-o", out3, "--duration", "3", "--direct", "--no-log", "--no-plots",
                        "-q"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    s3 = json.load(open(os.path.join(out3, "summary.json"))) if os.path.exists(os.path.join(out3, "summary.json")) else {}
    aid = [x for x in s3.get("aids", []) if x.get("name") == "aid_ukf"]
    check(p.returncode == 0 and len(aid) == 1 and aid[0]["updates"] == 0 and aid[0]["nis_mean"] is None and
          "nis_band95" not in aid[0] and aid[0]["nees"]["epochs"] == 0 and "position" not in aid[0]["nees"],
          "a 3 s flight, before the first epoch: NIS and NEES means null/absent, not 0 (exit %d, nis_mean %r)"
          % (p.returncode, aid[0]["nis_mean"] if aid else "-"))
    log = os.path.join(out, "run.lcmlog")

    def replay(*extra):
        r = subprocess.run([a.ggins_replay, log, "--json", os.path.join(w, "r.json")] + list(extra),
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        j = json.load(open(os.path.join(w, "r.json"))) if os.path.exists(os.path.join(w, "r.json")) else {}
        return r.returncode, r.stdout, j

    rc, txt, j = replay()
    check(rc == 0 and j.get("bit_exact") is True, "replay with the recorded tile: bit-exact (exit %d)" % rc)
    check(len(j.get("map_tiles", [])) == 1, "the replay names the one recorded tile")
    # a negative control: the same log without the tile's bytes as recorded
    good = open(tile, "rb").read()
    bad = bytearray(good)
    bad[200] ^= 0x01  # one bit of a node value
    open(tile, "wb").write(bytes(bad))
    rc, txt, j = replay()
    check(rc == 2 and "not the one the run flew" in txt, "a tile with one bit flipped: refused (exit %d)" % rc)
    os.remove(tile)
    rc, txt, j = replay()
    check(rc == 2 and "cannot be read" in txt, "the tile missing: refused (exit %d)" % rc)
    moved = os.path.join(w, "moved")
    os.makedirs(moved)
    open(os.path.join(moved, "tile_45n10e.bin"), "wb").write(good)
    rc, txt, j = replay("--map-dir", moved)
    check(rc == 0 and j.get("bit_exact") is True, "--map-dir with the moved tile: bit-exact (exit %d)" % rc)
    # the map built by run3d from the scenario's own field ([aid_ukf] map_from_field): the
    # same flight, the tiles in the output folder recorded as one directory source, replayed
    sc2 = os.path.join(w, "field.toml")
    open(sc2, "w").write(open(sc).read().replace('map = "tiles/tile_45n10e.bin"', 'map_from_field = true'))
    out2 = os.path.join(w, "run-field")
    p = subprocess.run([a.ggins_run3d, "-s", sc2, "-o", out2, "--duration", "60", "--no-plots", "-q"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    s2 = json.load(open(os.path.join(out2, "summary.json"))) if os.path.exists(os.path.join(out2, "summary.json")) else {}
    ms = s2.get("map_storage", [])
    aid = [x for x in s2.get("aids", []) if x.get("name") == "aid_ukf"]
    check(p.returncode == 0 and len(ms) == 1 and ms[0]["kind"] == "directory" and
          ms[0]["path"] == os.path.join(os.path.abspath(out2), "maps", "aid_ukf") and ms[0]["tiles"] >= 1 and
          len(aid) == 1 and aid[0]["updates"] >= 8 and aid[0]["no_map"] == 0,
          "map_from_field: run3d built %s tile(s) in its output folder and the aid updated from them (exit %d)%s"
          % (ms[0]["tiles"] if ms else None, p.returncode, "" if p.returncode == 0 else "\n" + p.stdout))
    log = os.path.join(out2, "run.lcmlog")
    rc, txt, j = replay()
    check(rc == 0 and j.get("bit_exact") is True, "map_from_field: the replay with the tiles it built is bit-exact "
          "(exit %d)" % rc)
    print("%d checks failed" % len(fails) if fails else "all checks passed")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
