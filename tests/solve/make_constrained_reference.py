#!/usr/bin/python3
"""Reference data for grip::solve_constrained, from an independent conic solver.

Solves seeded random instances of

    minimise   1/2 sum_i w_i |x_i - t_i|^2
    subject to G x + w_ext = 0,   x_i in K_i  (every contact inside its exact cone)

with Debian's python3-cvxopt (interior point, coneqp), and writes them to
constrained_reference.txt next to this script. The C++ test reads that file; it does
not need Python. Run:  /usr/bin/python3 tests/solve/make_constrained_reference.py

Cones (grip's conventions, docs/conventions.md: normal a_i unit INTO the object):
  H  hard finger,   x = f (3):      |f - (a.f) a| <= mu (a.f)              (eq. 4-5)
  S  soft finger,   x = (f, m) (4): |f_t|^2/mu^2 + m^2/mu_t^2 <= (a.f)^2   (elliptic)
  F  frictionless,  x = f_n (1):    f_n >= 0
Targets: H: s a; S: (s a, 0); F: s.

Feasibility is decided first by cvxopt's conelp on the feasibility problem (zero
objective); it returns 'primal infeasible' with a certificate when no forces in the
cones balance the wrench. Feasible instances are then solved by coneqp with tight
tolerances; instances cvxopt does not solve to 'optimal' are discarded (and counted).

File format (whitespace separated, '#' lines are comments):
  # counts H <instances> <infeasible> S <instances> <infeasible> F <instances> <infeasible>
  instance <k> <H|S|F> <n> <optimal|infeasible> <objective (0 if infeasible)> <residual> <gap>
  w <6 numbers: w_ext = (force; moment)>
  c <px py pz  nx ny nz  mu  mu_t  squeeze  weight [bound]>   (n lines)
  x <the optimal forces x*, n * dim numbers>           (optimal instances only)
[bound]: the contact's max_normal_force (N), in the bounded instances only (every contact of
such an instance has the field; -1 for none): then also f_n <= bound (a truncated cone).
<gap> is cvxopt's duality gap at x*: F2(x*) - F2_min <= gap, so that any x with
F2(x) - F2_min <= delta lies within sqrt(2 (gap + delta) / min w_i) of x* (F2 is strongly
convex with modulus min w_i).
All inputs are printed with 10 significant digits and the solver was given exactly the
printed (rounded) values, so that the C++ side parses the very same instance.
"""
import os

import numpy as np
from cvxopt import matrix, solvers

SEED = 20261121
COUNT = 300
EXTRA_SEED = SEED + 1
EXTRA_PER_KIND = 16  # per kind: rescaled by 1e-3, rescaled by 1e3, collinear, nearly collinear
BOUND_SEED = SEED + 2
BOUND_PER_KIND = 15  # per kind: bounds inactive, some active, too low (mostly infeasible)
# coneqp reaches status 'optimal' at 1e-10; a second run at 1e-12 usually stops with
# 'unknown' (progress stalls at round-off) but with a better objective. We keep the second
# objective when its residual is at round-off and it agrees with the first to 1e-9.
# The hardest instances stop short of 'optimal' at 1e-10; they are retried at 1e-9 and 1e-8 and
# kept with the duality gap reached (the C++ test's bound on |x - x*| grows with the gap).
LADDER = [{"show_progress": False, "abstol": t, "reltol": t, "feastol": t, "maxiters": 200}
          for t in (1e-10, 1e-9, 1e-8)]
TIGHT = {"show_progress": False, "abstol": 1e-12, "reltol": 1e-12, "feastol": 1e-12, "maxiters": 100}


def rnd(v):
    return float("%.10g" % v)


def skew(r):
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def tangent_basis(a):
    k = int(np.argmin(np.abs(a)))
    e = np.zeros(3)
    e[k] = 1.0
    e1 = np.cross(a, e)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(a, e1)


def random_contact(rng, axes, cap=None):
    """A contact on the ellipsoid with semi-axes `axes`, inward normal; `cap`: only z > cap."""
    while True:
        u = rng.normal(size=3)
        u /= np.linalg.norm(u)
        if cap is None or u[2] > cap:
            break
    p = u / np.sqrt(np.sum((u / axes) ** 2))
    nrm = -(p / axes ** 2)
    nrm /= np.linalg.norm(nrm)
    nrm = np.array([rnd(v) for v in nrm])
    return dict(p=np.array([rnd(v) for v in p]), a=nrm, mu=rnd(rng.uniform(0.2, 1.0)),
                mut=rnd(rng.uniform(0.002, 0.02)), s=rnd(rng.uniform(0.0, 3.0)), w=1.0)


