"""grip from Python against independent derivations: the grasp matrix and the KKT system
built here from their definitions, the optima from NumPy's linear algebra, and cvxopt's
solutions of the friction-cone problems (the reference data of the C++ suite)."""

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
    counts = {"Ok": 0, "Infeasible": 0}
    for ref in constrained_reference():
        c = ref["contacts"]
        model = MODELS[ref["model"]]
        g = grip.Grasp(c[:, 0:3], c[:, 3:6], c[:, 6], torsional_friction=c[:, 7], squeeze=c[:, 8], weights=c[:, 9],
                       model=model)
        s = grip.solve_constrained(g, ref["w"])
        G = g.grasp_matrix()
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
            # Every wrench the contacts can apply has y . w >= 0: here at the cone's axis.
            axis = np.hstack([g.normals, np.zeros((g.size, 1))])[:, : g.dim] if g.dim > 1 else np.ones((g.size, 1))
            for i in range(g.size):
                gi = G[:, i * g.dim:(i + 1) * g.dim]
                assert y @ (gi @ axis[i]) >= -1e-5 * (1 + np.linalg.norm(g.positions[i]) / 0.05)
    assert counts["Ok"] > 200 and counts["Infeasible"] > 100


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
    settings = grip.ConstrainedSettings()
    settings.max_passes = 1
    short = grip.solve_constrained(g, w, settings)
    assert short.status == grip.Status.IterationLimit and short.passes <= 1


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
        assert lo - 1e-9 * (1 + abs(lo)) <= f.margin <= hi + 1e-9 * (1 + abs(lo))
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
