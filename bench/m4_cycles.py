#!/usr/bin/env python3
"""Cortex-M4F cycles of solve_constrained (float, five hard fingers), from an instruction trace.

Usage: python3 bench/m4_cycles.py [build-dir] [instances]   (defaults: build/m4-cycles, 24)

Builds bench/m4_cycles.cpp with Debian's arm-linux-gnueabihf-g++ (GCC 12, as the embedded
check's arm-none-eabi-g++) and the embedded check's flags, cmake/embedded.flags (Cortex-M4,
FPv4-SP, hard float, -Os, EIGEN_UNROLLING_LIMIT=0; GRIP_M4_OPT=-O2 replaces -Os), runs it
under qemu-arm with its translation and execution logs, and
prices every instruction executed between m4_begin() and m4_end() with the Cortex-M4 cycle
counts of ARM's Technical Reference Manual (integer core and FPU tables): an estimate, not a
measurement on silicon. Assumed: no flash wait states, a taken branch refills the pipeline in
2 cycles (the manual's 1 to 3), neighbouring loads and stores pipeline to one cycle after the
first. The C library's memcpy and memset run as glibc's (one cycle per instruction).

Prints the cost of a solve as the benchmark's deadline model (bench_constrained Deadline):
T <= T_fixed + max_passes * T_pass, and the cycles of the fast path and of solves without a
deadline.
"""
import os
import re
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The embedded check's target and code flags (one file for both), with the optimisation level
# replaceable by GRIP_M4_OPT (e.g. -O2) to compare.
with open(os.path.join(ROOT, 'cmake', 'embedded.flags')) as _f:
    FLAGS = [os.environ.get('GRIP_M4_OPT', '-Os') if f == '-Os' else f for f in _f.read().split()]
FLAGS += ['-I' + os.path.join(ROOT, 'include'), '-isystem', '/usr/include/eigen3']
TAKEN_REFILL = 2

# Cycles per instruction, Cortex-M4 TRM (integer core and FPU tables), by mnemonic with an
# optional condition code (the width or type suffix, ".w" or ".f32", is dropped first).
COND = r'(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?'
PRICES = [(re.compile(p + COND + '$'), c) for p, c in [
    (r'^v(div|sqrt)', 14),
    (r'^v(n?ml[as]|fn?m[as])', 3),  # multiply-accumulate, fused or not
    (r'^(ldr|str)d', 3),
    (r'^(mla|mls)', 2),
    (r'^[su]div', 7),  # 2 to 12
    (r'^tb[bh]', 2),
]]
MEMORY = re.compile(r'^(v?ldr|v?str)(b|h|sb|sh|ex|exb|exh)?' + COND + '$')
MULTI = re.compile(r'^(v?ldm|v?stm)(ia|db|fd|ea)?' + COND + '$|^v?(push|pop)' + COND + '$')
BRANCH = re.compile(r'^(b|bl|blx|bx|cbz|cbnz|tbb|tbh)' + COND + '$')