def build(model, contacts, w_ext):
    """cvxopt data: P, q (objective), Gc, h, dims (cones), A, b (equilibrium)."""
    d = {"H": 3, "S": 4, "F": 1}[model]
    n = len(contacts)
    m = n * d
    P = np.zeros((m, m))
    q = np.zeros(m)
    A = np.zeros((6, m))
    rows_l, rows_q, sizes, h_l = [], [], [], []
    for i, c in enumerate(contacts):
        o = i * d
        a, r = c["a"], c["p"]
        bound = c.get("c", -1.0)
        if bound > 0:  # f_n <= bound
            g = np.zeros(m)
            if model == "F":
                g[o] = 1.0
            else:
                g[o:o + 3] = a
            rows_l.append(g)
            h_l.append(bound)
        if model == "F":
            t = np.array([c["s"]])
            A[:3, o] = a
            A[3:, o] = np.cross(r, a)
            g = np.zeros(m)
            g[o] = -1.0  # -x <= 0
            rows_l.append(g)
            h_l.append(0.0)
        else:
            t = np.concatenate([c["s"] * a, np.zeros(d - 3)])
            A[:3, o:o + 3] = np.eye(3)
            A[3:, o:o + 3] = skew(r)
            if d == 4:
                A[3:, o + 3] = a
            e1, e2 = tangent_basis(a)
            g = np.zeros(m)
            g[o:o + 3] = -a  # a.f >= 0 (needed for mu = 0; redundant otherwise)
            rows_l.append(g)
            h_l.append(0.0)
            blk = np.zeros((d, m))
            if d == 3:  # (mu a.f, e1.f, e2.f) in Q3
                blk[0, o:o + 3] = -c["mu"] * a
                blk[1, o:o + 3] = -e1
                blk[2, o:o + 3] = -e2
            else:  # (a.f, e1.f/mu, e2.f/mu, m/mu_t) in Q4
                blk[0, o:o + 3] = -a
                blk[1, o:o + 3] = -e1 / c["mu"]
                blk[2, o:o + 3] = -e2 / c["mu"]
                blk[3, o + 3] = -1.0 / c["mut"]
            rows_q.append(blk)
            sizes.append(d)
        P[o:o + d, o:o + d] = c["w"] * np.eye(d)
        q[o:o + d] = -c["w"] * t
    Gc = np.vstack(rows_l + rows_q)
    dims = {"l": len(rows_l), "q": sizes, "s": []}
    h = np.concatenate([np.array(h_l), np.zeros(Gc.shape[0] - len(h_l))])
    return P, q, Gc, h, dims, A, -np.asarray(w_ext)


def objective(model, contacts, x):
    d = {"H": 3, "S": 4, "F": 1}[model]
    f = 0.0
    for i, c in enumerate(contacts):
        xi = x[i * d:(i + 1) * d]
        t = np.array([c["s"]]) if model == "F" else np.concatenate([c["s"] * c["a"], np.zeros(d - 3)])
        f += 0.5 * c["w"] * np.sum((xi - t) ** 2)
    return f


def reduced_equality(A, b):
    """G x = -w_ext on the row space of G (cvxopt needs full row rank): (U_r^T A, U_r^T b, U_r,
    whether b lies in the range of A)."""
    U, sv, _ = np.linalg.svd(A)
    r = int(np.sum(sv > 1e-10 * sv[0]))
    Ur = U[:, :r]
    off = b - Ur @ (Ur.T @ b)
    return Ur.T @ A, Ur.T @ b, Ur, float(np.linalg.norm(off)) <= 1e-12 * (1.0 + float(np.linalg.norm(b)))


def lever_length(contacts):
    """L, the longest lever arm max_i |r_i| (1 when every contact is at the reference point):
    the residual's norm |(f, m / L)| weighs moments per L, as grip's solve_constrained does."""
    L = max(float(np.linalg.norm(c["p"])) for c in contacts)
    return L if L > 1e-15 else 1.0


