#!/usr/bin/env python3
"""Plot ggins-montecarlo3d output: sample one-sigma of N firmware runs (markers)
against the covariance one-sigma (lines), north/east/down, for position,
velocity, gravity and (strapdown) attitude.

usage: plot_montecarlo3d.py montecarlo3d.csv montecarlo3d.png [--title T]
Needs matplotlib (Debian python3-matplotlib: /usr/bin/python3).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from ggins_plot_common import finish_log_panel, ned_panels, read_csv_figure, save  # noqa: E402


def main():
    a, col, t, fig, ax = read_csv_figure()
    colors = {"n": "C0", "e": "C1", "d": "C2"}
    for axis, b, u, scale, label in ned_panels(ax):
        if "cov_%sn_%s" % (b, u) not in col:
            axis.axis("off")
            continue
        top = 0.0
        for c, name in zip("ned", ["north", "east", "down"]):
            k = "%s%s_%s" % (b, c, u)
            cv = [(x, v * scale) for x, v in zip(t, col["cov_" + k]) if v > 0]
            mc = [(x, v * scale) for x, v in zip(t, col["mc_" + k]) if v > 0]
            if cv:
                axis.semilogy([p[0] for p in cv], [p[1] for p in cv], color=colors[c], label=name + " covariance")
                top = max(top, max(p[1] for p in cv))
            if mc:
                axis.semilogy([p[0] for p in mc], [p[1] for p in mc], "o", ms=3, color=colors[c],
                              label=name + " Monte Carlo")
        finish_log_panel(axis, top, label, legend_fontsize=7)
    save(fig, "ggins montecarlo3d: %s" % a.title, a.png)


if __name__ == "__main__":
    main()
