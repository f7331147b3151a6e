"""Grasp quality, the force split, epsilon and the batch functions, against NumPy's SVD and
null spaces, qhull's convex hulls (SciPy) and the single calls."""

import itertools

import numpy as np
import pytest

import grip
from test_grip import DIM, grasp_matrix, make, random_contacts

MODELS = list(DIM)


def scaled(G, rho):
    return np.vstack([G[:3], G[3:] / rho])


@pytest.mark.parametrize("model", MODELS)
def test_grasp_quality_is_the_svd_of_the_scaled_grasp_matrix(model):
    rng = np.random.default_rng(5)
    for n in (2, 4, 9):
        c = random_contacts(rng, n)
        g = make(c, model)
        rho = 0.04
        s = np.linalg.svd(scaled(grasp_matrix(c, model), rho), compute_uv=False)
        s = np.concatenate([s, np.zeros(6 - len(s))])
        q = grip.grasp_quality(g, lever_length=rho)
        assert q.status == grip.Status.Ok
        # From the eigenvalues of the 6x6 Gram matrix: sqrt(eps) of sigma_max absolute.
        assert np.allclose(q.singular_values, s, rtol=1e-12, atol=1e-7 * s[0])
        vol_abs = np.pi ** 3 / 6 * np.prod(s[:5]) * 1e-7 * s[0]  # from sigma_6's error bound
        assert q.volume == pytest.approx(np.pi ** 3 / 6 * np.prod(s), rel=1e-10, abs=vol_abs + 1e-300)
        assert q.isotropy == pytest.approx(s[5] / s[0], rel=1e-10, abs=1e-7)


@pytest.mark.parametrize("model", MODELS)
def test_force_split_is_internal_plus_the_weighted_projection(model):
    rng = np.random.default_rng(6)
    c = random_contacts(rng, 8)
    g = make(c, model)
    x = rng.normal(size=(8, DIM[model]))
    d = grip.decompose_forces(g, x)
    ext, inn, status = d.external, d.internal, d.status
    assert isinstance(d, grip.ForceDecomposition)
    assert status == grip.Status.Ok
    unpacked = tuple(d)  # unpacks as (external, internal, status), as before
    assert np.array_equal(unpacked[0], ext) and np.array_equal(unpacked[1], inn) and unpacked[2] == status
    G = grasp_matrix(c, model)
    W = np.repeat(c["weights"], DIM[model])
    assert np.allclose(ext + inn, x, atol=1e-13)
    assert np.abs(G @ inn.ravel()).max() <= 1e-12 * (1 + np.abs(x).max())
    # The external part is W-orthogonal to every internal force (null space of G by SVD).
    null = np.linalg.svd(G)[2][6:].T
    assert np.abs(null.T @ (W * ext.ravel())).max() <= 1e-12 * (1 + np.abs(x).max())


def primitives(c, model, sides, rho):
    """The primitive wrenches of epsilon (docs/analysis.md): per contact the pyramid's edges
    with unit normal part, moments / rho; soft fingers also +-mu_t torsion; points: a."""
    out = []
    for r, a, mu, mut in zip(c["positions"], c["normals"], c["friction"], c["torsional_friction"]):
        e = np.array([0.0, 1.0, 0.0]) if abs(a[0]) > 0.9 else np.array([1.0, 0.0, 0.0])
        t1 = np.cross(a, e)
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(a, t1)
        mine = []
        dirs = [a] if model == grip.Model.FrictionlessPoint else [
            a + mu * (np.cos(th) * t1 + np.sin(th) * t2) for th in 2 * np.pi * np.arange(sides) / sides]
        for d in dirs:
            mine.append(np.concatenate([d, np.cross(r, d) / rho]))
        if model == grip.Model.SoftFinger:
            for m in (mut, -mut):
                mine.append(np.concatenate([a, (np.cross(r, a) + m * a) / rho]))
        out.append(np.array(mine))
    return out


def hull_epsilon(points):
    from scipy.spatial import ConvexHull

    h = ConvexHull(points)
    # qhull's facets: normal . x + offset <= 0 inside; the origin's distance is -offset.
    return max(0.0, float(np.min(-h.equations[:, -1])))