def least_residual(model, contacts, w_ext):
    """min |G x + w_ext|_L over the cones (|(f, m)|_L = |(f, m / L)|, L = lever_length), by two
    formulations that must agree to 1e-7: a QP, min |G x + w_ext|_L^2 / 2 (coneqp, singular
    P = G^T T^2 G), and an SOCP, min t with (t, T(G x + w_ext)) in Q7 (conelp). Returns
    (|G x_c + w_ext|_L, F2(x_c)) at the QP's minimiser x_c, or None when either fails or they
    disagree (a degenerate instance cvxopt cannot settle)."""
    P, q, Gc, h, dims, A, b = build(model, contacts, w_ext)
    L = lever_length(contacts)
    A = A.copy()
    b = b.copy()
    A[3:, :] /= L
    b[3:] /= L
    m = P.shape[0]
    M = lambda z: matrix(np.ascontiguousarray(z, dtype=float))
    qp = None
    for opts in LADDER:
        try:
            sol = solvers.coneqp(M(A.T @ A), M(-(A.T @ b)), M(Gc), M(h), dims, options=opts)
        except (ValueError, ArithmeticError):
            continue
        if sol["status"] == "optimal":
            x = np.array(sol["x"]).ravel()
            qp = (float(np.linalg.norm(A @ x - b)), objective(model, contacts, x))
            break
    if qp is None:
        return None
    G2 = np.vstack([np.hstack([Gc, np.zeros((Gc.shape[0], 1))]),
                    np.hstack([np.zeros((1, m)), -np.ones((1, 1))]),  # s_0 = t
                    np.hstack([-A, np.zeros((6, 1))])])               # s_k = (A x - b)_k
    h2 = np.concatenate([h, [0.0], -b])
    dims2 = {"l": dims["l"], "q": dims["q"] + [7], "s": []}
    c = np.zeros(m + 1)
    c[m] = 1.0
    for opts in LADDER:
        try:
            sol = solvers.conelp(M(c), M(G2), M(h2), dims2, options=opts)
        except (ValueError, ArithmeticError):
            continue
        if sol["status"] == "optimal":
            r = float(np.linalg.norm(A @ np.array(sol["x"]).ravel()[:m] - b))
            return qp if abs(r - qp[0]) <= 1e-7 * (1.0 + qp[0]) else None
    return None


def solve(model, contacts, w_ext):
    """(status, objective, residual, gap, x*, lambda*, least residual, hard) or None (undecided);
    hard: cvxopt reached 'optimal' only at a looser tolerance than 1e-10."""
    P, q, Gc, h, dims, A, b = build(model, contacts, w_ext)
    Ar, br, Ur, in_range = reduced_equality(A, b)
    M = lambda z: matrix(np.ascontiguousarray(z, dtype=float))
    try:
        infeasible = not in_range  # no forces at all balance w_ext: infeasible whatever the cones
        if in_range:
            feas = solvers.conelp(M(np.zeros(P.shape[0])), M(Gc), M(h), dims, M(Ar), M(br),
                                  options={"show_progress": False})  # default tolerances
            infeasible = feas["status"] == "primal infeasible"  # certificate found
            if not infeasible and feas["status"] != "optimal":
                return None
        if infeasible:
            lr = least_residual(model, contacts, w_ext)
            return None if lr is None else ("infeasible", 0.0, 0.0, 0.0, None, None, lr, False)
        best = None
        for rung, opts in enumerate(LADDER):
            sol = solvers.coneqp(M(P), M(q), M(Gc), M(h), dims, M(Ar), M(br), options=opts)
            if sol["status"] == "optimal":
                x = np.array(sol["x"]).ravel()
                y = -(Ur @ np.array(sol["y"]).ravel())  # cvxopt's y multiplies A x - b: lambda = -y
                best = (objective(model, contacts, x), float(np.linalg.norm(A @ x - b)), abs(float(sol["gap"])), x, y)
                break
        hard = rung > 0
        if best is None:
            return None
        sol2 = solvers.coneqp(M(P), M(q), M(Gc), M(h), dims, M(Ar), M(br), options=TIGHT)
        x2 = np.array(sol2["x"]).ravel()
        f2, r2 = objective(model, contacts, x2), float(np.linalg.norm(A @ x2 - b))
        if r2 < 1e-12 * (1.0 + np.linalg.norm(b)) and abs(f2 - best[0]) <= 1e-9 * abs(best[0]):
            best = (f2, r2, abs(float(sol2["gap"])), x2, -(Ur @ np.array(sol2["y"]).ravel()))
    except (ValueError, ArithmeticError):
        return None
    return ("optimal",) + best + (None, hard)


def random_instance(rng, model):
    """A random grasp of the base set: contacts on an ellipsoid (or an upper cap), a load."""
    kind = rng.uniform()
    n = int(rng.integers(7 if model == "F" else 3, 21))
    axes = rng.uniform(0.02, 0.06, size=3)
    if rng.uniform() < 0.3:
        axes[:] = axes[0]  # a sphere
    cap = 0.2 if kind < 0.1 else None  # contacts on an upper cap only: often infeasible
    contacts = [random_contact(rng, axes, cap) for _ in range(n)]
    if model == "H" and rng.uniform() < 0.1 and n >= 7:
        for c in contacts:
            c["mu"] = 0.0
    if rng.uniform() < 0.5:
        for c in contacts:
            c["w"] = rnd(rng.uniform(0.5, 2.0))
    force = rng.normal(size=3)
    force *= 5.0 * rng.uniform(0.2, 3.0) / np.linalg.norm(force)
    if cap is not None:
        force[2] = -abs(force[2]) - 2.0  # pushes the object down onto its upper contacts
    w_ext = np.concatenate([force, 0.05 * rng.normal(size=3)])
    return contacts, np.array([rnd(v) for v in w_ext])


