#!/usr/bin/env python3
"""Count the instructions one call of a firmware kernel executes on the Cortex-M7
build under QEMU (called by scripts/m7-qemu-count, which explains the method):
runs the images ggins_m7_qemu<variant>_<n1>.elf and _<n2>.elf with one
instruction per translation block, streams QEMU's exec log through a FIFO
(the logs of the filter images would be gigabytes), maps every executed
address to its mnemonic from the disassembly, and prints (count(n2) -
count(n1)) / (n2 - n1) per call with a single-issue Cortex-M7 cost model."""
import collections, os, re, subprocess, sys, tempfile, threading
# usage: m7count.py <bin dir> <variant> <n1> <n2> <description> <per-what>
bindir, variant, n1, n2, what, per = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5], sys.argv[6]
tmp = tempfile.mkdtemp()

def mix(n):
    elf = f"{bindir}/ggins_m7_qemu{variant}_{n}.elf"
    dis = {}
    out = subprocess.run(["arm-none-eabi-objdump", "-d", elf], capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        m = re.match(r'\s*([0-9a-f]+):\s+(?:[0-9a-f]{4}\s?){1,2}\s+(\S+)', line)
        if m:
            dis[int(m.group(1), 16)] = m.group(2)
    fifo = os.path.join(tmp, f"q{n}.fifo")
    os.mkfifo(fifo)
    addr = collections.Counter()
    def reader():
        # lines like "Trace 0: 0x... [00000000/000012ab/...]": count the block address
        with open(fifo, "rb") as f:
            for line in f:
                i = line.find(b"[")
                if i >= 0:
                    parts = line[i + 1:].split(b"/")
                    if len(parts) > 1:
                        addr[parts[1]] += 1
    t = threading.Thread(target=reader)
    t.start()
    subprocess.run(["timeout", "900", "qemu-system-arm", "-M", "mps2-an500", "-nographic", "-semihosting",
                    "-singlestep", "-d", "exec,nochain", "-D", fifo, "-kernel", elf],
                   stdout=subprocess.DEVNULL, check=True)
    t.join()
    c = collections.Counter()
    for a, k in addr.items():
        c[dis.get(int(a, 16), '?')] += k
    return c

c1, c2 = mix(n1), mix(n2)
dn = n2 - n1
d = {k: (c2[k] - c1[k]) / dn for k in set(c1) | set(c2)}
def cycles(op):  # Cortex-M7 cost model, cycles per instruction (single issue)
    if op.startswith(('vdiv', 'vsqrt')): return 17          # double divide / square root
    if op.startswith(('vmla', 'vmls', 'vfma', 'vfms', 'vnmla', 'vnmls')): return 4
    if op.startswith(('vmul', 'vnmul')): return 2
    if op.startswith(('vldr', 'vstr')): return 2            # 64-bit transfers
    if op.startswith(('vldm', 'vstm', 'vpush', 'vpop')): return 4
    if op.startswith(('ldrd', 'strd', 'ldm', 'stm', 'push', 'pop')): return 2
    if op.startswith('b') and not op.startswith('bic'): return 2
    return 1
n_ins = sum(d.values())
n_cyc = sum(v * cycles(k) for k, v in d.items())
dv = sum(v for k, v in d.items() if k.startswith(('vdiv', 'vsqrt')))
print(f"m7-qemu-count: {n_ins:.0f} Thumb-2 instructions per {what}, {dv:.0f} of them divide/sqrt")
print(f"m7-qemu-count: estimated {n_cyc:.0f} cycles per {per} (single-issue cost model)")
for mhz in (216, 480):
    us = n_cyc / mhz
    print(f"  at {mhz} MHz: {us:.1f} us per {per} ({100 * us / 10000:.2f} % of a 10 ms, 100 Hz step)")