def price(mnemonic, operands, previous_memory):
    """Cycles of one instruction (a taken branch's refill is added by the caller), and whether
    it is a single load or store (the next one then pipelines to one cycle)."""
    m = mnemonic.split('.')[0]
    for pattern, cycles in PRICES:
        if pattern.match(m):
            return cycles, False
    if MULTI.match(m):
        regs = re.search(r'\{([^}]*)\}', operands)
        words = sum(2 if r.strip().startswith('d') else 1 for r in regs.group(1).split(',')) if regs else 1
        return 1 + words + (TAKEN_REFILL if 'pc' in operands else 0), False
    if MEMORY.match(m):
        return (1 if previous_memory else 2), True
    return 1, False


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, 'build', 'm4-cycles')
    count = sys.argv[2] if len(sys.argv) > 2 else '24'
    os.makedirs(out, exist_ok=True)
    obj, exe, log = (os.path.join(out, f) for f in ('m4_cycles.o', 'm4_cycles', 'qemu.fifo'))
    cxx = 'arm-linux-gnueabihf-g++'
    subprocess.run([cxx] + FLAGS + ['-c', os.path.join(ROOT, 'bench', 'm4_cycles.cpp'), '-o', obj], check=True)
    # The C library is built for the A profile; the object's M-profile attributes would stop the
    # link, and the code (Thumb-2 with VFP) runs as it is.
    subprocess.run(['arm-linux-gnueabihf-objcopy', '--remove-section', '.ARM.attributes', obj], check=True)
    subprocess.run([cxx, '-static', obj, '-o', exe], check=True)
    # The trace (hundreds of MB) streams through a named pipe into the parser below.
    if os.path.exists(log):
        os.remove(log)
    os.mkfifo(log)
    report_file = os.path.join(out, 'driver.txt')
    with open(report_file, 'w') as stdout:
        qemu = subprocess.Popen(['qemu-arm', '-d', 'in_asm,exec,nochain', '-D', log, exe, count], stdout=stdout)

    blocks = {}  # start address -> [(address, size, mnemonic, operands)]
    cycles, costs, current, inside, last = 0, [], None, False, None
    insn = re.compile(r'^0x([0-9a-f]+):\s+((?:[0-9a-f]{4} ?)+)\s+(\S+)\s*(.*)$')
    trace = re.compile(r'^Trace \d+: \S+ \[[0-9a-f]+/([0-9a-f]+)/')
    with open(log) as f:  # blocks until qemu opens its end
        for line in f:
            if line.startswith('IN:'):
                current = []
                continue
            m = insn.match(line)
            if m and current is not None:
                if not current:
                    blocks[int(m.group(1), 16)] = current
                current.append((int(m.group(1), 16), len(m.group(2).replace(' ', '')) // 2, m.group(3), m.group(4)))
                continue
            t = trace.match(line)
            if not t:
                continue
            current = None
            pc = int(t.group(1), 16)
            name = line.rsplit(']', 1)[-1].strip()
            if name == 'm4_begin':
                inside, cycles, last = True, 0, None
                continue
            if name == 'm4_end':
                costs.append(cycles)
                inside = False
                continue
            if not inside:
                continue
            if last is not None:  # the previous block's last instruction: a branch taken?
                addr, size, mn, _ = last
                if BRANCH.match(mn.split('.')[0]) and pc != addr + size:
                    cycles += TAKEN_REFILL
            memory = False
            for ins in blocks.get(pc, []):
                c, memory = price(ins[2], ins[3], memory)
                cycles += c
            last = blocks[pc][-1] if pc in blocks and blocks[pc] else None
    if qemu.wait() != 0:
        sys.exit('the driver failed under qemu-arm')
    os.remove(log)
    with open(report_file) as f:
        reports = [tuple(int(v) for v in line.split()[1:]) for line in f if line.startswith('solve ')]
    if len(costs) != len(reports):
        sys.exit('traced %d solves, the driver reported %d' % (len(costs), len(reports)))

    # reports: (instance, deadline, passes, status, fast_path); deadline 0 = none.
    by = {}
    for (k, d, p, s, fp), c in zip(reports, costs):
        by.setdefault(k, {})[d] = (p, c, s, fp)
    fast = [v[0][1] for v in by.values() if v[0][3] == 1]
    slow = [v for v in by.values() if v[0][3] == 0]
    # The deadline model, as bench_constrained's Deadline: per pass, the slope between the
    # deadlines 1 and 4 (both reached by every solve that leaves the fast path); the fixed
    # part, what deadline 1 costs beyond one pass; the costliest pass, the slope between 4
    # and 32 per solve that needs 32.
    slope = (sum(v[4][1] - v[1][1] for v in slow) / sum(v[4][0] - v[1][0] for v in slow))
    fixed = statistics.mean(v[1][1] - v[1][0] * slope for v in slow)
    deep = [(v[32][1] - v[4][1]) / (v[32][0] - v[4][0]) for v in slow if v[0][0] >= 32 and v[32][0] > v[4][0]]
    free = sorted(v[0][1] for v in slow)
    passes = sorted(v[0][0] for v in slow)
    print('Cortex-M4F cycles (estimated from the trace), solve_constrained, float, 5 hard fingers:')
    print('  fast path (%d grasps inside the cones): median %d, max %d' %
          (len(fast), statistics.median(fast), max(fast)))
    print('  deadline model over %d grasps that leave the fast path: T_fixed %d, T_pass %d '
          '(costliest per grasp %s over %d grasps that need 32 passes)' %
          (len(slow), fixed, slope, '%d' % max(deep) if deep else '-', len(deep)))
    worst_pass = max([slope] + deep)
    print('  bound T_fixed + max_passes * (costliest pass): %d cycles at 8 passes, %d at 16' %
          (fixed + 8 * worst_pass, fixed + 16 * worst_pass))
    print('  without a deadline: passes median %d, max %d; cycles median %d, max %d' %
          (statistics.median(passes), passes[-1], statistics.median(free), free[-1]))


if __name__ == '__main__':
    main()
