#!/usr/bin/env python3
"""End to end: a small survey block (survey-small.toml: 3 lines, 1 tie, back over the start)
flown by ggins run3d in an anomaly field with Gao's sensor noise, then ggins gravimetry.

Checked against the scenario's field (the truth the product never sees):
  - the product's files and formats (survey.csv columns, survey.xyz Line/Tie blocks);
  - the lines, the tie, the three crossovers and the closing point are found;
  - the stated one-sigma holds: chi-square over the lines inside its 95 % band;
  - the first line (before any turn has added gyro noise to the dead-reckoned G) is within
    0.05 mGal of the truth at 6 km, and the crossover/closing adjustment reduces the
    horizontal error against the unadjusted estimate;
  - clear errors: --help, a missing folder (exit 2), a folder without the record (exit 1).
Python stdlib only.
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys

FAILS = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run3d", required=True)
    ap.add_argument("--gravimetry", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    here = os.path.dirname(os.path.abspath(__file__))
    if os.path.exists(a.workdir):
        shutil.rmtree(a.workdir)
    os.makedirs(a.workdir)
    flight = os.path.join(a.workdir, "flight")
    cmd = [a.run3d, "-s", os.path.join(here, "survey-small.toml"), "--direct", "--no-plots", "--no-log",
           "--no-reference", "-q", "-o", flight]
    print("$ " + " ".join(cmd))
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(p.stdout[-2000:])
    check(p.returncode == 0, "ggins run3d flew the survey (exit %d)" % p.returncode)
    check(os.path.exists(os.path.join(flight, "gravimetry_raw.csv")), "the flight wrote gravimetry_raw.csv")
    cmd = [a.gravimetry, flight]
    print("$ " + " ".join(cmd))
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(p.stdout)
    check(p.returncode == 0, "ggins gravimetry exit 0 (got %d)" % p.returncode)
    out = os.path.join(flight, "gravimetry")
    with open(os.path.join(out, "gravimetry.json")) as f:
        j = json.load(f)
    with open(os.path.join(out, "survey.csv")) as f:
        rows = list(csv.DictReader(f))
    check(len(rows) > 500 and {"line", "fid", "lat_deg", "lon_deg", "height_m", "dg_mgal", "xi_arcsec", "eta_arcsec",
                               "sigma_dg_mgal", "truth_dg_mgal"} <= set(rows[0]), "survey.csv rows and columns")
    with open(os.path.join(out, "survey.xyz")) as f:
        xyz = f.read().splitlines()
    check(xyz[0].startswith("/") and "Line 10" in xyz and "Tie 1000" in xyz, "survey.xyz: comment header, Line/Tie blocks")
    kinds = [(ln["type"], ln["line"]) for ln in j["lines"]]
    check(sum(1 for k in kinds if k[0] == "line") >= 3 and ("tie", 1000) in kinds, "3 lines and the tie found: %s" % kinds)
    check(j["crossovers"] == 3, "3 crossovers (got %d)" % j["crossovers"])
    check(j["closing"] is not None, "closing point found")
    c = j["chi2"]
    check(c["in_band"], "chi-square over the lines %.1f inside its 95 %% band %.1f..%.1f" % (c["value"], *c["band95"]))
    first = j["lines"][0]
    check(first["line"] == 10 and first["rms_dg_mgal"] < 0.05 and first["rms_horizontal_mgal"] < 0.05,
          "first line within 0.05 mGal of the truth (dg %.4f, horizontal %.4f mGal)" %
          (first["rms_dg_mgal"], first["rms_horizontal_mgal"]))
    check(j["all"]["rms_horizontal_mgal"] < j["unadjusted"]["rms_horizontal_mgal"],
          "adjustment reduces the horizontal error: %.3f < %.3f mGal unadjusted" %
          (j["all"]["rms_horizontal_mgal"], j["unadjusted"]["rms_horizontal_mgal"]))
    check(len(j["table"]) == 4 and len(j["spectrum"]) > 5, "error table and spectrum written")

    p = subprocess.run([a.gravimetry, "--help"], stdout=subprocess.PIPE, text=True)
    check(p.returncode == 0 and "survey.xyz" in p.stdout and "closing" in p.stdout, "--help explains the product")
    p = subprocess.run([a.gravimetry, os.path.join(a.workdir, "nope")], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    check(p.returncode == 2, "missing folder: exit 2 (got %d)" % p.returncode)
    empty = os.path.join(a.workdir, "empty")
    os.makedirs(empty)
    p = subprocess.run([a.gravimetry, empty], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    check(p.returncode == 1 and "cannot read" in p.stdout, "folder without the record: exit 1, named (%s)" %
          p.stdout.strip())
    if FAILS:
        print("\n%d check(s) failed" % len(FAILS))
        sys.exit(1)


if __name__ == "__main__":
    main()
