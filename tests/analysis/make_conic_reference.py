#!/usr/bin/python3
"""Reference data for grip::force_closure and grip::max_resistible_wrench, from an
independent conic solver (Debian's python3-cvxopt, conelp).

For seeded random grasps of the three contact models it solves, in the primal form written
out below (grip solves their duals by its own interior-point method):

  margin  = max t  s.t.  G x = 0,  sum_i e_i . x_i = 1,  x_i - t e_i in K_i
  scale   = max s  s.t.  G x + s d = 0,  sum_i e_i . x_i <= B,  x_i in K_i

with the exact cones (grip's conventions, docs/conventions.md: normal a_i unit INTO the object):
  H  hard finger,   x = f (3):      |f - (a.f) a| <= mu (a.f)
  S  soft finger,   x = (f, m) (4): |f_t|^2/mu^2 + m^2/mu_t^2 <= (a.f)^2
  F  frictionless,  x = f_n (1):    f_n >= 0
and e_i = a_i, (a_i, 0) or 1. It writes conic_reference.txt next to this script; the C++ test
reads it and does not need Python. Run:  /usr/bin/python3 tests/analysis/make_conic_reference.py

Each problem is solved at cvxopt tolerance 1e-10 (retried at 1e-9 if cvxopt stops short);
conelp's primal and dual objectives then bracket the optimum. An instance is kept only when
both brackets are narrower than 1e-9 (relative to 1 + |value|), or the margin problem is
'primal infeasible' (no internal force at all); the file stores each bracket.

File format (whitespace separated, '#' lines are comments):
  # counts H <instances> S <instances> F <instances>
  instance <k> <H|S|F> <n> <margin lower> <margin upper> <B> <scale lower> <scale upper>
  d <6 numbers: the wrench direction d (force; moment)>
  c <px py pz  nx ny nz  mu  mu_t>      (n lines)
"none none": the margin problem is infeasible (G x = 0 with sum e.x = 1 has no solution in the cones).
All inputs are printed with 10 significant digits and the solver was given exactly the printed
(rounded) values.
"""
import os
import sys

import numpy as np
from cvxopt import matrix, solvers

# The rounding of printed inputs and the tangent basis (grip's TangentBasis) are the
# constrained solver's reference generator's.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "solve"))
from make_constrained_reference import rnd, skew, tangent_basis  # noqa: E402

SEED = 20261127
PER_MODEL = 40
TOLS = [1e-10, 1e-9]
WIDTH = 1e-9


def random_contact(rng, axes):
    """A contact on the ellipsoid with semi-axes `axes` (m), inward normal."""
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    p = u / np.sqrt(np.sum((u / axes) ** 2))
    nrm = -(p / axes ** 2)
    nrm /= np.linalg.norm(nrm)
    return dict(p=np.array([rnd(v) for v in p]), a=np.array([rnd(v) for v in nrm]),
                mu=rnd(rng.uniform(0.2, 1.0)), mut=rnd(rng.uniform(0.002, 0.02)))


def blocks(model, contacts):
    """G (6 x m), e (m), and the cone rows: for each contact the matrix C_i with
    x_i in K_i  <=>  C_i x_i in Q (second-order cone) or >= 0 (frictionless)."""
    d = {"H": 3, "S": 4, "F": 1}[model]
    n = len(contacts)
    G = np.zeros((6, n * d))
    e = np.zeros(n * d)
    cones = []
    for i, c in enumerate(contacts):
        o = i * d
        a = c["a"] / np.linalg.norm(c["a"])
        if model == "F":
            G[:3, o] = c["a"]
            G[3:, o] = np.cross(c["p"], c["a"])
            e[o] = 1.0
            cones.append(np.ones((1, 1)))
            continue
        G[:3, o:o + 3] = np.eye(3)
        G[3:, o:o + 3] = skew(c["p"])
        if d == 4:
            G[3:, o + 3] = c["a"]
        e[o:o + 3] = a
        e1, e2 = tangent_basis(a)
        C = np.zeros((d, d))
        C[0, :3] = a
        C[1, :3] = e1 / c["mu"]
        C[2, :3] = e2 / c["mu"]
        if d == 4:
            C[3, 3] = 1.0 / c["mut"]
        cones.append(C)
    return G, e, cones, d


