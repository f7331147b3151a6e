"""grip from Python against independent derivations: the grasp matrix and the KKT system
built here from their definitions, the optima from NumPy's linear algebra, cvxopt's
solutions of the friction-cone problems (the reference data of the C++ suite), and SciPy's
of a pinch whose normal forces are bounded."""

import threading

import numpy as np
import pytest

import grip
from references import conic_reference, constrained_reference

MODELS = {"H": grip.Model.HardFinger, "S": grip.Model.SoftFinger, "F": grip.Model.FrictionlessPoint}
DIM = {grip.Model.HardFinger: 3, grip.Model.SoftFinger: 4, grip.Model.FrictionlessPoint: 1}


def skew(r):
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def random_contacts(rng, n):
    """n contacts on a 4 cm sphere, normals inwards but off the centre (else frictionless
    points have no moment arm), with random coefficients."""
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    a = -u + 0.5 * rng.uniform(-1, 1, size=(n, 3))
    a /= np.linalg.norm(a, axis=1)[:, None]
    return dict(positions=0.04 * u, normals=a, friction=rng.uniform(0.3, 0.9, n),
                torsional_friction=rng.uniform(0.002, 0.02, n), squeeze=rng.uniform(0.5, 3.0, n),
                weights=rng.uniform(0.5, 2.0, n))


def make(c, model):
    return grip.Grasp(c["positions"], c["normals"], c["friction"], torsional_friction=c["torsional_friction"],
                      squeeze=c["squeeze"], weights=c["weights"], model=model)


def grasp_matrix(c, model):
    """G from its definition (docs/conventions.md), block by block."""
    blocks = []
    for r, a in zip(c["positions"], c["normals"]):
        if model == grip.Model.HardFinger:
            blocks.append(np.vstack([np.eye(3), skew(r)]))
        elif model == grip.Model.SoftFinger:
            blocks.append(np.vstack([np.hstack([np.eye(3), np.zeros((3, 1))]), np.hstack([skew(r), a[:, None]])]))
        else:
            blocks.append(np.concatenate([a, np.cross(r, a)])[:, None])
    return np.hstack(blocks)


def normal_forces(g, forces):
    """f_n of every contact: f . a (a frictionless point's unknown is f_n itself)."""
    return forces[:, 0] if g.dim == 1 else np.einsum("ij,ij->i", forces[:, :3], g.normals)


def dual_cone_slack(g, y):
    """h_i = min of y . G_i x over x in contact i's cone with f_n = 1 (the cone's definition, per
    model): y . G_i x >= f_n h_i there, so h_i >= 0 says G_i^T y is in the dual cone K_i^*."""
    G = g.grasp_matrix()
    h = np.empty(g.size)
    for i in range(g.size):
        gi = G[:, i * g.dim:(i + 1) * g.dim].T @ y
        if g.dim == 1:
            h[i] = gi[0]
            continue
        a, mu = g.normals[i], g.friction[i]
        gt = gi[:3] - (gi[:3] @ a) * a
        spread = mu * np.linalg.norm(gt)
        if g.dim == 4:
            spread = np.hypot(spread, g.torsional_friction[i] * gi[3])
        h[i] = gi[:3] @ a - spread
    return h


def infeasibility_margin(g, y, w):
    """min over forces in the cones, each f_n <= max_normal_force, of y . (G x + w), over the
    bounded contacts: y . w + sum_i c_i min(0, h_i). Positive, with h_i >= 0 at the unbounded
    contacts, proves that no such forces balance w; returns it with the least unbounded h_i."""
    h = dual_cone_slack(g, y)
    c = g.max_normal_force
    bounded = np.isfinite(c)
    unbounded_h = h[~bounded].min() if (~bounded).any() else np.inf
    return y @ w + np.sum(c[bounded] * np.minimum(h[bounded], 0.0)), unbounded_h