@pytest.mark.parametrize("model", [grip.Model.HardFinger, grip.Model.SoftFinger])
def test_epsilon_equals_the_hull_distance_from_qhull(model):
    pytest.importorskip("scipy")
    rng = np.random.default_rng(7)
    for n in (3, 4):
        c = random_contacts(rng, n)
        g = make(c, model)
        rho = 0.04
        prim = primitives(c, model, 8, rho)
        l1 = hull_epsilon(np.vstack([np.zeros((1, 6))] + prim))
        e = grip.epsilon(g, "L1", lever_length=rho, sides=8)
        assert e.status == grip.Status.Ok
        assert e.epsilon == pytest.approx(l1, rel=1e-7, abs=1e-12)
        # L-infinity: the Minkowski sum of the contacts' hulls, every sum of one point of each
        # (4-sided pyramids keep the (K + 1)^n points few enough for qhull).
        prim = primitives(c, model, 4, rho)
        sums = [np.sum(choice, axis=0) for choice in itertools.product(*[np.vstack([np.zeros((1, 6)), p]) for p in prim])]
        linf = hull_epsilon(np.array(sums))
        e = grip.epsilon(g, "Linf", lever_length=rho, sides=4)
        assert e.status == grip.Status.Ok
        assert e.epsilon == pytest.approx(linf, rel=1e-7, abs=1e-12)


def batch_contacts(rng, k, n):
    cs = [random_contacts(rng, n) for _ in range(k)]
    return {key: np.stack([c[key] for c in cs]) for key in cs[0]}


@pytest.mark.parametrize("model", MODELS)
def test_evaluate_batch_equals_the_single_calls_on_any_number_of_threads(model):
    rng = np.random.default_rng(8)
    b = batch_contacts(rng, 24, 7)
    args = dict(torsional_friction=b["torsional_friction"], squeeze=b["squeeze"], weights=b["weights"], model=model,
                lever_length=0.04, epsilon_linf=model != grip.Model.SoftFinger, sides=4)
    runs = [grip.evaluate_batch(b["positions"], b["normals"], b["friction"], threads=t, **args) for t in (1, 2, 5)]
    for r in runs[1:]:
        for key in r:
            assert np.array_equal(r[key], runs[0][key]), key
    r = runs[0]
    for j in range(24):
        g = grip.Grasp(b["positions"][j], b["normals"][j], b["friction"][j], torsional_friction=b["torsional_friction"][j],
                       squeeze=b["squeeze"][j], weights=b["weights"][j], model=model)
        assert np.array_equal(grip.grasp_quality(g, 0.04).singular_values, r["singular_values"][j])
        fc = grip.force_closure(g)
        assert fc.margin == r["closure_margin"][j] and fc.closure == r["closure"][j]
        assert grip.epsilon(g, "L1", 0.04, 4).epsilon == r["epsilon_l1"][j]
        if args["epsilon_linf"]:
            assert grip.epsilon(g, "Linf", 0.04, 4).epsilon == r["epsilon_linf"][j]
        assert r["status"][j] == int(grip.Status.Ok)


@pytest.mark.parametrize("method", ["range_space", "kkt", "constrained"])
def test_solve_batch_equals_the_single_calls(method):
    rng = np.random.default_rng(9)
    b = batch_contacts(rng, 30, 5)
    w = rng.normal(scale=[5, 5, 20, 0.1, 0.1, 0.1], size=(30, 6))
    single = {"range_space": grip.solve_range_space, "kkt": grip.solve_kkt, "constrained": grip.solve_constrained}[method]
    r = grip.solve_batch(b["positions"], b["normals"], b["friction"], w, squeeze=b["squeeze"], weights=b["weights"],
                         method=method, threads=3)
    assert r["forces"].shape == (30, 5, 3)
    for j in range(30):
        g = grip.Grasp(b["positions"][j], b["normals"][j], b["friction"][j], squeeze=b["squeeze"][j], weights=b["weights"][j])
        s = single(g, w[j])
        assert np.array_equal(s.forces, r["forces"][j]) and np.array_equal(s.multipliers, r["multipliers"][j])
        assert s.residual == r["residual"][j] and int(s.status) == r["status"][j] and s.iterations == r["iterations"][j]
        if method == "constrained":
            assert np.array_equal(s.certificate, r["certificate"][j])


