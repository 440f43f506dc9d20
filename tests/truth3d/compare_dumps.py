#!/usr/bin/env python3
"""Compares two truth3d_dump outputs value by value (exact decimal arithmetic):
largest difference and how many printed values are identical, per quantity.
   compare_dumps.py BEFORE AFTER"""
import sys
from decimal import Decimal

NAMES = ["G_e"] * 3 + ["Gamma_e"] * 9 + ["f_b"] * 3 + ["accelerometers"] * 18


def main(a, b):
    la, lb = open(a).read().split("\n"), open(b).read().split("\n")
    la, lb = [l.split() for l in la if l], [l.split() for l in lb if l]
    if len(la) != len(lb):
        print(f"different frame counts: {len(la)} vs {len(lb)}")
        return 1
    st = {}
    for x, y in zip(la, lb):
        if x[0] != y[0]:
            print(f"different steps: {x[0]} vs {y[0]}")
            return 1
        for i, (u, v) in enumerate(zip(x[1:], y[1:])):
            s = st.setdefault(NAMES[i], [Decimal(0), Decimal(0), 0, 0])
            s[0] = max(s[0], abs(Decimal(u) - Decimal(v)))
            s[1] = max(s[1], abs(Decimal(u)))
            s[2] += u == v
            s[3] += 1
    print(f"{len(la)} frames")
    for n, s in st.items():
        print(f"  {n:15s} max |difference| {float(s[0]):.2e} (largest |value| {float(s[1]):.2e}); identical {s[2]}/{s[3]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