def conelp(model, contacts, extra_cols, c_obj, A, b, lin_rows, lin_h, shift, tol):
    """Solves min c_obj . v over v = (x, extra) with A v = b, lin_rows v <= lin_h and
    C_i (x_i - shift_i * v_last) in the cone of contact i."""
    G, e, cones, d = blocks(model, contacts)
    m = G.shape[1] + extra_cols
    rows_l, h_l, rows_q, sizes = list(lin_rows), list(lin_h), [], []
    for i, C in enumerate(cones):
        o = i * d
        blk = np.zeros((d, m))
        blk[:, o:o + d] = -C
        if shift is not None:
            blk[:, m - 1] = C @ shift[o:o + d]
        if model == "F":
            rows_l.append(blk[0])
            h_l.append(0.0)
        else:
            rows_q.append(blk)
            sizes.append(d)
    Gc = np.vstack([np.array(rows_l).reshape(-1, m)] + rows_q)
    h = np.concatenate([np.array(h_l), np.zeros(sum(sizes))])
    M = lambda z: matrix(np.ascontiguousarray(z, dtype=float))
    opts = {"show_progress": False, "abstol": tol, "reltol": tol, "feastol": tol, "maxiters": 200}
    try:
        return solvers.conelp(M(c_obj), M(Gc), M(h), {"l": len(rows_l), "q": sizes, "s": []},
                              M(A), M(b), options=opts)
    except (ValueError, ArithmeticError):
        return None


def margin(model, contacts, tol):
    G, e, _, _ = blocks(model, contacts)
    m = G.shape[1] + 1
    A = np.zeros((7, m))
    A[:6, :-1] = G
    A[6, :-1] = e
    b = np.zeros(7)
    b[6] = 1.0
    if np.linalg.matrix_rank(A) < 7:
        return None
    c = np.zeros(m)
    c[-1] = -1.0
    sol = conelp(model, contacts, 1, c, A, b, [], [], e, tol)
    if sol is None:
        return None
    if sol["status"] == "optimal":
        return bracket(sol)
    if sol["status"] == "primal infeasible":
        return "none"
    return None


def bracket(sol):
    """(lower, upper) on max t = -min(-t): minus the primal and minus the dual objective."""
    lo, hi = -sol["primal objective"], -sol["dual objective"]
    if hi - lo > WIDTH * (1.0 + abs(lo)):
        return None
    return (lo, hi)


def scale(model, contacts, d, budget, tol):
    G, e, _, _ = blocks(model, contacts)
    m = G.shape[1] + 1
    A = np.hstack([G, d.reshape(6, 1)])
    U, sv, _ = np.linalg.svd(A)
    r = int(np.sum(sv > 1e-10 * sv[0]))
    A = U[:, :r].T @ A
    c = np.zeros(m)
    c[-1] = -1.0
    lin = np.zeros(m)
    lin[:-1] = e
    sol = conelp(model, contacts, 1, c, A, np.zeros(r), [lin], [budget], None, tol)
    if sol is None or sol["status"] != "optimal":
        return None
    return bracket(sol)


def first(f):
    """The first tolerance of TOLS at which f(tol) gives an answer."""
    for t in TOLS:
        r = f(t)
        if r is not None:
            return r
    return None


def main():
    rng = np.random.default_rng(SEED)
    out = []
    counts = {"H": 0, "S": 0, "F": 0}
    k = 0
    for model in "HSF":
        while counts[model] < PER_MODEL:
            lo = 7 if model == "F" else 3
            n = int(rng.integers(lo, 21))
            axes = rng.uniform(0.02, 0.06, size=3)
            contacts = [random_contact(rng, axes) for _ in range(n)]
            d = rng.normal(size=6)
            d[3:] *= 0.05
            d = np.array([rnd(v) for v in d])
            budget = rnd(rng.uniform(1.0, 50.0))
            mb = first(lambda t: margin(model, contacts, t))
            sb = first(lambda t: scale(model, contacts, d, budget, t))
            if mb is None or sb is None:
                continue
            mtext = "none none" if mb == "none" else "%.17g %.17g" % mb
            out.append("instance %d %s %d %s %.10g %.17g %.17g" % (k, model, n, mtext, budget, sb[0], sb[1]))
            out.append("d " + " ".join("%.10g" % v for v in d))
            for c in contacts:
                out.append("c " + " ".join("%.10g" % v for v in list(c["p"]) + list(c["a"]) + [c["mu"], c["mut"]]))
            counts[model] += 1
            k += 1
    head = ["# Force-closure margins and largest resistible wrenches from cvxopt (conelp);",
            "# written by make_conic_reference.py (see its docstring for the format).",
            "# counts H %d S %d F %d" % (counts["H"], counts["S"], counts["F"])]
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "conic_reference.txt")
    with open(path, "w") as f:
        f.write("\n".join(head + out) + "\n")


if __name__ == "__main__":
    main()
