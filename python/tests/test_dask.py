"""grip.dask: batches as Dask tasks, on the default scheduler and on a local cluster of
worker processes, equal to the serial batch bit for bit."""

import numpy as np
import pytest

import grip

dask = pytest.importorskip("dask")
distributed = pytest.importorskip("distributed")
import dask.array as da  # noqa: E402

import grip.dask  # noqa: E402


def candidates(k, n, seed):
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(k, n, 3))
    u /= np.linalg.norm(u, axis=2)[..., None]
    return 0.04 * u, -u, rng.uniform(0.3, 0.9, size=(k, n))


def same(a, b):
    assert a.keys() == b.keys()
    for key in a:
        assert np.array_equal(a[key], b[key]), key


def test_dask_batches_equal_the_serial_ones_on_the_default_scheduler():
    p, a, mu = candidates(1000, 5, 1)
    serial = grip.evaluate_batch(p, a, mu, squeeze=1.0, sides=4)
    same(grip.dask.evaluate_batch(p, a, mu, squeeze=1.0, sides=4, chunk_size=130), serial)
    w = np.array([0.0, 0.0, -5.0, 0.0, 0.01, 0.0])
    serial = grip.solve_batch(p, a, mu, w, squeeze=1.0, method="constrained")
    same(grip.dask.solve_batch(p, a, mu, w, squeeze=1.0, method="constrained", chunk_size=333), serial)
    bounds = np.random.default_rng(4).uniform(1.0, 4.0, size=(1000, 5))
    serial = grip.solve_batch(p, a, mu, w, squeeze=1.0, max_normal_force=bounds, method="constrained")
    same(grip.dask.solve_batch(p, a, mu, w, squeeze=1.0, max_normal_force=bounds, method="constrained", chunk_size=333),
         serial)


def test_dask_batches_equal_the_serial_ones_on_a_local_cluster():
    p, a, mu = candidates(3000, 6, 2)
    serial = grip.evaluate_batch(p, a, mu, squeeze=1.0, epsilon_l1=False)
    # Dask arrays chunked along the candidates: each chunk goes to the task that needs it.
    dp, dn = da.from_array(p, chunks=(700, 6, 3)), da.from_array(a, chunks=(700, 6, 3))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        same(grip.dask.evaluate_batch(dp, dn, mu, squeeze=1.0, epsilon_l1=False, client=client, chunk_size=500), serial)
        same(grip.dask.evaluate_batch(p, a, mu, squeeze=1.0, epsilon_l1=False, client=client, chunk_size=1000), serial)


def test_dask_batches_check_their_input():
    p, a, mu = candidates(10, 4, 3)
    with pytest.raises(ValueError, match="chunk_size must be >= 1"):
        grip.dask.evaluate_batch(p, a, mu, chunk_size=0)
    with pytest.raises(ValueError, match="friction must be a number or have shape"):
        grip.dask.evaluate_batch(p, a, np.ones(3))
    bad = a.copy()
    bad[7, 2] = 0
    with pytest.raises(ValueError, match=r"normals\[7, 2\] must be a unit vector"):  # in the second chunk of 5
        grip.dask.evaluate_batch(p, bad, mu, chunk_size=5)
