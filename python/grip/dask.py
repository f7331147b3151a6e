"""Batches of candidate grasps on a Dask cluster: the chunks of the candidates are Dask tasks.

    from distributed import Client, LocalCluster
    import grip.dask
    with Client(LocalCluster(n_workers=2, threads_per_worker=1)) as client:
        metrics = grip.dask.evaluate_batch(positions, normals, 0.5, client=client)

The arrays may be NumPy arrays (split here into chunks of `chunk_size` candidates, which the
task graph then carries to the workers) or Dask arrays chunked along the candidates (each
chunk is then computed where its task runs: for datasets larger than one machine's memory,
build them lazily, for example from files). On a cluster of several machines only the
client changes: Client("tcp://scheduler:8786"), with grip installed on every worker.

Each task calls grip.evaluate_batch or grip.solve_batch on its chunk with `threads`
threads (1 by default: Dask provides the parallelism); every candidate is evaluated by the
same code as in a serial call, so the results equal the serial ones bit for bit.
"""

import dask
import dask.array as da
import numpy as np

from . import batch as _batch
from ._grip import Model


def _chunks(value, k, n, shape, chunk_size, name):
    """value as a list of per-chunk delayed (or NumPy) blocks of `shape` ((k, n), (k, n, 3) or (k, 6));
    TypeError naming `name` when it holds complex numbers (a Dask array's dtype tells, uncomputed)."""
    if isinstance(value, da.Array):
        if value.dtype.kind == "c":
            raise TypeError(f"{name}: complex values are not accepted (imaginary parts would be dropped)")
        if value.shape != shape:
            raise ValueError(f"{name} must have shape {shape}, not {value.shape}")
        value = value.rechunk((chunk_size,) + value.shape[1:])
        return list(value.to_delayed().ravel())
    value = np.ascontiguousarray(np.broadcast_to(_batch._real(value, name), shape))
    return [value[s:s + chunk_size] for s in range(0, k, chunk_size)]


def _split(positions, normals, numbers, w_ext, chunk_size):
    if positions.ndim != 3 or positions.shape[2] != 3:
        raise ValueError(f"positions must have shape (k, n, 3), not {positions.shape}")
    if chunk_size < 1:
        raise ValueError(f"chunk_size must be >= 1, not {chunk_size}")
    k, n = positions.shape[:2]
    out = [_chunks(positions, k, n, (k, n, 3), chunk_size, "positions"),
           _chunks(normals, k, n, (k, n, 3), chunk_size, "normals")]
    for name, value in numbers.items():
        try:
            out.append(_chunks(value, k, n, (k, n), chunk_size, name))
        except ValueError:
            raise ValueError(f"{name} must be a number or have shape (n,) or (k, n) = ({k}, {n})")
    if w_ext is not None:
        out.append(_chunks(w_ext, k, n, (k, 6), chunk_size, "w_ext"))
    return list(zip(*out))


def _run(tasks, client):
    if client is not None:
        results = client.gather(client.compute(tasks))
    else:
        results = dask.compute(*tasks)
    return {key: np.concatenate([r[key] for r in results]) for key in results[0]}


def _evaluate_chunk(first, p, a, mu, mut, s, w, kwargs):
    return _batch.evaluate_batch(p, a, mu, torsional_friction=mut, squeeze=s, weights=w, _first=first, **kwargs)


def _solve_chunk(first, p, a, mu, mut, s, w, fmax, w_ext, kwargs):
    return _batch.solve_batch(p, a, mu, w_ext, torsional_friction=mut, squeeze=s, weights=w, max_normal_force=fmax,
                              _first=first, **kwargs)


def evaluate_batch(positions, normals, friction, *, torsional_friction=0.0, squeeze=0.0, weights=1.0,
                   model=Model.HardFinger, client=None, chunk_size=20000, threads=1, **metrics):
    """grip.evaluate_batch as Dask tasks of chunk_size candidates each, on `client`'s cluster
    (or Dask's default scheduler). `metrics`: lever_length, force_closure, epsilon_l1,
    epsilon_linf, sides, as in grip.evaluate_batch. Returns its dict of NumPy arrays."""
    numbers = dict(friction=friction, torsional_friction=torsional_friction, squeeze=squeeze, weights=weights)
    kwargs = dict(model=model, threads=threads, **metrics)
    parts = _split(positions, normals, numbers, None, chunk_size)
    return _run([dask.delayed(_evaluate_chunk)(b * chunk_size, *part, kwargs) for b, part in enumerate(parts)], client)


def solve_batch(positions, normals, friction, w_ext, *, torsional_friction=0.0, squeeze=0.0, weights=1.0,
                max_normal_force=np.inf, model=Model.HardFinger, method="range_space", settings=None, client=None,
                chunk_size=20000, threads=1):
    """grip.solve_batch as Dask tasks of chunk_size candidates each (see evaluate_batch)."""
    numbers = dict(friction=friction, torsional_friction=torsional_friction, squeeze=squeeze, weights=weights,
                   max_normal_force=max_normal_force)
    kwargs = dict(model=model, method=method, settings=settings, threads=threads)
    parts = _split(positions, normals, numbers, w_ext, chunk_size)
    return _run([dask.delayed(_solve_chunk)(b * chunk_size, *part, kwargs) for b, part in enumerate(parts)], client)