def targets(c, model):
    s, a = c["squeeze"], c["normals"]
    if model == grip.Model.HardFinger:
        return s[:, None] * a
    if model == grip.Model.SoftFinger:
        return np.hstack([s[:, None] * a, np.zeros((len(s), 1))])
    return s[:, None]


@pytest.mark.parametrize("model", list(MODELS.values()))
def test_grasp_matrix_target_and_kkt_system_follow_their_definitions(model):
    rng = np.random.default_rng(1)
    for n in (1, 3, 7, 20, 64):
        c = random_contacts(rng, n)
        g = make(c, model)
        assert g.size == n and g.dim == DIM[model] and g.model == model
        G = grasp_matrix(c, model)
        assert np.array_equal(g.grasp_matrix(), G)
        assert np.array_equal(g.target(), targets(c, model))
        m = G.shape[1]
        W = np.diag(np.repeat(c["weights"], DIM[model]))
        H = np.block([[G, np.zeros((6, 6))], [W, -G.T]])
        assert np.array_equal(g.kkt_matrix(), H)
        w = rng.normal(size=6)
        b = np.concatenate([-w, W @ targets(c, model).ravel()])
        assert np.array_equal(g.kkt_rhs(w), b)
        assert g.kkt_matrix().shape == (6 + m, 6 + m)
        assert np.array_equal(g.positions, c["positions"]) and np.array_equal(g.weights, c["weights"])


@pytest.mark.parametrize("model", list(MODELS.values()))
def test_range_space_and_kkt_give_the_least_squares_optimum(model):
    rng = np.random.default_rng(2)
    for n in (3, 5, 10, 20):
        c = random_contacts(rng, n)
        g = make(c, model)
        w = np.concatenate([rng.normal(scale=5.0, size=3), rng.normal(scale=0.1, size=3)])
        if model == grip.Model.FrictionlessPoint and n < 6:  # fewer than 6 unknowns: rank < 6
            assert grip.solve_range_space(g, w).status == grip.Status.Singular
            assert grip.solve_kkt(g, w).status == grip.Status.Singular
            continue
        G = grasp_matrix(c, model)
        t = targets(c, model).ravel()
        winv = 1.0 / np.repeat(c["weights"], DIM[model])
        # x = t + W^-1 G^T lambda with G x + w = 0: (G W^-1 G^T) lambda = -(G t + w).
        lam = np.linalg.solve(G @ (winv[:, None] * G.T), -(G @ t + w))
        x = t + winv * (G.T @ lam)
        scale = 1 + np.abs(x).max()
        for solve in (grip.solve_range_space, grip.solve_kkt):
            s = solve(g, w)
            assert s.status == grip.Status.Ok, (solve.__name__, n)
            assert s.forces.shape == (n, DIM[model])
            assert np.abs(s.forces.ravel() - x).max() <= 1e-9 * scale
            assert np.abs(G @ s.forces.ravel() + w).max() <= 1e-9 * scale
            assert s.residual <= 1e-9 * scale
            # W (x - t) = G^T lambda.
            assert np.abs(s.multipliers - lam).max() <= 1e-8 * (1 + np.abs(lam).max())


