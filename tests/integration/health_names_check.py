#!/usr/bin/env python3
"""The host's one table of health-bit names (host_tools/lib/hil/frame_names.hpp)
against firmware/include/ggins/frame.h: every GG_HEALTH_* bit of frame.h has
exactly one row, named as its macro, each value a single distinct bit; no row
names a bit frame.h does not define. Both files parsed here as text."""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
frame_h = open(os.path.join(ROOT, "firmware/include/ggins/frame.h")).read()
table = open(os.path.join(ROOT, "host_tools/lib/hil/frame_names.hpp")).read()
defs = {m.group(1): int(m.group(2), 16) for m in re.finditer(r"#define\s+GG_HEALTH_(\w+)\s+(0x[0-9A-Fa-f]+)u", frame_h)}
body = table[table.index("kHealthBits[] = {"):]
body = body[:body.index("};")]
rows = re.findall(r"\{GG_HEALTH_(\w+),\s*\"(\w+)\"\}", body)
fails = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        fails.append(what)


check(len(defs) >= 28, "frame.h defines %d health bits" % len(defs))
macros = [m for m, _ in rows]
check(len(macros) == len(set(macros)), "no bit named twice in the table")
for m, v in sorted(defs.items(), key=lambda kv: kv[1]):
    check(m in macros, "GG_HEALTH_%s (0x%08x) has a row" % (m, v))
for m, n in rows:
    check(m in defs, "row GG_HEALTH_%s is a bit of frame.h" % m)
    check(m == n, "row GG_HEALTH_%s is named %s" % (m, n))
vals = list(defs.values())
check(all(v and v & (v - 1) == 0 for v in vals) and len(vals) == len(set(vals)),
      "every frame.h health value is one bit, all distinct")
print("%d failure(s)" % len(fails))
sys.exit(1 if fails else 0)
