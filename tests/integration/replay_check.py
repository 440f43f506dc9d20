#!/usr/bin/env python3
"""Replay integration tests: `ggins replay` must reproduce a clean run's log bit
for bit (exit 0), and must refuse, with a nonzero exit and a message naming the
problem, every log that is not the whole record of the run.

  corrupt-2d   a short 2-D run with transport faults (ggins-run -> hal_sim); the
               clean log replays bit-exact; copies of it are damaged the ways a
               disk, a copy or a hand can damage them (truncated at 50 % and 90 %,
               cut at an event boundary, an event header corrupted, an event length
               of 0x7fffffff, one output removed, undecodable or added, the START
               message removed) and each must fail with the documented exit code.
  3d           short 3-D runs (ggins run3d -> hal_sim 3-D mode), stabilized and
               strapdown: bit-exact replay; damaged copies fail as in 2-D.
  fields-2d,   one bit flipped in each field of one output, in turn: every field
  fields-3d    but cycles[] and republished must be reported as a mismatch under its
               own name. The field list is read from lcmtypes/*.lcm here (independent
               of the replay's own table).

The damage is done by an independent reader/writer of the LCM event log format
(big-endian: sync 0xEDA1DA01, event number i64, timestamp i64, channel length i32,
data length i32, channel, data). Only the Python standard library is used.

usage: replay_check.py TEST --ggins-replay PATH [--ggins-run PATH] [--ggins-run3d PATH] --workdir DIR
"""
import argparse
import os
import re
import shutil
import struct
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
LCMTYPES = os.path.join(HERE, "..", "..", "lcmtypes")
sys.path.insert(0, HERE)
import hil_check as H  # noqa: E402  (runner, check)
from hil_check import check  # noqa: E402

SYNC = 0xEDA1DA01
# exit codes of ggins replay (ggins replay --help, docs/robustness.md)
EXACT, DIFFERENT, UNREADABLE, NOTHING, CORRUPT, INCOMPLETE = 0, 1, 2, 3, 4, 5


# ---- LCM event log, independently ------------------------------------------------------
class Ev:
    def __init__(self, off, num, ts, ch, data):
        self.off, self.num, self.ts, self.ch, self.data = off, num, ts, ch, data


def parse(raw):
    evs, pos = [], 0
    while pos < len(raw):
        sync, num, ts, clen, dlen = struct.unpack_from(">IqqiI", raw, pos)
        assert sync == SYNC, "the test's own log is not clean at %d" % pos
        ch = raw[pos + 28:pos + 28 + clen].decode()
        evs.append(Ev(pos, num, ts, ch, bytes(raw[pos + 28 + clen:pos + 28 + clen + dlen])))
        pos += 28 + clen + dlen
    return evs


def serialize(evs, renumber=True):
    out = bytearray()
    for i, e in enumerate(evs):
        ch = e.ch.encode()
        out += struct.pack(">IqqiI", SYNC, i if renumber else e.num, e.ts, len(ch), len(e.data)) + ch + e.data
    return bytes(out)


# ---- message layout, from the .lcm files (LCM encodes the fields in order, no padding,
# after an 8-byte fingerprint) ------------------------------------------------------------
SIZES = {"int8_t": 1, "byte": 1, "int16_t": 2, "int32_t": 4, "int64_t": 8, "float": 4, "double": 8}


def layout(lcm_name):
    """[(name, type, offset, element count)] of the non-constant fields of lcmtypes/<lcm_name>.lcm."""
    text = open(os.path.join(LCMTYPES, lcm_name + ".lcm")).read()
    body = text[text.index("{") + 1:text.rindex("}")]
    fields, off = [], 8
    for line in body.splitlines():
        line = line.split("//")[0].strip()
        m = re.match(r"^(\w+)\s+(\w+)((?:\[\d+\])*)\s*;$", line)
        if not m:
            continue
        typ, name, dims = m.group(1), m.group(2), [int(d) for d in re.findall(r"\[(\d+)\]", m.group(3))]
        n = 1
        for d in dims:
            n *= d
        fields.append((name, typ, off, n, dims))
        off += SIZES[typ] * n
    return fields


def field_off(lay, name):
    return [f for f in lay if f[0] == name][0][2]


