#!/usr/bin/env python3
"""docs/faults.md must still say what the firmware does: the generated matrix table
in it (scripts/fault-matrix, 30 s flights) is compared with the table the reduced
matrix prints now (test_fault_matrix --md, 3 s flights, the same cases).

Compared, row by row (a row: dimension, class, fault kind): the number of cases,
how many were detected, flagged and navigating, the frames rejected, the degraded
modes seen, the result and the geometry note. Not compared: the detection latency
and the errors at the end (|dr| and its ratio to the bound), which depend on the
flight's length. A row added, removed or changed in any compared column fails the
test, naming it: regenerate the document with scripts/fault-matrix.

usage: faults_doc_check.py --matrix PATH/test_fault_matrix --doc docs/faults.md
"""
import argparse
import re
import subprocess
import sys

HEAD = "| dim | class | fault | cases |"


def rows(lines):
    """{(dim, class, fault): {column: value}} of the matrix table in lines."""
    out = {}
    cols = None
    for line in lines:
        line = line.rstrip()
        if line.startswith(HEAD):
            cols = [c.strip() for c in line.strip("|").split(" | ")]
            continue
        if cols is None or not line.startswith("|"):
            if cols is not None and out:
                break  # the end of the table
            continue
        if line.startswith("|---"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
        if len(cells) != len(cols):
            raise ValueError("malformed table row: %s" % line)
        r = dict(zip(cols, cells))
        out[(r["dim"], r["class"], r["fault"])] = r
    return out


def compared(r):
    det = re.match(r"(\d+/\d+)", r["detected (max latency, steps)"])
    return {
        "cases": r["cases"],
        "detected": det.group(1) if det else r["detected (max latency, steps)"],
        "flagged": r["flagged"],
        "degraded modes seen": r["degraded modes seen"],
        "navigating": r["navigating"],
        "frames rejected": r["frames rejected"],
        "result": r["result"],
        "geometry": r["geometry"],
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--matrix", required=True)
    ap.add_argument("--doc", required=True)
    a = ap.parse_args()
    p = subprocess.run([a.matrix, "--md"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    now = rows(p.stdout.splitlines())
    with open(a.doc) as f:
        doc = rows(f.read().splitlines())
    bad = []
    if p.returncode != 0:
        bad.append("test_fault_matrix --md exited %d" % p.returncode)
    if not now:
        bad.append("test_fault_matrix --md printed no table")
    if not doc:
        bad.append("%s has no matrix table" % a.doc)
    for k in sorted(set(now) | set(doc)):
        if k not in doc:
            bad.append("row %s: produced now, missing from %s" % (" / ".join(k), a.doc))
        elif k not in now:
            bad.append("row %s: in %s, no longer produced" % (" / ".join(k), a.doc))
        else:
            cn, cd = compared(now[k]), compared(doc[k])
            for c in cn:
                if cn[c] != cd[c]:
                    bad.append("row %s, %s: document '%s', now '%s'" % (" / ".join(k), c, cd[c], cn[c]))
    # the strapdown GAMMA_ASYM table (printed with the prefix "ASYM "): every row, its
    # expectation, the bits seen and the result (the step counts depend on the flight's length)
    def asym_rows(lines):
        out = {}
        for line in lines:
            if not line.startswith("|") or line.startswith(("|---", "| strapdown case")):
                continue
            c = [x.strip() for x in line.strip().strip("|").split(" | ")]
            if len(c) == 8 and ("silent" in c[1] or "step" in c[1]):
                out[c[0]] = (c[1], c[4], c[7])
        return out
    a_now = asym_rows(l[len("ASYM "):] for l in p.stdout.splitlines() if l.startswith("ASYM |"))
    with open(a.doc) as f:
        a_doc = asym_rows(f.read().splitlines())
    if not a_now:
        bad.append("test_fault_matrix --md printed no strapdown (ASYM) table")
    for k in sorted(set(a_now) | set(a_doc)):
        if a_now.get(k) != a_doc.get(k):
            bad.append("strapdown row '%s': document %s, now %s" % (k, a_doc.get(k), a_now.get(k)))
    print("%d rows now, %d in %s" % (len(now), len(doc), a.doc))
    for b in bad:
        print("FAIL " + b)
    if bad:
        print("docs/faults.md is out of date: regenerate it with scripts/fault-matrix")
        return 1
    print("ok   every row of the document's matrix matches the reduced matrix (columns independent of the flight length)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
