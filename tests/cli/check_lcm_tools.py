#!/usr/bin/env python3
"""LCM tools of ggins, checked as a user meets them.

  check_lcm_tools.py example SRC BIN PYTYPES   docs/lcm-tools.md's Python example, as written there,
                                               on a 5 s `ggins run`; plus the reader on a hand-made log
  check_lcm_tools.py retime  SRC BIN PYTYPES   `ggins logtime retime`: flight-time stamps, lcm-logplayer
                                               takes the flight time / speed
  check_lcm_tools.py spy     SRC BIN PYTYPES N `ggins spy` under Xvfb with Java 17 loads the N generated types
"""
import os
import re
import subprocess
import struct
import sys
import tempfile
import time

mode, src, bindir, pytypes = sys.argv[1:5]
sys.path.insert(0, os.path.join(src, "host_tools", "lib", "python"))
os.environ["GGINS_LCMTYPES_PYTHON"] = pytypes
os.environ["PYTHONPATH"] = os.path.join(src, "host_tools", "lib", "python")
tmp = tempfile.mkdtemp(prefix="ggins-lcm-")
failures = []
passes = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    (passes if cond else failures).append(what)


def fly(folder, seconds=5):
    r = subprocess.run([os.path.join(bindir, "ggins"), "run", "--duration", str(seconds), "--no-plots", "-o", folder],
                       capture_output=True, text=True, timeout=90)
    if r.returncode != 0:
        print(r.stdout[-2000:], r.stderr[-2000:])
        sys.exit(f"ggins run failed with exit {r.returncode}")