def seq_of(e, lay):
    return struct.unpack_from(">q", e.data, field_off(lay, "seq"))[0]


def set_i64(data, off, v):
    b = bytearray(data)
    struct.pack_into(">q", b, off, v)
    return bytes(b)


# ---- outputs alone (GGINS_NAV*) or as items of output batches (GGINS_NAV*S) -----------------
# A record is (event index, base): field F of the output is at data[base + offset of F].
def records(evs, nav_ch):
    return H.log_records([(e.ch, e.data) for e in evs], nav_ch, nav_ch + "S")


def rec_i64(evs, r, off):
    return struct.unpack_from(">q", evs[r[0]].data, r[1] + off)[0]


def rec_item(evs, r):
    """The bytes of the record's output (a standalone message's data; a batch item's bytes)."""
    i, base = r
    if base == 0:
        return None
    for off, size in H.batch_items(evs[i].data):
        if off - 8 == base:
            return evs[i].data[off:off + size]
    raise AssertionError("no item at %d" % base)


def batch_of(template, items):
    """A batch message with the header and MAC bytes of `template` holding `items`."""
    head = bytearray(template[:H.BATCH_HEAD])
    struct.pack_into(">i", head, 32, len(items))
    return bytes(head) + b"".join(items) + template[len(template) - H.BATCH_MAC:]


def without_seq(evs, nav_lay, nav_ch, k):
    """The log without any output of seq k (messages dropped, batch items removed)."""
    out, so = [], field_off(nav_lay, "seq")
    for e in evs:
        if e.ch == nav_ch and struct.unpack_from(">q", e.data, so)[0] == k:
            continue
        if e.ch == nav_ch + "S":
            items = [e.data[o:o + n] for o, n in H.batch_items(e.data)]
            keep = [it for it in items if struct.unpack_from(">q", it, so - 8)[0] != k]
            if len(keep) != len(items):
                if keep:
                    out.append(Ev(0, 0, e.ts, e.ch, batch_of(e.data, keep)))
                continue
        out.append(e)
    return out


def isolated(evs, nav_lay, nav_ch, k):
    """The log with every batch that holds output k split in three (items before,
    output k alone, items after): [events], [indices of the events holding k alone]."""
    out, alone, so = [], [], field_off(nav_lay, "seq")
    for e in evs:
        if e.ch == nav_ch + "S":
            items = [e.data[o:o + n] for o, n in H.batch_items(e.data)]
            idx = [j for j, it in enumerate(items) if struct.unpack_from(">q", it, so - 8)[0] == k]
            if idx:
                j = idx[0]
                if j > 0:
                    out.append(Ev(0, 0, e.ts, e.ch, batch_of(e.data, items[:j])))
                alone.append(len(out))
                out.append(Ev(0, 0, e.ts, e.ch, batch_of(e.data, [items[j]])))
                if j + 1 < len(items):
                    out.append(Ev(0, 0, e.ts, e.ch, batch_of(e.data, items[j + 1:])))
                continue
        if e.ch == nav_ch and struct.unpack_from(">q", e.data, so)[0] == k:
            alone.append(len(out))
        out.append(e)
    return out, alone


def copy_of(evs, r, nav_lay, seq=None):
    """A new event holding a copy of record r's output (seq patched if given)."""
    e = evs[r[0]]
    item = rec_item(evs, r)
    if item is None:
        d = e.data
        if seq is not None:
            d = set_i64(d, field_off(nav_lay, "seq"), seq)
        return Ev(0, 0, e.ts, e.ch, d)
    if seq is not None:
        item = set_i64(item, field_off(nav_lay, "seq") - 8, seq)
    return Ev(0, 0, e.ts, e.ch, batch_of(e.data, [item]))


# ---- running replay ---------------------------------------------------------------------
def replay(a, log, *extra):
    cmd = [a.ggins_replay, log, "--show", "5"] + list(extra)
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    return p.returncode, p.stdout.replace(log, "<log>")  # the file name must not match the words looked for