def rescaled_instance(rng, model, scale):
    """A base-set grasp with every length times `scale`: positions, moments and mu_t."""
    contacts, w_ext = random_instance(rng, model)
    for c in contacts:
        c["p"] = np.array([rnd(scale * v) for v in c["p"]])
        c["mut"] = rnd(scale * c["mut"])
    w_ext[3:] = [rnd(scale * v) for v in w_ext[3:]]
    return contacts, w_ext


def line_instance(rng, model, offset):
    """Contacts along a coordinate axis (offset 0: G has rank 5 for hard fingers and
    frictionless points, no moment about the line) or off it by `offset` metres (nearly
    collinear), normals across the line; the load balanced by forces inside the cones (in the
    range of G), with its moment about the line removed, or unchanged (often out of range)."""
    n = int(rng.integers(7 if model == "F" else 3, 13))
    u = np.eye(3)[int(rng.integers(0, 3))]  # a coordinate axis: collinear after rounding too
    e1, e2 = tangent_basis(u)
    contacts = []
    for _ in range(n):
        s = rng.uniform(-0.05, 0.05)
        th = rng.uniform(0, 2 * np.pi)
        radial = np.cos(th) * e1 + np.sin(th) * e2
        p = s * u + offset * rng.normal() * radial
        a = -radial + 0.3 * rng.normal() * u
        a /= np.linalg.norm(a)
        contacts.append(dict(p=np.array([rnd(v) for v in p]), a=np.array([rnd(v) for v in a]),
                             mu=rnd(rng.uniform(0.2, 1.0)), mut=rnd(rng.uniform(0.002, 0.02)),
                             s=rnd(rng.uniform(0.0, 3.0)), w=rnd(rng.uniform(0.5, 2.0))))
    choice = rng.uniform()
    if choice < 0.4:
        d = {"H": 3, "S": 4, "F": 1}[model]
        x0 = np.zeros(n * d)
        for i, c in enumerate(contacts):  # inside each cone: mostly normal
            fn = rng.uniform(0.5, 3.0)
            if model == "F":
                x0[i] = fn
            else:
                t1, t2 = tangent_basis(c["a"])
                f = fn * c["a"] + 0.5 * c["mu"] * fn * (rng.uniform(-1, 1) * t1 + rng.uniform(-1, 1) * t2) / np.sqrt(2)
                x0[i * d:i * d + 3] = f
                if d == 4:
                    x0[i * d + 3] = 0.5 * c["mut"] * fn * rng.uniform(-1, 1)
        A = build(model, contacts, np.zeros(6))[5]
        w_ext = -(A @ x0)
    else:
        force = rng.normal(size=3)
        force *= 5.0 * rng.uniform(0.2, 3.0) / np.linalg.norm(force)
        w_ext = np.concatenate([force, 0.05 * rng.normal(size=3)])
        if choice < 0.7:
            w_ext[3:] -= np.dot(w_ext[3:], u) * u
    return contacts, np.array([rnd(v) for v in w_ext])


