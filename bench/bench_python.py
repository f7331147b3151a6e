#!/usr/bin/python3
"""Python costs of grip (issue: the Python package), each against a baseline measured in the
same run:

1. the call overhead of solve_range_space at n = 20: a Python call (timeit, least of 7 runs)
   against the same solve timed in C++ (grip._grip_bench, built with -DGRIP_BUILD_BENCH=ON);
2. batch throughput, grasps per second, on 1 and 2 threads, of solve_batch (range space) and
   evaluate_batch (force closure only), against a Python loop of single calls.

Run after building the module and the hooks (-DGRIP_BUILD_BENCH=ON, targets grip_python and
grip_python_bench): PYTHONPATH=build/py/python /usr/bin/python3 bench/bench_python.py
"""

import os
import platform
import timeit

import numpy as np

import grip
from grip import _grip_bench


def candidates(k, n, seed=1):
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(k, n, 3))
    u /= np.linalg.norm(u, axis=2)[..., None]
    a = -u + 0.3 * rng.uniform(-1, 1, size=(k, n, 3))
    a /= np.linalg.norm(a, axis=2)[..., None]
    return 0.04 * u, a, rng.uniform(0.3, 0.9, size=(k, n))


def best(stmt, number, repeat=7):
    return min(timeit.repeat(stmt, number=number, repeat=repeat)) / number


def main():
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; numpy {np.__version__}")
    p, a, mu = candidates(1, 20)
    g = grip.Grasp(p[0], a[0], mu[0], squeeze=1.0)
    w = np.array([0.0, 0.0, -9.81, 0.1, 0.0, 0.0])
    py = best(lambda: grip.solve_range_space(g, w), 20000) * 1e9
    cpp = min(_grip_bench.time_range_space(g, w, 200000) for _ in range(7))
    print("| n | C++ call (ns) | Python call (ns) | overhead (ns) |")
    print("| ---: | ---: | ---: | ---: |")
    print(f"| 20 | {cpp:.0f} | {py:.0f} | {py - cpp:.0f} |")

    k, n = 4000, 6
    p, a, mu = candidates(k, n, 2)
    ws = np.tile(w, (k, 1))
    grasps = [grip.Grasp(p[j], a[j], mu[j], squeeze=1.0) for j in range(k)]
    rows = []
    loop = best(lambda: [grip.solve_range_space(x, w) for x in grasps], 1, 3)
    one = best(lambda: grip.solve_batch(p, a, mu, ws, squeeze=1.0, threads=1), 1, 3)
    two = best(lambda: grip.solve_batch(p, a, mu, ws, squeeze=1.0, threads=2), 1, 3)
    rows.append(("solve_range_space", loop, one, two))
    loop = best(lambda: [grip.force_closure(x) for x in grasps], 1, 3)
    kw = dict(squeeze=1.0, epsilon_l1=False)
    one = best(lambda: grip.evaluate_batch(p, a, mu, threads=1, **kw), 1, 3)
    two = best(lambda: grip.evaluate_batch(p, a, mu, threads=2, **kw), 1, 3)
    rows.append(("force_closure", loop, one, two))
    print()
    print(f"| {k} grasps of {n} contacts | Python loop (grasps/s) | batch, 1 thread (grasps/s) | batch, 2 threads (grasps/s) | 2 threads / loop |")
    print("| --- | ---: | ---: | ---: | ---: |")
    for name, loop, one, two in rows:
        print(f"| `{name}` | {k / loop:,.0f} | {k / one:,.0f} | {k / two:,.0f} | {loop / two:.1f} |")


if __name__ == "__main__":
    main()