def expect(a, name, raw, code, words):
    path = os.path.join(a.workdir, name + ".lcmlog")
    with open(path, "wb") as f:
        f.write(raw)
    rc, out = replay(a, path)
    print("--- %s: exit %d\n%s" % (name, rc, "\n".join("    " + ln for ln in out.rstrip().splitlines()[-8:])))
    ok = rc == code and rc >= 0
    check(ok, "%s: exit %d (got %d)" % (name, code, rc))
    for w in words:
        ok = (w in out) and ok
        check(w in out, "%s: the message names the problem (%r)" % (name, w))
    if ok:
        os.remove(path)  # kept when a check failed
    return out


def not_boundary(evs, cut):
    starts = {e.off for e in evs}
    while cut in starts:
        cut += 1
    return cut


def damage_cases(a, raw, nav_ch, nav_lay, n, prefix):
    """Damaged copies of a clean log of an n-step run: each must fail, named."""
    evs = parse(raw)
    so = field_off(nav_lay, "seq")
    navs = records(evs, nav_ch)
    k = 567 if n > 600 else n // 2
    of_k = [r for r in navs if rec_i64(evs, r, so) == k]
    check(len(of_k) >= 1, "%s: the log has the output of seq %d (%d copies)" % (prefix, k, len(of_k)))
    mid = evs[len(evs) * 2 // 5]

    for pct in (50, 90):
        cut = not_boundary(evs, len(raw) * pct // 100)
        expect(a, "%s-truncated-%d" % (prefix, pct), raw[:cut], CORRUPT, ["truncated"])
    # a cut inside an event header
    cut = evs[len(evs) * 3 // 5].off + 10
    expect(a, prefix + "-truncated-in-header", raw[:cut], CORRUPT, ["truncated", "fewer than an event header"])
    # a cut exactly between two events: the framing is intact, the run is not
    cut = evs[len(evs) * 7 // 10].off
    expect(a, prefix + "-cut-at-event", raw[:cut], INCOMPLETE, ["missing", "of the %d steps" % n])

    b = bytearray(raw)
    b[mid.off + 1] ^= 0x40  # one bit of the sync word
    expect(a, prefix + "-header-sync", bytes(b), CORRUPT, ["sync word", "byte %d" % mid.off])
    b = bytearray(raw)
    struct.pack_into(">i", b, mid.off + 24, 0x7FFFFFFF)  # data length
    expect(a, prefix + "-length-7fffffff", bytes(b), CORRUPT, ["data length 2147483647", "byte %d" % mid.off])
    b = bytearray(raw)
    struct.pack_into(">i", b, mid.off + 20, struct.unpack_from(">i", b, mid.off + 20)[0] + 3)  # channel length
    expect(a, prefix + "-header-channel-length", bytes(b), CORRUPT, ["corrupt event header"])
    b = bytearray(raw)
    struct.pack_into(">i", b, mid.off + 20, 0)
    expect(a, prefix + "-channel-length-0", bytes(b), CORRUPT, ["channel length 0", "byte %d" % mid.off])

    drop = without_seq(evs, nav_lay, nav_ch, k)
    expect(a, prefix + "-output-dropped", serialize(drop), INCOMPLETE, ["missing", "seq %d" % k])
    holding_k = {r[0] for r in of_k}
    drop_nr = [e for i, e in enumerate(evs) if i not in holding_k]
    expect(a, prefix + "-output-dropped-not-renumbered", serialize(drop_nr, renumber=False), CORRUPT,
           ["event numbers"])

    und, alone = isolated(evs, nav_lay, nav_ch, k)
    for i in alone:
        d = bytearray(und[i].data)
        d[0] ^= 0xFF  # fingerprint: the payload no longer decodes as the output type
        und[i] = Ev(0, 0, und[i].ts, und[i].ch, bytes(d))
    expect(a, prefix + "-output-undecodable", serialize(und), INCOMPLETE, ["undecodable", "seq %d" % k])

    last = max(navs, key=lambda r: rec_i64(evs, r, so))
    extra = list(evs)
    extra.insert(last[0] + 1, copy_of(evs, last, nav_lay, seq=n))
    expect(a, prefix + "-output-extra-beyond-n", serialize(extra), INCOMPLETE, ["extra", "seq %d" % n])

    rep = field_off(nav_lay, "republished")
    first = [r for r in navs if evs[r[0]].data[r[1] + rep] == 0 and rec_i64(evs, r, so) > k]
    check(len(first) > 0, "%s: an output published once as a first publication" % prefix)
    extra, ks = list(evs), rec_i64(evs, first[0], so)
    extra.insert(first[0][0] + 1, copy_of(evs, first[0], nav_lay))
    expect(a, prefix + "-output-extra-copy", serialize(extra), INCOMPLETE, ["extra", "seq %d" % ks])

    cmd = field_off(layout("run_control_t"), "command")
    ctl = [e for e in evs if not (e.ch == "GGINS_CONTROL" and struct.unpack_from(">i", e.data, cmd)[0] == 1)]
    check(len(ctl) < len(evs), "%s: the log has a START message" % prefix)
    expect(a, prefix + "-start-removed", serialize(ctl), INCOMPLETE, ["START"])
    # a START that promises 2^62 steps: named, and in no time (the gaps are counted, not walked)
    nst = field_off(layout("run_control_t"), "n_steps")
    big = [Ev(0, 0, e.ts, e.ch, set_i64(e.data, nst, 1 << 62))
           if e.ch == "GGINS_CONTROL" and struct.unpack_from(">i", e.data, cmd)[0] == 1 else e for e in evs]
    expect(a, prefix + "-start-n-steps-2e62", serialize(big), INCOMPLETE,
           ["outputs missing: %d of the %d steps" % ((1 << 62) - n, 1 << 62)])


def field_cases(a, raw, nav_ch, nav_lay, prefix):
    """One bit of one field of one output flipped, field by field."""
    evs = parse(raw)
    so = field_off(nav_lay, "seq")
    navs = records(evs, nav_ch)
    k = rec_i64(evs, navs[len(navs) // 2], so)
    of_k = [r for r in navs if rec_i64(evs, r, so) == k]
    skip = {"cycles", "republished", "mac"}  # not reproducible: timing and transport (replay has no key)
    renamed = {"seq", "run_id"}            # the output then belongs to another step or run
    for name, typ, off, cnt, dims in nav_lay:
        el = cnt - 1  # the last element of an array
        eoff = off + SIZES[typ] * el
        byte = eoff + SIZES[typ] - 1  # big-endian: the least significant byte
        ev = list(evs)
        for i, base in of_k:
            d = bytearray(ev[i].data)
            d[base + byte] ^= 1
            ev[i] = Ev(0, 0, ev[i].ts, ev[i].ch, bytes(d))
        path = os.path.join(a.workdir, "%s-flip-%s.lcmlog" % (prefix, name))
        with open(path, "wb") as f:
            f.write(serialize(ev))
        rc, out = replay(a, path)
        label = name
        if len(dims) == 1:
            label += "[%d]" % el
        elif len(dims) == 2:
            label += "[%d][%d]" % divmod(el, dims[1])
        if name in skip:
            check(rc == EXACT, "%s: %s flipped in seq %d: not compared, exit 0 (got %d)" % (prefix, label, k, rc))
        elif name in renamed:
            check(rc != EXACT, "%s: %s flipped in seq %d: refused (exit %d)" % (prefix, label, k, rc))
        else:
            check(rc == DIFFERENT and ("MISMATCH seq %d %s:" % (k, label)) in out,
                  "%s: %s flipped in seq %d: exit 1, MISMATCH seq %d %s (got %d)" % (prefix, label, k, k, label, rc))
        os.remove(path)


def clean(a, log, n, what):
    rc, out = replay(a, log, "--json", log + ".json")
    print(out.rstrip())
    check(rc == EXACT, "%s: clean log bit-exact, exit 0 (got %d)" % (what, rc))
    check("BIT-EXACT (%d outputs, every step of the run" % n in out, "%s: all %d outputs compared" % (what, n))


# ---- tests ------------------------------------------------------------------------------
def run2d(a, name, duration, transport=True):
    sys.path.insert(0, HERE)
    import robustness_check as R
    os.makedirs(a.workdir, exist_ok=True)
    sc = os.path.join(a.workdir, name + ".toml")
    faults = [{"kind": "nan", "sensor": 3, "axis": "z", "start_s": 2.0, "prob": 0.05},
              {"kind": "step", "sensor": 2, "axis": "x", "start_s": 4.0, "size": 1e-9}]
    extra = ("[transport]\nseed = 5\ndrop_prob = 0.05\nduplicate_prob = 0.05\nreorder_prob = 0.05\n"
             "output_drop_prob = 0.05\ngarbage_prob = 0.05\n") if transport else ""
    with open(sc, "w") as f:
        f.write(R.scenario(name, faults, duration=duration, extra=extra))
    out = os.path.join(a.workdir, name)
    # exit 0, or 4 when the run reports itself degraded: either way its log is a record to replay
    p = H.run(a.ggins_run, out, "--scenario", sc, "--no-plots", "--resend-timeout-ms", "10", check_rc=False)
    check(p.returncode in (0, 4), "ggins run: the run completed (exit %d)" % p.returncode)
    log = os.path.join(out, "run.lcmlog")
    return log, int(round(duration * 100)) + 1


def run3d(a, name, scenario, duration, *extra):
    os.makedirs(a.workdir, exist_ok=True)
    out = os.path.join(a.workdir, name)
    if os.path.exists(out):
        shutil.rmtree(out)
    cmd = [a.ggins_run3d, "--out", out, "--no-plots", "-q", "--scenario", scenario, "--duration", str(duration)]
    cmd += list(extra)
    print("$ " + " ".join(cmd))
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    print(p.stdout.rstrip())
    check(p.returncode == 0, "ggins run3d %s: exit 0 (got %d)" % (scenario, p.returncode))
    return os.path.join(out, "run.lcmlog"), int(round(duration * 100)) + 1


def test_corrupt_2d(a):
    log, n = run2d(a, "run2d", 10.0)
    clean(a, log, n, "2-D with transport faults")
    with open(log, "rb") as f:
        raw = f.read()
    damage_cases(a, raw, "GGINS_NAV", layout("nav_output_t"), n, "2d")
    rc, out = replay(a, os.path.join(a.workdir, "run2d.toml"))
    check(rc == UNREADABLE and "not an LCM event log" in out, "a file that is not an LCM log: exit 2 (got %d)" % rc)


# transport faults of `ggins run` (the same options on `ggins run3d`, where it has them)
TRANSPORT = [("--drop-prob", "0.05"), ("--dup-prob", "0.05"), ("--reorder-prob", "0.05"),
             ("--drop-output-prob", "0.05"), ("--garbage-prob", "0.05")]


def test_3d(a):
    lay = layout("nav3d_output_t")
    for name, scenario, duration in (("stab", "3d-stabilized-1h", 10.0), ("strap", "3d-strapdown-1h", 20.0)):
        log, n = run3d(a, name, scenario, duration)
        clean(a, log, n, "3-D " + scenario)
    helptext = subprocess.run([a.ggins_run3d, "--help"], stdout=subprocess.PIPE, text=True).stdout
    opts = [x for o in TRANSPORT if o[0] in helptext for x in o]
    if opts:
        flog, fn = run3d(a, "strap-transport", "3d-strapdown-1h", 10.0, *opts, "--resend-timeout-ms", "10")
        clean(a, flog, fn, "3-D with transport faults " + " ".join(opts))
    else:
        print("note: ggins run3d has none of the transport fault options %s: no 3-D fault replay"
              % " ".join(o[0] for o in TRANSPORT))
    with open(log, "rb") as f:
        raw = f.read()
    damage_cases(a, raw, "GGINS_NAV3D", lay, n, "3d")


def test_fields(a, dim):
    if dim == "2d":
        log, _ = run2d(a, "run2d", 3.0, transport=False)
        ch, lay = "GGINS_NAV", layout("nav_output_t")
    else:
        log, _ = run3d(a, "strap", "3d-strapdown-1h", 3.0)
        ch, lay = "GGINS_NAV3D", layout("nav3d_output_t")
    with open(log, "rb") as f:
        raw = f.read()
    clean(a, log, 301, dim)
    field_cases(a, raw, ch, lay, dim)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("test", choices=["corrupt-2d", "3d", "fields-2d", "fields-3d"])
    ap.add_argument("--ggins-replay", required=True)
    ap.add_argument("--ggins-run")
    ap.add_argument("--ggins-run3d")
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    if a.test == "corrupt-2d":
        test_corrupt_2d(a)
    elif a.test == "3d":
        test_3d(a)
    else:
        test_fields(a, a.test[-2:])
    if H.FAILURES:
        print("FAILED: %d check(s)" % len(H.FAILURES))
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
