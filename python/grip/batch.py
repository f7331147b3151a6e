"""Thousands of candidate grasps at once: arrays in, arrays out, on all cores.

Every candidate of a batch has the same number of contacts n and the same contact model.
The per-contact numbers may be scalars, arrays of shape (n,) (the same for every
candidate) or (k, n). Each candidate is evaluated by the same C++ code as a single call,
on one thread, so results do not depend on the number of threads and equal the single
calls' bit for bit. Complex input raises TypeError naming the argument (a cast to float would
keep only its real parts).
"""

import numpy as np

from . import _grip
from ._grip import ConstrainedSettings, Model


def _real(value, name):
    """value as a NumPy array of floats; TypeError naming `name` when it holds complex numbers."""
    value = np.asarray(value)
    if value.dtype.kind == "c":
        raise TypeError(f"{name}: complex values are not accepted (imaginary parts would be dropped)")
    return np.asarray(value, dtype=float)


def _scalar(value, name, kind):
    """value as a Python float or int (kind); TypeError naming `name` when it is complex."""
    if np.iscomplexobj(value):
        raise TypeError(f"{name}: complex values are not accepted (imaginary parts would be dropped)")
    return kind(value)


def _per_contact(value, name, k, n):
    value = _real(value, name)
    try:
        return np.ascontiguousarray(np.broadcast_to(value, (k, n)))
    except ValueError:
        raise ValueError(f"{name} must be a number or have shape (n,) or (k, n) = ({k}, {n}), not {value.shape}")


def _arrays(positions, normals, friction, torsional_friction, squeeze, weights):
    positions = np.ascontiguousarray(_real(positions, "positions"))
    normals = np.ascontiguousarray(_real(normals, "normals"))
    if positions.ndim != 3 or positions.shape[2] != 3:
        raise ValueError(f"positions must have shape (k, n, 3), not {positions.shape}")
    k, n = positions.shape[:2]
    return (positions, normals, _per_contact(friction, "friction", k, n),
            _per_contact(torsional_friction, "torsional_friction", k, n), _per_contact(squeeze, "squeeze", k, n),
            _per_contact(weights, "weights", k, n))


def evaluate_batch(positions, normals, friction, *, torsional_friction=0.0, squeeze=0.0, weights=1.0,
                   model=Model.HardFinger, lever_length=1.0, force_closure=True, epsilon_l1=True,
                   epsilon_linf=False, sides=8, threads=0, _first=0):
    """Quality metrics of k candidate grasps: positions and normals (k, n, 3).

    Returns a dict of arrays: singular_values (k, 6), volume and isotropy (k,) (grasp_quality
    with lever_length, m), closure (k,) bool and closure_margin (k,) (force_closure, if
    force_closure), epsilon_l1 and epsilon_linf (k,) (epsilon with `sides`-sided cones, if
    requested; 0 otherwise), status (k,) int: Status values, Ok when every metric was Ok.
    threads: 0 for every core. Invalid input raises ValueError naming the grasp and contact.
    """
    args = _arrays(positions, normals, friction, torsional_friction, squeeze, weights)
    return _grip._evaluate_batch(*args, model, _scalar(lever_length, "lever_length", float), bool(force_closure),
                                 bool(epsilon_l1), bool(epsilon_linf), _scalar(sides, "sides", int),
                                 _scalar(threads, "threads", int), int(_first))


def solve_batch(positions, normals, friction, w_ext, *, torsional_friction=0.0, squeeze=0.0, weights=1.0,
                max_normal_force=np.inf, model=Model.HardFinger, method="range_space", settings=None, threads=0,
                _first=0):
    """Solves k candidate grasps: positions and normals (k, n, 3), w_ext (6,) or (k, 6).

    method: 'range_space', 'kkt' or 'constrained' (with `settings`, a ConstrainedSettings; it
    alone keeps each contact's normal force below max_normal_force, inf for no bound).
    Returns a dict of arrays: forces (k, n, dim), multipliers (k, 6), certificate (k, 6)
    (constrained and Infeasible; else 0), residual (k,), status (k,) int (Status values),
    iterations (k,). threads: 0 for every core. (_first: the index of the first candidate in
    error messages, for chunks of a larger batch.)
    """
    args = _arrays(positions, normals, friction, torsional_friction, squeeze, weights)
    k, n = args[0].shape[:2]
    bounds = _per_contact(max_normal_force, "max_normal_force", k, n)
    w = _real(w_ext, "w_ext")
    try:
        w = np.ascontiguousarray(np.broadcast_to(w, (k, 6)))
    except ValueError:
        raise ValueError(f"w_ext must have shape (6,) or (k, 6) = ({k}, 6), not {w.shape}")
    settings = settings if settings is not None else ConstrainedSettings()
    return _grip._solve_batch(*args, bounds, model, w, str(method), settings, _scalar(threads, "threads", int),
                              int(_first))
