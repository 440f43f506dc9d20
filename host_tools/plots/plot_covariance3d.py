#!/usr/bin/env python3
"""Plot ggins-covariance3d output: one-sigma position, velocity, gravity and
(strapdown) attitude errors in NED against time.

usage: plot_covariance3d.py covariance3d.csv covariance3d.png [--title T]
Needs matplotlib (Debian python3-matplotlib: /usr/bin/python3).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from ggins_plot_common import finish_log_panel, ned_panels, read_csv_figure, save  # noqa: E402


def main():
    a, col, t, fig, ax = read_csv_figure()
    for axis, b, u, scale, label in ned_panels(ax):
        keys = ["%s%s_%s" % (b, c, u) for c in "ned"]
        if keys[0] not in col:
            axis.axis("off")
            continue
        top = 0.0
        for k, name in zip(keys, ["north", "east", "down"]):
            pts = [(x, v * scale) for x, v in zip(t, col[k]) if v > 0]
            if pts:
                axis.semilogy([p[0] for p in pts], [p[1] for p in pts], label=name)
                top = max(top, max(p[1] for p in pts))
        finish_log_panel(axis, top, label)
    save(fig, "ggins covariance3d: %s" % a.title, a.png)


if __name__ == "__main__":
    main()