def test_constrained_solver_agrees_with_cvxopt():
    counts = {"Ok": 0, "Infeasible": 0, "bounded": 0, "at bound": 0}
    for ref in constrained_reference():
        c = ref["contacts"]
        model = MODELS[ref["model"]]
        g = grip.Grasp(c[:, 0:3], c[:, 3:6], c[:, 6], torsional_friction=c[:, 7], squeeze=c[:, 8], weights=c[:, 9],
                       max_normal_force=c[:, 10], model=model)
        assert np.array_equal(g.max_normal_force, c[:, 10])
        s = grip.solve_constrained(g, ref["w"])
        G = g.grasp_matrix()
        # Whatever the status, the forces keep the bounds (and the cones: the monitor's tests).
        assert np.all(normal_forces(g, s.forces) <= c[:, 10] * (1 + 1e-9))
        if np.isfinite(c[:, 10]).any():
            counts["bounded"] += 1
            counts["at bound"] += grip.monitor(g, s.forces).at_bound_count > 0
        if ref["feasible"]:
            assert s.status == grip.Status.Ok
            counts["Ok"] += 1
            x = s.forces.ravel()
            f2 = 0.5 * np.sum(np.repeat(c[:, 9], g.dim) * (x - g.target().ravel()) ** 2)
            assert abs(f2 - ref["objective"]) <= 1e-6 * max(ref["objective"], 1e-12) + 1e-9
            scale = 1 + np.abs(x).max() + np.abs(ref["w"]).max()
            assert np.abs(G @ x + ref["w"]).max() <= 1e-8 * scale
        else:
            assert s.status == grip.Status.Infeasible
            counts["Infeasible"] += 1
            y = s.certificate
            assert y @ ref["w"] > 0
            # Every wrench the contacts can apply has y . w >= 0: G_i^T y in the dual cones (to
            # the certificate's tolerance, per lever arm), and the bounded contacts cannot make
            # up y . w.
            margin, least = infeasibility_margin(g, y, ref["w"])
            assert least >= -1e-5 * (1 + np.linalg.norm(g.positions, axis=1).max() / 0.05)
            assert margin > 0
    assert counts["Ok"] > 200 and counts["Infeasible"] > 100
    assert counts["bounded"] >= 45 and counts["at bound"] >= 15, counts


