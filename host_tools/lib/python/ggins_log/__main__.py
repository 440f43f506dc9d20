"""python3 -m ggins_log info LOG | retime LOG OUT [--speed S] | csv LOG CHANNEL OUT.csv"""
import argparse
import sys

import numpy as np

from . import read, retime
from .eventlog import CorruptLog


def _report(path, log):
    """Print what makes the log incomplete or corrupt; returns the exit code (0 or 4)."""
    probs = log.problems()
    for p in probs:
        print(f"ggins logtime: {path}: {p}", file=sys.stderr)
    return 4 if probs else 0


def main(argv=None):
    ap = argparse.ArgumentParser(prog="ggins logtime",
                                 description="ggins LCM logs: list channels, rewrite event times to flight time",
                                 epilog="exit status: 0 done; 1 failed (unreadable file, no flight clock); 2 bad "
                                        "arguments; 4 a corrupt or incomplete log (no events, cut short, a broken "
                                        "sync word, undecodable messages: said on stderr; what is readable is "
                                        "still listed, copied or written)")
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("info", help="channels, types, message counts and the flight-time span")
    p.add_argument("log")
    p = sub.add_parser("retime", help="copy LOG to OUT with event time stamps = flight time (lcm-logplayer at 1x)")
    p.add_argument("log")
    p.add_argument("out")
    p.add_argument("--speed", type=float, default=1.0, help="replay speed factor (default 1: flight time)")
    p = sub.add_parser("csv", help="the numeric fields of one channel as CSV")
    p.add_argument("log")
    p.add_argument("channel")
    p.add_argument("out")
    a = ap.parse_args(argv)
    rc = 0
    try:
        if a.cmd == "info":
            log = read(a.log)
            for name, ch in sorted(log.items()):
                span = ""
                if "utime" in ch.keys() and len(ch):
                    u = ch["utime"]
                    span = f"  utime {u[0] / 1e6:.3f} .. {u[-1] / 1e6:.3f} s"
                print(f"{name:24s} {ch.type.__name__:18s} {len(ch):8d}{span}")
            for name, n in sorted(log.unknown.items()):
                print(f"{name:24s} {'(unknown type)':18s} {n:8d}")
            rc = _report(a.log, log)
        elif a.cmd == "retime":
            if not (a.speed > 0 and np.isfinite(a.speed)):
                print(f"ggins logtime: --speed {a.speed}: allowed a finite number > 0", file=sys.stderr)
                return 2
            n, nf, cut = retime(a.log, a.out, speed=a.speed)
            print(f"{a.out}: {n} events, {nf} stamped with flight time")
            if cut is not None:
                print(f"ggins logtime: {a.log}: cut short: a partial event at byte {cut}; the {n} complete "
                      f"events before it were copied", file=sys.stderr)
                rc = 4
        else:
            log = read(a.log, channels={a.channel})
            ch = log.get(a.channel)
            if ch is None:
                print(f"ggins logtime: no channel {a.channel} in {a.log}", file=sys.stderr)
                _report(a.log, log)
                return 2
            cols, names = [], []
            for k, v in ch.fields.items():
                if v.dtype.kind in "iuf" and k != "mac":
                    v2 = v.reshape(len(ch), -1)
                    cols.append(v2)
                    names += [k] if v2.shape[1] == 1 else [f"{k}_{i}" for i in range(v2.shape[1])]
            np.savetxt(a.out, np.hstack(cols), delimiter=",", header=",".join(names), comments="", fmt="%.17g")
            rc = _report(a.log, log)
    except BrokenPipeError:  # output piped into head, less
        return 0
    except CorruptLog as e:
        print(f"ggins logtime: {a.log}: corrupt log: {e}", file=sys.stderr)
        return 4
    except (OSError, ValueError) as e:
        print(f"ggins logtime: {e}", file=sys.stderr)
        return 1
    return rc


if __name__ == "__main__":
    sys.exit(main())
