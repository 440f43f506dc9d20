"""Helpers shared by the covariance and Monte Carlo plotting scripts
(covariance/plot_covariance.py, covariance/plot_covariance3d.py,
montecarlo/plot_montecarlo3d.py): their command line, CSV reading, the 2x2
figure, the north/east/down panels and saving the figure.

The scripts are run by path from the C++ tools (any working directory): each
puts this folder on sys.path (host_tools/plots, beside its own folder)
before importing this module.
Needs matplotlib (Debian python3-matplotlib: /usr/bin/python3).
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv_figure():
    """Parse `csv png [--title T]`, read the CSV and open the 2x2 figure.

    Returns (args, col, t, fig, ax): col maps each CSV column to its values
    (floats), t is the time column t_s in minutes.
    """
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    with open(a.csv) as f:
        rows = list(csv.DictReader(f))
    col = {k: [float(r[k]) for r in rows] for k in rows[0]}
    t = [x / 60.0 for x in col["t_s"]]
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    return a, col, t, fig, ax


def ned_panels(ax):
    """The four 3-D panels: (axis, quantity, unit, scale, label); the CSV
    columns are <quantity><n|e|d>_<unit>."""
    return [
        (ax[0, 0], "r", "m", 1.0, "position error 1σ [m]"),
        (ax[0, 1], "v", "mps", 100.0, "velocity error 1σ [cm/s]"),
        (ax[1, 0], "g", "mps2", 1e3, "gravity error 1σ [mm/s²]"),
        (ax[1, 1], "psi", "rad", 1e6, "attitude error 1σ [µrad]"),
    ]


def finish_log_panel(axis, top, label, legend_fontsize=None):
    """Limits, labels, grid and legend of a log-scale panel whose largest
    value is top (the first minutes start from zero: six decades shown)."""
    if top > 0:
        axis.set_ylim(top * 1e-6, top * 3)
    axis.set_xlabel("time [min]")
    axis.set_ylabel(label)
    axis.grid(True, which="both", alpha=0.3)
    if legend_fontsize is None:
        axis.legend()
    else:
        axis.legend(fontsize=legend_fontsize)


def save(fig, title, png):
    """Title the figure and write it to png."""
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


# ---- flight reports (ggins run, ggins run3d: summary.json + timeseries.csv) ----------

FRAME_2D = "flight's inertial frame: x equatorial, z polar"
FRAME_3D = "NED at the true position"


def read_run(out):
    """A flight's output folder: (columns of timeseries.csv as a numpy record
    array, summary.json as a dict, {} if missing)."""
    import json
    import os

    import numpy as np

    d = np.atleast_1d(np.genfromtxt(os.path.join(out, "timeseries.csv"), delimiter=",", names=True, dtype=None,
                                    encoding="utf-8"))
    try:
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
    except (OSError, ValueError):
        s = {}
    return d, s


def error_model(out, csv_name, t_s):
    """The error model's covariance that `ggins run` / `ggins run3d` computed for the plots
    (OUTPUT_DIR/covariance/csv_name): its columns interpolated onto the flight's times t_s
    (NaN outside), and "" -- or None and why it is missing (the last line of
    covariance/covariance.log, e.g. a field the model does not cover)."""
    import os

    import numpy as np

    path = os.path.join(out, "covariance", csv_name)
    if os.path.exists(path):
        c = np.atleast_1d(np.genfromtxt(path, delimiter=",", names=True))
        return {k: np.interp(t_s, c["t_s"], c[k], left=np.nan, right=np.nan) for k in c.dtype.names if k != "t_s"}, ""
    log = os.path.join(out, "covariance", "covariance.log")
    why = [x.strip() for x in open(log) if x.strip()] if os.path.exists(log) else []
    # "ggins-covariance: <file>: gravity.model 'rw-anomaly' not supported ...": the reason alone
    return None, (why[-1].split(": ", 2)[-1] if why else "the error model was not computed")


def time_axis(t_s):
    """Time in the unit that suits the flight's length: (values, axis label)."""
    import numpy as np

    t_s = np.asarray(t_s, dtype=float)
    end = t_s[-1] if len(t_s) else 0.0
    if end > 3 * 3600:
        return t_s / 3600.0, "time since start [h]"
    if end > 600:
        return t_s / 60.0, "time since start [min]"
    return t_s, "time since start [s]"


def run_title(s, fallback):
    """Scenario, status and how much of it was flown, from a flight report."""
    if not s:
        return fallback
    t = "%s %s: %s" % (s.get("tool", "ggins"), s.get("scenario", fallback), s.get("status", "?"))
    t += " (%s, %s of %s steps" % (s.get("mode", "?"), s.get("steps_flown", "?"), s.get("steps_expected", "?"))
    if s.get("steps_unflown"):
        t += ", %d unflown" % s["steps_unflown"]
    return t + ", frames lost %s)" % s.get("frames_lost", "?")


def log_line(ax, t, y, label, color, lw=0.9, ls="-"):
    """|y| on a log axis, zeros left out."""
    import numpy as np

    y = np.abs(np.asarray(y, dtype=float))
    ax.semilogy(t, np.where(y > 0, y, np.nan), color=color, lw=lw, ls=ls, label=label)


def envelope(ax, t, sigma, label="1σ envelope", color="0.6", k=1.0, log=False):
    """The covariance envelope ±k sigma around an error (on a log axis of |error|:
    the k sigma line)."""
    import numpy as np

    sg = k * np.asarray(sigma, dtype=float)
    if log:
        pos = np.where(sg > 0, sg, np.nan)
        ax.semilogy(t, pos, color=color, lw=1.2, ls="--", label=label)
    else:
        ax.fill_between(t, -sg, sg, color=color, alpha=0.3, lw=0, label=label)