def test_a_slip_decided_from_the_previous_certificate():
    # Three fingers on top of an object pushing down, loaded downwards: no force in the cones
    # pushes up, so y = (0, 0, -1, 0, 0, 0) (scaled) certifies the slip (Farkas, by hand). A
    # certificate that fails (the opposite direction) changes nothing.
    phi = 2 * np.pi * np.arange(3) / 3
    positions = np.stack([0.02 * np.cos(phi), 0.02 * np.sin(phi), np.full(3, 0.03)], axis=1)
    g = grip.Grasp(positions, np.tile([0.0, 0.0, -1.0], (3, 1)), 0.8, squeeze=1.0)
    w = np.array([0.0, 0.0, -5.0, 0.01, 0.0, 0.0])
    cold = grip.solve_constrained(g, w)
    assert cold.status == grip.Status.Infeasible
    warm = grip.solve_constrained(g, w, warm_certificate=[0.0, 0.0, -3.0, 0.0, 0.0, 0.0])
    assert warm.status == grip.Status.Infeasible
    assert warm.passes < cold.passes
    np.testing.assert_allclose(warm.certificate, [0, 0, -1, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(warm.forces, cold.forces, rtol=1e-9, atol=1e-12)
    wrong = grip.solve_constrained(g, w, warm_certificate=[0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    assert wrong.status == cold.status and np.array_equal(wrong.forces, cold.forces)
    assert wrong.passes == cold.passes


def test_warm_start_and_settings_reach_the_same_optimum():
    rng = np.random.default_rng(3)
    c = random_contacts(rng, 8)
    c["friction"] = np.full(8, 0.3)
    g = make(c, grip.Model.HardFinger)
    w = np.array([0.0, 0.0, -30.0, 0.2, 0.0, 0.0])
    cold = grip.solve_constrained(g, w)
    assert cold.status == grip.Status.Ok and not cold.fast_path
    warm = grip.solve_constrained(g, w, warm_start=cold.multipliers)
    assert warm.status == grip.Status.Ok
    assert np.abs(warm.forces - cold.forces).max() <= 1e-8 * (1 + np.abs(cold.forces).max())
    assert warm.iterations <= cold.iterations
    assert cold.refined and warm.refined
    # Without Newton's refinement: the interior-point answer, optimal to its tolerance.
    settings = grip.ConstrainedSettings()
    settings.newton_passes = 0
    unrefined = grip.solve_constrained(g, w, settings)
    assert unrefined.status == grip.Status.Ok and not unrefined.refined and unrefined.iterations > 0
    assert abs(unrefined.objective - cold.objective) <= 1e-6 * cold.objective
    # Cut short: at most two interior-point iterations (three passes each, one more per run: the
    # optimum's, then the one it resumes), no Newton pass.
    settings.max_iterations = 2
    short = grip.solve_constrained(g, w, settings)
    assert short.status == grip.Status.IterationLimit and not short.refined
    assert short.iterations <= 2 and short.passes <= 3 * 2 + 2
    assert grip.monitor(g, short.forces).min_margin >= -1e-9 * np.abs(short.forces).max()  # still in the cones
    # Settings out of their domain answer InvalidInput, as in C++.
    for name, bad in (("max_iterations", 0), ("newton_passes", -1), ("tolerance", 0.0), ("certificate_tolerance", 1.0),
                      ("least_residual_weight", float("nan"))):
        settings = grip.ConstrainedSettings()
        setattr(settings, name, bad)
        assert grip.solve_constrained(g, w, settings).status == grip.Status.InvalidInput, name


def test_constrained_settings_expose_exactly_the_solvers_fields():
    settings = grip.ConstrainedSettings()
    fields = {name for name in dir(settings) if not name.startswith("_")}
    assert fields == {"tolerance", "certificate_tolerance", "least_residual_weight", "max_iterations", "newton_passes"}
    assert settings.max_iterations == 40 and settings.newton_passes == 8
    assert 0 < settings.tolerance < 1e-9 and 0 < settings.certificate_tolerance < 1e-3
    for name in fields:
        assert getattr(grip.ConstrainedSettings, name).__doc__, name


def with_bounds(g, bounds):
    """g's contacts with max_normal_force = bounds."""
    return grip.Grasp(g.positions, g.normals, g.friction, torsional_friction=g.torsional_friction, squeeze=g.squeeze,
                      weights=g.weights, model=g.model, max_normal_force=bounds)


@pytest.mark.parametrize("model", list(MODELS.values()))
def test_an_inactive_bound_changes_nothing(model):
    rng = np.random.default_rng(21)
    checked = {"fast path": 0, "cones active": 0}
    for trial in range(16):
        c = random_contacts(rng, 10 if model != grip.Model.FrictionlessPoint else 24)
        wide = trial % 2 == 0  # wide cones and a firm squeeze against a light load: the fast path
        c["friction"] = np.full(len(c["friction"]), 2.0 if wide else 0.25)
        if wide:
            c["squeeze"] *= 5.0
            c["torsional_friction"] = np.full(len(c["friction"]), 0.05)
            if model == grip.Model.FrictionlessPoint:  # pushes that balance: an internal force, each >= 5 N
                closure = grip.force_closure(make(c, model))
                if closure.closure:
                    c["squeeze"] = 5.0 * closure.internal_force[:, 0] / closure.margin
        g = make(c, model)
        w = np.concatenate([rng.normal(scale=0.5 if wide else 3.0, size=3),
                            rng.normal(scale=0.01 if wide else 0.05, size=3)])
        free = grip.solve_constrained(g, w)
        if free.status != grip.Status.Ok:
            continue
        bounds = 1.5 * np.abs(normal_forces(g, free.forces)) + 0.5
        gb = with_bounds(g, bounds)
        bounded = grip.solve_constrained(gb, w)
        assert bounded.status == grip.Status.Ok and bounded.fast_path == free.fast_path
        assert grip.monitor(gb, bounded.forces).at_bound_count == 0
        if bounded.refined and free.refined:  # both exact projections: the same optimum to round-off
            scale = 1 + np.abs(free.forces).max()
            assert np.abs(bounded.forces - free.forces).max() <= 1e-8 * scale
            assert abs(bounded.objective - free.objective) <= 1e-9 * (1 + free.objective)
        else:
            # The interior-point method's answer (bounded soft fingers have it alone; an unbounded
            # soft finger's when Newton's refinement does not finish): optimal to its tolerance,
            # 1e-7 of F2, and by F2's strong convexity (modulus min w_i) within sqrt(2 gap / min w_i)
            # of the optimum. Below it by at most |lambda| |r|: the forces balance w_ext to the residual.
            assert model == grip.Model.SoftFinger
            gap = 1e-7 * free.objective
            below = np.linalg.norm(bounded.multipliers) * bounded.residual + np.linalg.norm(free.multipliers) * free.residual
            assert abs(bounded.objective - free.objective) <= gap + below
            assert np.linalg.norm(bounded.forces - free.forces) <= 2 * np.sqrt(2 * gap / g.weights.min())
        checked["fast path" if free.fast_path else "cones active"] += 1
    assert checked["fast path"] >= 3 and checked["cones active"] >= 3, checked


def pinch(bounds):
    """Two hard fingers pinching a 0.6 kg box from its sides at x = 3 and -2 cm (on a line through
    its centre of mass: two fingers resist no moment about that line), mu 0.5, squeezing harder
    than needed (targets 8 and 12 N, weights 1 and 2); w_ext: the weight, a push of 1 N towards
    -x and 0.02 N m about y. Equilibrium fixes the tangential forces (2.75 and 3.13 N up) and
    f_n2 = f_n1 + 1, so the fingers need f_n1 >= 5.51 N; unbounded, f_n = (10, 11) N."""
    p = np.array([[0.03, 0.0, 0.0], [-0.02, 0.0, 0.0]])
    a = np.array([[-1.0, 0, 0], [1.0, 0, 0]])
    g = grip.Grasp(p, a, 0.5, squeeze=[8.0, 12.0], weights=[1.0, 2.0], max_normal_force=bounds)
    return g, np.array([-1.0, 0.0, -0.6 * 9.81, 0.0, 0.02, 0.0])


def scipy_optimum(g, w, bounds):
    """min F2 over the same problem by SciPy's SLSQP, from the definitions: G x + w = 0 (its rows
    on the range of G: two contacts cannot apply a moment about the line joining them), mu f_n
    >= |f_t| (squared, with f_n >= 0: smooth) and f_n <= the bound."""
    optimize = pytest.importorskip("scipy.optimize")
    G, t, wt = g.grasp_matrix(), g.target().ravel(), np.repeat(g.weights, 3)
    u, sv, _ = np.linalg.svd(G)
    Q = u[:, sv > 1e-9 * sv[0]]
    assert np.linalg.norm(w - Q @ (Q.T @ w)) <= 1e-12 * np.linalg.norm(w)  # balanceable at all

    def parts(x):
        f = x.reshape(-1, 3)
        fn = np.einsum("ij,ij->i", f, g.normals)
        return fn, f - fn[:, None] * g.normals

    constraints = [
        {"type": "eq", "fun": lambda x: Q.T @ (G @ x + w), "jac": lambda x: Q.T @ G},
        {"type": "ineq", "fun": lambda x: (g.friction * parts(x)[0]) ** 2 - np.sum(parts(x)[1] ** 2, axis=1)},
        {"type": "ineq", "fun": lambda x: parts(x)[0]},
        {"type": "ineq", "fun": lambda x: bounds - parts(x)[0]},
    ]
    x0 = np.ravel(0.5 * np.minimum(bounds, g.squeeze)[:, None] * g.normals)
    r = optimize.minimize(lambda x: 0.5 * np.sum(wt * (x - t) ** 2), x0, jac=lambda x: wt * (x - t), method="SLSQP",
                          constraints=constraints, options={"ftol": 1e-14, "maxiter": 500})
    assert r.success, r.message
    return r.x.reshape(-1, 3), r.fun


def test_a_pinch_bounded_below_its_optimum_holds_at_the_bound():
    free_g, w = pinch(np.inf)
    free = grip.solve_constrained(free_g, w)
    assert free.status == grip.Status.Ok
    free_fn = normal_forces(free_g, free.forces)
    assert np.allclose(free_fn, [10.0, 11.0], rtol=1e-9)
    # The first finger can give 7 N, enough to hold the box (5.51 N), not what it would like
    # (10 N); the second's bound is not reached.
    bounds = np.array([7.0, 20.0])
    assert free_fn[0] > bounds[0]
    g, _ = pinch(bounds)
    s = grip.solve_constrained(g, w)
    assert s.status == grip.Status.Ok and not s.fast_path
    fn = normal_forces(g, s.forces)
    assert np.all(fn <= bounds * (1 + 1e-9))
    at_bound = np.abs(fn - bounds) <= 1e-9 * bounds
    assert at_bound.sum() >= 1  # a finger gives all it can
    assert np.allclose(fn, [7.0, 8.0], rtol=1e-9)  # the analysis above: f_n1 = 7, f_n2 = f_n1 + 1
    G = g.grasp_matrix()
    assert np.linalg.norm(G @ s.forces.ravel() + w) <= 1e-9 * (np.linalg.norm(w) + np.abs(s.forces).max())
    report = grip.monitor(g, s.forces)
    assert report.stable and report.at_bound_count >= 1 and report.at_bound.dtype == bool
    assert np.array_equal(report.at_bound, at_bound)
    # The same optimum by SciPy from the definitions; grip's is no worse, and the same point.
    x, f2 = scipy_optimum(g, w, bounds)
    assert s.objective <= f2 * (1 + 1e-9)
    assert abs(s.objective - f2) <= 1e-6 * f2
    assert np.abs(s.forces - x).max() <= 1e-4 * np.abs(x).max()
    t = g.target()
    assert abs(s.objective - 0.5 * np.sum(g.weights[:, None] * (s.forces - t) ** 2)) <= 1e-12 * s.objective
    assert s.objective > free.objective  # the bound costs something


def test_a_bound_too_low_to_hold_the_weight_is_infeasible_with_a_certificate():
    g, w = pinch(np.array([4.0, 4.0]))  # the first finger needs 5.51 N
    s = grip.solve_constrained(g, w)
    assert s.status == grip.Status.Infeasible
    y = s.certificate
    assert y @ w > 0 and np.all(s.multipliers == 0)
    # It proves that no forces in the cones below the bounds balance w: each finger's cone
    # alone is no obstacle (y . G_i x can be negative), but not enough below the bounds.
    margin, _ = infeasibility_margin(g, y, w)
    assert margin > 0 and np.any(dual_cone_slack(g, y) < 0)
    # The forces that come closest still keep the bounds and the cones.
    assert np.all(normal_forces(g, s.forces) <= 4.0 * (1 + 1e-9))
    assert grip.monitor(g, s.forces).min_margin >= -1e-9 * np.abs(s.forces).max()
    assert s.residual > 0.1
    # Unbounded, the same fingers hold it.
    assert grip.solve_constrained(pinch(np.inf)[0], w).status == grip.Status.Ok


def test_max_normal_force_is_per_contact_and_read_back():
    p, a = np.eye(3) * 0.04, -np.eye(3)
    assert np.all(np.isinf(grip.Grasp(p, a, 0.5).max_normal_force))
    assert np.array_equal(grip.Grasp(p, a, 0.5, max_normal_force=3.0).max_normal_force, [3.0, 3.0, 3.0])
    bounds = [1.0, np.inf, 1e15]
    assert np.array_equal(grip.Grasp(p, a, 0.5, max_normal_force=bounds).max_normal_force, bounds)


def test_force_closure_agrees_with_cvxopt():
    checked = 0
    for ref in conic_reference():
        if ref["margin"] is None:
            continue
        c = ref["contacts"]
        g = grip.Grasp(c[:, 0:3], c[:, 3:6], c[:, 6], torsional_friction=c[:, 7], squeeze=1.0,
                       model=MODELS[ref["model"]])
        f = grip.force_closure(g)
        assert f.status == grip.Status.Ok
        lo, hi = ref["margin"]
        tol = grip.ConicAnalysisSettings().tolerance  # Ok: the margin bracketed within it
        assert lo - tol * (1 + abs(lo)) <= f.margin <= hi + tol * (1 + abs(lo))
        if f.closure:
            assert np.abs(g.grasp_matrix() @ f.internal_force.ravel()).max() <= 1e-9
        checked += 1
    assert checked > 100


def test_force_closure_of_textbook_grasps():
    # Three hard fingers 120 degrees apart on a disc, mu 0.5: force closure.
    angles = np.radians([0, 120, 240])
    p = 0.04 * np.stack([np.cos(angles), np.sin(angles), np.zeros(3)], axis=1)
    f = grip.force_closure(grip.Grasp(p, -p / 0.04, 0.5))
    assert f.closure and f.margin > 0 and np.all(f.unresisted == 0)
    # Two antipodal hard fingers cannot resist a moment about the line joining them (rank 5).
    p2 = np.array([[0.04, 0, 0], [-0.04, 0, 0]])
    f2 = grip.force_closure(grip.Grasp(p2, -p2 / 0.04, 0.5))
    assert not f2.closure and f2.rank == 5
    u = f2.unresisted
    assert abs(np.linalg.norm(u) - 1) < 1e-12 and abs(abs(u[3]) / np.linalg.norm(u[3:])) > 1 - 1e-9
    # Frictionless points pressing from one side only: no closure, and the certificate pulls away.
    p3 = np.array([[0.0, 0.0, -0.04], [0.02, 0.0, -0.04], [0.0, 0.02, -0.04], [0.01, 0.01, -0.04],
                   [-0.02, 0.0, -0.04], [0.0, -0.02, -0.04], [0.01, -0.01, -0.04]])
    a3 = np.tile([0.0, 0.0, 1.0], (7, 1))
    f3 = grip.force_closure(grip.Grasp(p3, a3, 0.0, model=grip.Model.FrictionlessPoint))
    assert not f3.closure


def test_conic_analysis_settings_are_read_and_used():
    s = grip.ConicAnalysisSettings()
    assert s.tolerance == 1e-6 and s.max_iterations == 50
    angles = np.radians([0, 130, 250])
    p = 0.04 * np.stack([np.cos(angles), np.sin(angles), 0.01 * angles], axis=1)
    g = grip.Grasp(p, -p / np.linalg.norm(p, axis=1)[:, None], 0.5)
    full = grip.force_closure(g, s)
    assert full.status == grip.Status.Ok and full.iterations > 2
    s.max_iterations = 2
    cut = grip.force_closure(g, s)
    # Cut short: not decided, and the margin an upper bound on the converged one.
    assert cut.status == grip.Status.IterationLimit and not cut.closure and cut.margin >= full.margin
    assert np.all(cut.unresisted == 0)
    s.max_iterations = 0
    assert grip.force_closure(g, s).status == grip.Status.InvalidInput


BAD = [
    (dict(positions=np.zeros((3, 2))), "positions must have shape (n, 3), not (3, 2)"),
    (dict(positions=[[0, 0, 0], [0, np.nan, 0], [0, 0, 0]]), "positions[1] is not finite"),
    (dict(normals=[[1, 0, 0], [0, 1, 0], [0, 0, 1.01]]), "normals[2] must be a unit vector"),
    (dict(normals=np.eye(3)[:2]), "normals must have as many rows as positions (3), not 2"),
    (dict(friction=[0.5, -0.1, 0.5]), "friction[1] must be >= 0"),
    (dict(friction=[0.5, 0.5]), "friction must be a number or have shape (3,), not (2,)"),
    (dict(squeeze=np.inf), "squeeze is not finite"),
    (dict(weights=[1.0, 1.0, 0.0]), "weights[2] must be >= 1e-12"),
    (dict(torsional_friction=-1.0), "torsional_friction must be >= 0"),
    (dict(max_normal_force=0.0), "max_normal_force must be > 0"),
    (dict(max_normal_force=-np.inf), "max_normal_force must be > 0"),
    (dict(max_normal_force=[1.0, np.nan, 1.0]), "max_normal_force[1] must be > 0"),
    (dict(max_normal_force=[1.0, 1.0, -2.0]), "max_normal_force[2] must be > 0"),
    (dict(max_normal_force=2e15), "max_normal_force must be > 0 (and at most 1e15, or inf for no bound)"),
    (dict(max_normal_force=[1.0, 1.0]), "max_normal_force must be a number or have shape (3,), not (2,)"),
    (dict(positions=np.zeros((0, 3)), normals=np.zeros((0, 3))), "a grasp has 1 to 64 contacts, not 0"),
    (dict(positions=np.zeros((65, 3)), normals=np.tile([0, 0, 1.0], (65, 1))), "a grasp has 1 to 64 contacts, not 65"),
]


@pytest.mark.parametrize("change,message", BAD)
def test_invalid_input_raises_value_error_naming_field_and_index(change, message):
    args = dict(positions=np.eye(3) * 0.04, normals=-np.eye(3), friction=0.5, squeeze=1.0, weights=1.0,
                torsional_friction=0.0)
    args.update(change)
    with pytest.raises(ValueError) as e:
        grip.Grasp(args.pop("positions"), args.pop("normals"), args.pop("friction"), **args)
    assert message in str(e.value)


def test_invalid_wrench_raises_value_error():
    g = grip.Grasp(np.eye(3) * 0.04, -np.eye(3), 0.5)
    for w, message in ((np.zeros(5), "w_ext must have shape (6,)"), ([0, 0, np.nan, 0, 0, 0], "w_ext[2] is not finite")):
        for solve in (grip.solve_range_space, grip.solve_kkt, grip.solve_constrained):
            with pytest.raises(ValueError) as e:
                solve(g, w)
            assert message in str(e.value)
    with pytest.raises(ValueError, match=r"warm_start\[0\] is not finite"):
        grip.solve_constrained(g, np.zeros(6), warm_start=[np.inf, 0, 0, 0, 0, 0])
    with pytest.raises(ValueError, match=r"warm_certificate\[3\] is not finite"):
        grip.solve_constrained(g, np.zeros(6), warm_certificate=[0, 0, 0, np.nan, 0, 0])


def test_statuses_are_reported_not_raised():
    # One contact cannot balance a general wrench: rank 3 < 6.
    g = grip.Grasp([[0.04, 0, 0]], [[-1.0, 0, 0]], 0.5)
    assert grip.solve_range_space(g, np.ones(6)).status == grip.Status.Singular
    # Pulling an object off frictionless supports: no push can hold it.
    p = np.array([[0.02, 0.0, -0.04], [-0.01, 0.017, -0.04], [-0.01, -0.017, -0.04]])
    g3 = grip.Grasp(p, np.tile([0.0, 0.0, 1.0], (3, 1)), 0.0)
    s = grip.solve_constrained(g3, np.array([0.0, 0.0, 10.0, 0.0, 0.0, 0.0]))
    assert s.status == grip.Status.Infeasible and s.certificate[2] > 0
    assert str(grip.Status.Infeasible) == "Status.Infeasible"


def test_solves_in_threads_match_the_serial_ones():
    rng = np.random.default_rng(4)
    grasps = [make(random_contacts(rng, 20), grip.Model.HardFinger) for _ in range(16)]
    w = np.array([0.0, 0.0, -20.0, 0.1, 0.0, 0.0])
    serial = [grip.solve_constrained(g, w).forces for g in grasps]
    results = [None] * len(grasps)

    def work(k):
        for _ in range(20):
            results[k] = grip.solve_constrained(grasps[k], w).forces

    threads = [threading.Thread(target=work, args=(k,)) for k in range(len(grasps))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(serial, results):
        assert np.array_equal(a, b)


def test_the_example_of_the_docs_runs():
    import os
    import re

    text = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs", "python.md")).read()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks
    scope = {}
    exec(compile(blocks[0], "docs/python.md", "exec"), scope)  # the "Use" section's example
    assert scope["held"].status == grip.Status.Ok and scope["held"].forces.shape == (3, 3)
