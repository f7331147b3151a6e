"""Readers of the cvxopt reference data that the C++ suite also checks against
(tests/analysis/conic_reference.txt, tests/solve/constrained_reference.txt)."""

import os

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def _blocks(path):
    block = None
    with open(path) as f:
        for line in f:
            words = line.split()
            if not words or words[0].startswith("#"):
                continue
            if words[0] == "instance":
                if block:
                    yield block
                block = {"head": words[1:], "c": []}
            elif words[0] == "c":
                block["c"].append([float(v) for v in words[1:]])
            else:
                block[words[0]] = [float(v) for v in words[1:]]
    if block:
        yield block


def conic_reference():
    """Force-closure margins: dicts with model, contacts (n x 8: p, a, mu, mu_t) and the
    bracket (lo, hi) of the optimal margin, or None when no internal force exists."""
    out = []
    for b in _blocks(os.path.join(ROOT, "tests", "analysis", "conic_reference.txt")):
        _, model, n, lo, hi = b["head"][:5]
        feasible = lo != "none"
        out.append({"model": model, "contacts": np.array(b["c"]), "n": int(n),
                    "margin": (float(lo), float(hi)) if feasible else None})
    return out


def constrained_reference():
    """solve_constrained instances: dicts with model, kind, w_ext, contacts (n x 11: p, a, mu,
    mu_t, squeeze, weight, max_normal_force: inf where the file has none or -1), feasible,
    objective, and x* when feasible."""
    out = []
    for b in _blocks(os.path.join(ROOT, "tests", "solve", "constrained_reference.txt")):
        _, model, n, feasible, objective = b["head"][:5]
        rows = [row + [-1.0] * (11 - len(row)) for row in b["c"]]
        contacts = np.array(rows)
        contacts[contacts[:, 10] <= 0, 10] = np.inf
        out.append({"model": model, "kind": b["head"][-1], "n": int(n), "feasible": feasible == "optimal",
                    "objective": float(objective), "w": np.array(b["w"]), "contacts": contacts,
                    "x": np.array(b.get("x", []))})
    return out