def finish():
    print(f"{len(passes)} passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)


if mode == "example":
    import numpy as np
    import ggins_log
    # 1. the reader on a hand-made log: known values of a generated type, a message of
    #    no known type, a truncated last event
    types = ggins_log.load_types()
    cls = next(c for c in types.values() if c.__name__ == "nav_output_t")
    events = []
    for k in range(3):
        m = cls()
        m.utime, m.seq, m.status = 10000 * k, k, 0
        m.r_i = [1.5 * k, -2.0, 3.25]
        m.gamma_i = [[k, 0.0, 1.0], [0.0, 2.0, 0.0], [1.0, 0.0, -k]]
        m.mac = bytes(range(32))
        events.append(ggins_log.Event(k, 1000 + k, "NAV_TEST", m.encode()))
    events.append(ggins_log.Event(3, 1003, "OTHER", b"\x01" * 8 + b"payload"))
    path = os.path.join(tmp, "hand.lcmlog")
    with open(path, "wb") as f:
        ggins_log.write_events(f, events)
        f.write(b"\xed\xa1\xda\x01" + b"\x00" * 10)  # a cut-off event header
    log = ggins_log.read(path)
    nav = log["NAV_TEST"]
    check(len(nav) == 3 and nav.type is cls, "hand-made log: 3 nav_output_t messages found by fingerprint")
    check(np.array_equal(nav["r_i"], np.array([[0, -2, 3.25], [1.5, -2, 3.25], [3.0, -2, 3.25]])), "r_i decoded as (3, 3)")
    check(nav["gamma_i"].shape == (3, 3, 3) and nav["gamma_i"][2, 2, 2] == -2.0, "gamma_i decoded as (3, 3, 3)")
    check(nav["mac"].shape == (3, 32) and nav["mac"][1, 31] == 31, "mac as uint8 (n, 32)")
    check(list(nav.event_utime) == [1000, 1001, 1002], "event time stamps")
    check(log.unknown == {"OTHER": 1}, "an unknown fingerprint is counted, not decoded")
    size = os.path.getsize(path)
    check(log.truncated_at == size - 14 and log.events == 4 and any("cut short" in p for p in log.problems()),
          f"the cut-off event is reported: truncated_at {log.truncated_at} (the file's last 14 bytes start at "
          f"{size - 14}), {log.events} events, problems {log.problems()}")
    bad = cls()
    bad.r_i, bad.gamma_i, bad.mac = [0.0] * 3, [[0.0] * 3] * 3, bytes(32)
    with open(path, "wb") as f:
        ggins_log.write_events(f, [ggins_log.Event(0, 1, "NAV_TEST", bad.encode()[:20])])
    log = ggins_log.read(path)
    check(log.undecodable == {"NAV_TEST": 1} and not log.unknown and log.problems(),
          "a message of a known type that does not decode is counted as undecodable, not unknown")
    # 2. the doc's example, as written, on a real 5 s run
    doc = open(os.path.join(src, "docs", "lcm-tools.md")).read()
    m = re.search(r"<!-- ctest: lcm.python_example -->\s*```python\n(.*?)```", doc, re.S)
    check(m is not None, "docs/lcm-tools.md has the marked example")
    if m:
        fly(os.path.join(tmp, "out", "lcm-example"))
        r = subprocess.run(["/usr/bin/python3", "-c", m.group(1)], cwd=tmp, capture_output=True, text=True, timeout=60)
        print(r.stdout, r.stderr)
        check(r.returncode == 0 and "final position error" in r.stdout, "the example runs and agrees with summary.json")
    finish()

if mode == "retime":
    import numpy as np
    import ggins_log
    run = os.path.join(tmp, "run")
    fly(run)
    src_log = os.path.join(run, "run.lcmlog")
    dst_log = os.path.join(tmp, "flight.lcmlog")
    r = subprocess.run([os.path.join(bindir, "ggins"), "logtime", "retime", src_log, dst_log], capture_output=True, text=True)
    print(r.stdout, r.stderr)
    check(r.returncode == 0, "ggins logtime retime exits 0")
    # logs that are not whole: exit 4 (corrupt log) with the reason, what is readable still read
    logtime = [os.path.join(bindir, "ggins"), "logtime"]
    whole = open(src_log, "rb").read()
    # the first event's header: sync 0..3, eventnum 4..11, time 12..19, channel length 20..23,
    # data length 24..27; the second event starts after its channel and data
    second = 28 + sum(struct.unpack(">ii", whole[20:28]))
    r = subprocess.run(logtime + ["info", src_log], capture_output=True, text=True)
    check(r.returncode == 0 and "GGINS_FRAME" in r.stdout and not r.stderr, f"info on the run's log: exit {r.returncode}")
    cases = {"empty": b"", "two bytes of text": b"x\n", "cut at 60 %": whole[:len(whole) * 6 // 10],
             "a broken sync word": whole[:second] + b"\x00" + whole[second + 1:],
             "a data length of 0x7fffffff": whole[:24] + b"\x7f\xff\xff\xff" + whole[28:]}
    for what, data in cases.items():
        bad = os.path.join(tmp, "bad.lcmlog")
        open(bad, "wb").write(data)
        r = subprocess.run(logtime + ["info", bad], capture_output=True, text=True, timeout=60)
        check(r.returncode == 4 and "ggins logtime: " in r.stderr,
              f"info on a log with {what}: exit {r.returncode} (want 4), {r.stderr.strip()[:160]!r}")
    cut = os.path.join(tmp, "cut.lcmlog")
    open(cut, "wb").write(whole[:len(whole) * 6 // 10])
    r = subprocess.run(logtime + ["csv", cut, "GGINS_FRAME", os.path.join(tmp, "cut.csv")], capture_output=True, text=True)
    rows = len(open(os.path.join(tmp, "cut.csv")).read().splitlines()) - 1 if os.path.exists(os.path.join(tmp, "cut.csv")) else 0
    check(r.returncode == 4 and "cut short" in r.stderr and rows > 0,
          f"csv of a log cut short: exit {r.returncode}, {rows} rows of the complete events written, the cut reported")
    r = subprocess.run(logtime + ["retime", cut, os.path.join(tmp, "cut-retimed.lcmlog")], capture_output=True, text=True)
    check(r.returncode == 4 and "cut short" in r.stderr, f"retime of a log cut short: exit {r.returncode}, the cut reported")
    a, b = ggins_log.read(src_log), ggins_log.read(dst_log)
    fa = a["GGINS_FRAME"]  # every frame, batched or not
    check(abs((fa["utime"][-1] - fa["utime"][0]) * 1e-6 - 5.0) < 1e-9, "the log holds the 5 s of frames")
    # the events that carry frames (batches of frames in lockstep): each retimed event is
    # stamped with the sample time of the last frame it carries (when the batch can exist)
    ea = ggins_log.read(src_log, unbatch=False)
    eb = ggins_log.read(dst_log, unbatch=False)
    ch = "GGINS_FRAMES" if "GGINS_FRAMES" in ea else "GGINS_FRAME"
    last = np.array([ggins_log.batch_items(m)[-1].utime if ggins_log.batch_items(m) else m.utime
                      for m in ea[ch].messages], dtype=np.int64)
    wall_span = (ea[ch].event_utime[-1] - ea[ch].event_utime[0]) * 1e-6
    flight_span = (eb[ch].event_utime[-1] - eb[ch].event_utime[0]) * 1e-6
    print(f"{ch}: {len(last)} events; wall-time stamps span {wall_span:.3f} s, retimed {flight_span:.3f} s, "
          f"flight {(last[-1] - last[0]) * 1e-6:.3f} s to the last event's last frame")
    check(abs(flight_span - (last[-1] - last[0]) * 1e-6) < 1e-9 and flight_span > 4.0,
          "retimed frame events span the flight")
    check(np.array_equal(eb[ch].event_utime - eb[ch].event_utime[0], last - last[0]),
          "each frame event's stamp = the sample time of its last frame (relative)")
    with open(src_log, "rb") as f1, open(dst_log, "rb") as f2:
        e1, e2 = list(ggins_log.read_events(f1)), list(ggins_log.read_events(f2))
    check(len(e1) == len(e2) and all(x.data == y.data and x.channel == y.channel for x, y in zip(e1, e2)),
          "every message is kept, byte for byte, in its place")
    check(all(e2[i].timestamp <= e2[i + 1].timestamp for i in range(len(e2) - 1)), "stamps never decrease")
    url = "udpm://239.255.76.67:7699?ttl=0"
    def play(path, speed):
        t0 = time.monotonic()
        subprocess.run(["lcm-logplayer", "-s", str(speed), "-l", url, path], capture_output=True, timeout=60, check=True)
        return time.monotonic() - t0
    t_wall, t_flight = play(src_log, 10), play(dst_log, 10)
    print(f"lcm-logplayer --speed 10: wall-stamped log {t_wall:.2f} s, retimed log {t_flight:.2f} s (flight 5 s / 10)")
    check(0.45 <= t_flight <= 1.5, "the retimed log plays in flight time / speed")
    finish()

if mode == "spy":
    n = int(sys.argv[5])
    p = subprocess.Popen(["xvfb-run", "-a", os.path.join(bindir, "ggins"), "spy", "--lcm-url=udpm://239.255.76.67:7698?ttl=0"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        out, _ = p.communicate(timeout=12)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, 15)
        out, _ = p.communicate()
    print(out)
    check(f"Found {n} LCM types" in out, f"lcm-spy found the {n} generated types")
    check("Unrecognized option" not in out and "Could not create the Java Virtual Machine" not in out, "Java 17 starts it")
    finish()
