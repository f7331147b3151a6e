#!/usr/bin/python3
"""Evaluates a million candidate grasps (5 hard fingers on random points of a 4 cm sphere)
on a Dask cluster of this machine: force closure and grasp quality, the candidates
generated lazily in chunks on the workers. Prints the share in force closure, the best
isotropy, the throughput, and checks a sample against the serial call.

    python3 examples/python/dask_batch.py [count]

On a cluster of several machines, start `dask scheduler` and `dask worker tcp://host:8786`
(grip installed on each) and replace the LocalCluster by Client("tcp://host:8786").
"""

import os
import sys
import time

import dask.array as da
import numpy as np
from distributed import Client, LocalCluster

import grip
import grip.dask


def candidates(count, n, chunk, seed=7):
    rs = da.random.RandomState(seed)
    u = rs.normal(size=(count, n, 3), chunks=(chunk, n, 3))
    u = u / da.sqrt((u ** 2).sum(axis=2, keepdims=True))
    return 0.04 * u, -u


def main(count=1_000_000, n=5, chunk=25_000):
    count = int(count)
    chunk = min(chunk, count)
    positions, normals = candidates(count, n, chunk)
    workers = os.cpu_count() or 1
    with LocalCluster(n_workers=workers, threads_per_worker=1, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        t = time.perf_counter()
        r = grip.dask.evaluate_batch(positions, normals, 0.5, squeeze=1.0, epsilon_l1=False, client=client,
                                     chunk_size=chunk)
        seconds = time.perf_counter() - t
    ok = r["status"] == int(grip.Status.Ok)
    print(f"{count} grasps of {n} contacts on {workers} workers: {seconds:.1f} s, {count / seconds:,.0f} grasps/s")
    print(f"in force closure: {np.mean(r['closure'][ok]):.1%}; best isotropy {np.max(r['isotropy']):.3f}")
    sample = slice(0, min(count, 500))
    serial = grip.evaluate_batch(positions[sample].compute(), normals[sample].compute(), 0.5, squeeze=1.0,
                                 epsilon_l1=False)
    assert all(np.array_equal(serial[key], r[key][sample]) for key in serial), "Dask and serial results differ"
    print("the first 500 equal the serial evaluation bit for bit")


if __name__ == "__main__":
    main(*sys.argv[1:2])
