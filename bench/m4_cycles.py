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

Prints the cost of a solve as the solver's bounds make it (ConstrainedSettings: newton_passes
Newton passes before and after the interior-point method, max_iterations iterations of it):
T <= T_fixed + 2 newton_passes T_pass + max_iterations T_iteration, with T_pass the cost of a
Newton pass (newton_passes 1 against 8), T_iteration that of an interior-point iteration
(max_iterations 2 against 12), T_fixed the largest remainder of a solve that leaves the fast
path; and the cycles of the fast path and of solves with the default settings.
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

    # reports: (instance, newton_passes, max_iterations, passes, iterations, status, fast_path,
    # refined), status as grip::Status (0 Ok, 3 Infeasible, 4 IterationLimit).
    by = {}
    for (k, np_, mi, p, it, s, fp, rf), c in zip(reports, costs):
        by.setdefault(k, {})[(np_, mi)] = dict(newton_passes=np_, passes=p, iterations=it, status=s, fast=fp,
                                               refined=rf, cycles=c)
    default = (reports[0][1], reports[0][2])  # the first solve of an instance: the defaults
    fast = [v[default]['cycles'] for v in by.values() if v[default]['fast']]
    slow = [v for v in by.values() if not v[default]['fast']]
    if not fast or not slow:
        sys.exit('too few grasps for the cost model: run more instances (at least 8)')

    def newton_passes(r):
        """Newton's passes of a solve: its passes less the interior-point method's (three per
        iteration and one per run; a step halved back, rare, counts as an iteration of one pass:
        it is then left in the remainder, T_fixed, on the safe side)."""
        if r['newton_passes'] == 0:
            return 0
        runs = 0 if r['iterations'] == 0 and r['refined'] else 2 if r['status'] == 3 else 1
        return max(r['passes'] - 3 * r['iterations'] - runs, 0)

    def slope(pairs, unit):
        """Cycles per unit between two solves of each grasp: over all of them, and the costliest
        grasp's."""
        pairs = [(a, b) for a, b in pairs if unit(b) > unit(a)]
        if not pairs:
            sys.exit('too few grasps for the cost model: run more instances (at least 8)')
        total = sum(b['cycles'] - a['cycles'] for a, b in pairs) / sum(unit(b) - unit(a) for a, b in pairs)
        worst = max((b['cycles'] - a['cycles']) / (unit(b) - unit(a)) for a, b in pairs)
        return total, worst, len(pairs)

    # A Newton pass: newton_passes 1 against 8 at max_iterations 1 (one interior-point pass, no
    # iteration), over the grasps whose Newton's method has not converged by then (the two
    # solves then end alike). An interior-point iteration: max_iterations 2 against 12 with no
    # Newton pass, over the grasps where both make one interior-point run (not a slipping grasp
    # whose certificate comes within 12: the least-residual problem's set-up is a fixed cost).
    t_pass, worst_pass, n_pass = slope([(v[(1, 1)], v[(8, 1)]) for v in slow if not v[(8, 1)]['refined']],
                                       newton_passes)
    t_iter, worst_iter, n_iter = slope([(v[(0, 2)], v[(0, 12)]) for v in slow if v[(0, 12)]['status'] != 3],
                                       lambda r: r['iterations'])
    # The fixed part: the most any solve that leaves the fast path costs beyond its Newton passes
    # and interior-point iterations (the fast path, the set-up of Newton's method and of each
    # interior-point run, the certificate, the answer's residual and objective).
    runs = [r for v in slow for r in v.values()]
    fixed = max(r['cycles'] - newton_passes(r) * t_pass - r['iterations'] * t_iter for r in runs)
    np_d, mi_d = default
    bound = fixed + 2 * np_d * t_pass + mi_d * t_iter
    print('Cortex-M4F cycles (estimated from the trace), solve_constrained, float, 5 hard fingers:')
    print('  fast path (%d grasps inside the cones): median %d, max %d' %
          (len(fast), statistics.median(fast), max(fast)))
    print('  a Newton pass with its 6x6 solve: %d (costliest grasp %d; %d grasps, newton_passes 1 to 8)' %
          (t_pass, worst_pass, n_pass))
    print('  an interior-point iteration: %d (costliest grasp %d; %d grasps, max_iterations 2 to 12)' %
          (t_iter, worst_iter, n_iter))
    print('  T_fixed %d (the largest remainder over the %d solves that leave the fast path)' % (fixed, len(runs)))
    print('  bound T_fixed + 2 newton_passes T_pass + max_iterations T_iteration at the defaults '
          '(%d, %d): %d' % (np_d, mi_d, bound))
    for name, keep in (('holding (Ok)', lambda s: s == 0), ('slipping (Infeasible)', lambda s: s == 3),
                       ('IterationLimit', lambda s: s == 4)):
        group = [v[default] for v in slow if keep(v[default]['status'])]
        if not group:
            continue
        slowest = max(group, key=lambda r: r['cycles'])
        print('  defaults, %d %s: cycles median %d (medians: %d iterations, %d passes), slowest %d '
              '(%d iterations, %d passes)' %
              (len(group), name, statistics.median(r['cycles'] for r in group),
               statistics.median(r['iterations'] for r in group), statistics.median(r['passes'] for r in group),
               slowest['cycles'], slowest['iterations'], slowest['passes']))
    over = [v[default]['cycles'] for v in slow if v[default]['cycles'] > bound]
    print('  default solves above the bound: %d of %d' % (len(over), len(slow)))


if __name__ == '__main__':
    main()