def test_solve_batch_keeps_the_bounds_as_the_single_calls():
    rng = np.random.default_rng(19)
    b = batch_contacts(rng, 20, 5)
    w = rng.normal(scale=[2, 2, 10, 0.05, 0.05, 0.05], size=(20, 6))
    bounds = rng.uniform(1.0, 6.0, size=(20, 5))
    bounds[:, 0] = np.inf  # a contact without a bound in every candidate
    r = grip.solve_batch(b["positions"], b["normals"], b["friction"], w, squeeze=b["squeeze"], weights=b["weights"],
                         max_normal_force=bounds, method="constrained", threads=2)
    statuses = set()
    for j in range(20):
        g = grip.Grasp(b["positions"][j], b["normals"][j], b["friction"][j], squeeze=b["squeeze"][j],
                       weights=b["weights"][j], max_normal_force=bounds[j])
        s = grip.solve_constrained(g, w[j])
        assert np.array_equal(s.forces, r["forces"][j]) and np.array_equal(s.certificate, r["certificate"][j])
        assert int(s.status) == r["status"][j] and s.iterations == r["iterations"][j]
        assert np.all(np.einsum("ij,ij->i", s.forces, g.normals) <= bounds[j] * (1 + 1e-9))
        statuses.add(s.status)
    assert {grip.Status.Ok, grip.Status.Infeasible} <= statuses
    # A scalar bound broadcasts; the default is none, as inf; the other methods ignore it.
    one = grip.solve_batch(b["positions"], b["normals"], b["friction"], w, squeeze=b["squeeze"], max_normal_force=3.0,
                           method="constrained")
    same = grip.solve_batch(b["positions"], b["normals"], b["friction"], w, squeeze=b["squeeze"],
                            max_normal_force=np.full((20, 5), 3.0), method="constrained")
    assert np.array_equal(one["forces"], same["forces"])
    free = grip.solve_batch(b["positions"], b["normals"], b["friction"], w, squeeze=b["squeeze"], method="constrained")
    inf = grip.solve_batch(b["positions"], b["normals"], b["friction"], w, squeeze=b["squeeze"], max_normal_force=np.inf,
                           method="constrained")
    assert np.array_equal(free["forces"], inf["forces"])
    rs = grip.solve_batch(b["positions"], b["normals"], b["friction"], w, squeeze=b["squeeze"], max_normal_force=bounds)
    assert np.array_equal(rs["forces"], grip.solve_batch(b["positions"], b["normals"], b["friction"], w,
                                                         squeeze=b["squeeze"])["forces"])


def test_batch_numbers_broadcast():
    rng = np.random.default_rng(10)
    b = batch_contacts(rng, 6, 4)
    full = grip.evaluate_batch(b["positions"], b["normals"], np.full((6, 4), 0.5), squeeze=np.ones((6, 4)))
    for friction in (0.5, np.full(4, 0.5)):
        r = grip.evaluate_batch(b["positions"], b["normals"], friction, squeeze=1.0)
        for key in r:
            assert np.array_equal(r[key], full[key])


def test_batch_invalid_input_names_grasp_and_contact():
    rng = np.random.default_rng(11)
    b = batch_contacts(rng, 5, 4)
    bad = b["normals"].copy()
    bad[3, 1] *= 1.5
    with pytest.raises(ValueError, match=r"normals\[3, 1\] must be a unit vector"):
        grip.evaluate_batch(b["positions"], bad, 0.5)
    f = np.full((5, 4), 0.5)
    f[2, 0] = np.nan
    with pytest.raises(ValueError, match=r"friction\[2, 0\] is not finite"):
        grip.solve_batch(b["positions"], b["normals"], f, np.zeros(6))
    with pytest.raises(ValueError, match=r"positions must have shape \(k, n, 3\)"):
        grip.evaluate_batch(b["positions"][0], b["normals"][0], 0.5)
    with pytest.raises(ValueError, match=r"friction must be a number or have shape"):
        grip.evaluate_batch(b["positions"], b["normals"], np.ones(3))
    bounds = np.ones((5, 4))
    bounds[4, 3] = 0.0
    with pytest.raises(ValueError, match=r"max_normal_force\[4, 3\] must be > 0"):
        grip.solve_batch(b["positions"], b["normals"], 0.5, np.zeros(6), max_normal_force=bounds, method="constrained")
    with pytest.raises(ValueError, match=r"max_normal_force must be a number or have shape"):
        grip.solve_batch(b["positions"], b["normals"], 0.5, np.zeros(6), max_normal_force=np.ones(3))
    with pytest.raises(ValueError, match=r"w_ext must have shape \(6,\) or \(k, 6\)"):
        grip.solve_batch(b["positions"], b["normals"], 0.5, np.zeros(5))
    with pytest.raises(ValueError, match="method must be"):
        grip.solve_batch(b["positions"], b["normals"], 0.5, np.zeros(6), method="newton")
    with pytest.raises(ValueError, match="sides must be 4, 8 or 16"):
        grip.evaluate_batch(b["positions"], b["normals"], 0.5, sides=5)
    with pytest.raises(ValueError, match="norm must be"):
        grip.epsilon(grip.Grasp(b["positions"][0], b["normals"][0], 0.5), "L2")