def bounded_instance(rng, model, kind):
    """A base-set grasp whose unbounded optimum x* (cvxopt's) sets bounds on the normal forces:
    bounded-inactive, every contact at 1.5 max_i f_n,i + 1 (the same optimum); bounded-active,
    the contacts of the largest third of f_n* at 0.8 of theirs (some at their bound, or a slip);
    bounded-low, every contact at 0.3 of its f_n* + 0.05 (mostly infeasible). None when the
    unbounded instance is not solved to 'optimal'."""
    contacts, w_ext = random_instance(rng, model)
    res = solve(model, contacts, w_ext)
    if res is None or res[0] != "optimal":
        return None
    x = res[4]
    d = {"H": 3, "S": 4, "F": 1}[model]
    fn = np.array([x[i * d] if model == "F" else float(np.dot(x[i * d:i * d + 3], c["a"]))
                   for i, c in enumerate(contacts)])
    if kind == "bounded-inactive":
        for c in contacts:
            c["c"] = rnd(1.5 * float(np.max(fn)) + 1.0)
    elif kind == "bounded-active":
        top = np.argsort(-fn)[:max(1, len(contacts) // 3)]
        if not fn[top[0]] > 0.05:
            return None
        for i in top:
            if fn[i] > 0.05:
                contacts[i]["c"] = rnd(0.8 * float(fn[i]))
    else:
        for i, c in enumerate(contacts):
            c["c"] = rnd(0.3 * max(float(fn[i]), 0.0) + 0.05)
    return contacts, w_ext


def record(out, k, model, kind, contacts, w_ext, res):
    status, obj, resid, gap, x, lam, lr, hard = res
    if hard:
        kind += "-hard"
    out.append("instance %d %s %d %s %.17g %.3g %.3g %s" % (k, model, len(contacts), status, obj, resid, gap, kind))
    out.append("w " + " ".join("%.10g" % v for v in w_ext))
    bounded = any("c" in c for c in contacts)
    for c in contacts:
        vals = list(c["p"]) + list(c["a"]) + [c["mu"], c["mut"], c["s"], c["w"]]
        if bounded:
            vals.append(c.get("c", -1.0))
        out.append("c " + " ".join("%.10g" % v for v in vals))
    if x is not None:
        out.append("x " + " ".join("%.17g" % v for v in x))
        out.append("l " + " ".join("%.17g" % v for v in lam))
    if lr is not None:
        out.append("r %.17g %.17g" % lr)


def main():
    out = []
    skipped = 0
    counts = {"H": [0, 0], "S": [0, 0], "F": [0, 0]}
    k = 0

    def take(model, kind, contacts, w_ext):
        nonlocal k, skipped
        res = solve(model, contacts, w_ext)
        if res is None:
            skipped += 1
            return False
        counts[model][0] += 1
        counts[model][1] += res[0] == "infeasible"
        record(out, k, model, kind, contacts, w_ext, res)
        k += 1
        return True

    rng = np.random.default_rng(SEED)
    base = 0
    while base < COUNT:
        model = "HSF"[base % 3]
        base += take(model, "random", *random_instance(rng, model))
    rng = np.random.default_rng(EXTRA_SEED)
    makers = [("rescaled-1e-3", lambda m: rescaled_instance(rng, m, 1e-3)),
              ("rescaled-1e3", lambda m: rescaled_instance(rng, m, 1e3)),
              ("collinear", lambda m: line_instance(rng, m, 0.0)),
              ("nearly-collinear", lambda m: line_instance(rng, m, 1e-4))]
    for kind, make in makers:
        done = 0
        while done < EXTRA_PER_KIND:
            model = "HSF"[done % 3]
            done += take(model, kind, *make(model))
    rng = np.random.default_rng(BOUND_SEED)
    for kind in ("bounded-inactive", "bounded-active", "bounded-low"):
        done = 0
        while done < BOUND_PER_KIND:
            model = "HSF"[done % 3]
            made = bounded_instance(rng, model, kind)
            if made is None:
                skipped += 1
                continue
            done += take(model, kind, *made)
    infeasible = sum(counts[m][1] for m in "HSF")
    head = ["# Generated by make_constrained_reference.py (cvxopt %s, seeds %d and %d): %d instances, "
            "%d infeasible, %d candidates discarded (feasibility or optimum undecided by cvxopt)."
            % (solvers.__dict__.get("__version__", "1.3"), SEED, EXTRA_SEED, k, infeasible, skipped),
            "# Bounded instances (kinds bounded-*) from seed %d." % BOUND_SEED,
            "# counts " + " ".join("%s %d %d" % (m, counts[m][0], counts[m][1]) for m in "HSF"),
            "# instance <k> <H|S|F> <n> <optimal|infeasible> <objective> <cvxopt residual |Gx+w|> <cvxopt gap> <kind>",
            "# w <w_ext: force; moment>", "# c <px py pz nx ny nz mu mu_t squeeze weight [bound]>",
            "# x <optimal forces x*>", "# l <multipliers lambda* of G x + w_ext = 0 (grip's sign)>",
            "# [bound]: max_normal_force (N) of the bounded instances' contacts, -1 for none",
            "# r <least residual |G x_c + w_ext|_L over the cones> <F2(x_c)> (infeasible instances;",
            "#   |(f, m)|_L = |(f, m / L)|, L = max_i |r_i|: moments per the longest lever arm)"]
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "constrained_reference.txt")
    with open(path, "w") as f:
        f.write("\n".join(head + out) + "\n")
    print("wrote %s: %d instances, %d infeasible, %d discarded" % (path, k, infeasible, skipped))


if __name__ == "__main__":
    main()
