#!/usr/bin/env python3
"""scripts/survey-route: the block it writes has the geometry asked for (line length, spacing,
ties, back at the start) at the flight height, measured along WGS-84's parallels (east-west
lines: N(lat) cos(lat) dlon, exact for an arc of a parallel) and meridians (M dlat at the mean
latitude, ties and spacing), tolerance 0.05 %; and ggins run3d accepts it as a route (every
leg leaves room for its turns). Python stdlib only."""
import argparse
import math
import os
import subprocess
import sys
import tempfile

A, E2, H = 6378137.0, 6.69437999014e-3, 1000.0  # WGS-84, the block's height


def dist(a, b):
    """An arc of a parallel (two points of one latitude) at height H: N(lat) cos(lat) dlon, exact."""
    if abs(a[0] - b[0]) < 1e-9:
        la = math.radians(a[0])
        n = A / math.sqrt(1 - E2 * math.sin(la) ** 2)
        return (n + H) * math.cos(la) * abs(math.radians(b[1] - a[1]))
    raise ValueError("not on one parallel: %r %r" % (a, b))


def north(a, b):
    """The meridian arc between two latitudes at height H (Simpson's rule on M(lat)): a north-south
    leg's length to 1e-6 (the block's east offsets keep its ends within metres of one meridian)."""
    def m(lat):
        return A * (1 - E2) / (1 - E2 * math.sin(lat) ** 2) ** 1.5 + H
    l1, l2 = math.radians(a[0]), math.radians(b[0])
    return abs(l2 - l1) / 6 * (m(l1) + 4 * m((l1 + l2) / 2) + m(l2))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--script", required=True)
    ap.add_argument("--run3d", required=True)
    a = ap.parse_args()
    fails = []

    def check(c, what):
        print(("ok   " if c else "FAIL ") + what)
        if not c:
            fails.append(what)
    args = ["--lat", "62", "--lon", "25", "--lines", "6", "--length-km", "50", "--spacing-km", "5",
            "--ties-km", "0,25,50", "--run-in-km", "6", "--height-m", "1000", "--speed-mps", "90",
            "--turn-rate-dps", "4"]
    p = subprocess.run([sys.executable, a.script] + args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    check(p.returncode == 0, "survey-route exit 0")
    text = p.stdout
    pts, cur = [], None
    start = None
    for line in text.splitlines():
        if line.startswith("lat_deg"):
            cur = [float(line.split("=")[1])]
        elif line.startswith("lon_deg") and cur is not None:
            cur.append(float(line.split("=")[1]))
            if start is None:
                start = tuple(cur)
            else:
                pts.append(tuple(cur))
            cur = None
    route = [start] + pts
    check(len(pts) == 20, "20 waypoints after the start (got %d)" % len(pts))
    # lines: start -> pts[0] is line 1 (62 km with its run-ins), pts[0] -> pts[1] the 5 km step
    check(abs(dist(route[0], route[1]) - 62000) < 31, "line 1: %.0f m (62 km)" % dist(route[0], route[1]))
    check(abs(north(route[1], route[2]) - 5000) < 2.5, "line spacing: %.1f m (5 km)" % north(route[1], route[2]))
    for k in range(6):  # each line's two ends on one parallel of the block, 62 km apart
        i = 2 * k
        check(abs(dist(route[i], route[i + 1]) - 62000) < 31, "line %d: %.0f m" % (k + 1, dist(route[i], route[i + 1])))
    # the first tie at x = 0: 6 km east of the start's meridian line, spanning the block + run-ins
    tie = (route[13], route[14])
    check(abs(north(tie[0], tie[1]) - (25000 + 12000)) < 19, "tie 1: %.1f m (37 km)" % north(*tie))
    check(route[-1] == route[0], "back at the start")
    with tempfile.TemporaryDirectory() as d:
        sc = os.path.join(d, "s.toml")
        with open(sc, "w") as f:
            f.write('name = "survey-route-check"\n' + text +
                    '\n[platform]\nkind = "strapdown"\n[time]\nduration_s = 60.0\nrate_hz = 100.0\n')
        q = subprocess.run([a.run3d, "-s", sc, "--print-scenario"], stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True)
        check(q.returncode == 0, "ggins run3d accepts the route" + ("" if q.returncode == 0 else ": " + q.stdout[-300:]))
    p = subprocess.run([sys.executable, a.script, "--lat", "95", "--lon", "0"], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    check(p.returncode != 0 and "latitude" in p.stdout, "a latitude beyond the pole refused")
    if fails:
        print("%d check(s) failed" % len(fails))
        sys.exit(1)


if __name__ == "__main__":
    main()
