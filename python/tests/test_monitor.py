"""The friction-cone monitor against the cones' definitions evaluated in NumPy."""

import numpy as np
import pytest

import grip
from test_grip import make, random_contacts


def test_hard_finger_modes_and_margins_follow_the_coulomb_cone():
    rng = np.random.default_rng(12)
    c = random_contacts(rng, 40)
    g = make(c, grip.Model.HardFinger)
    a, mu = c["normals"], c["friction"]
    # Forces around each cone's boundary, some pulling: f = f_n a + t with |t| = r mu f_n.
    fn = rng.uniform(-1, 3, 40)
    t = rng.normal(size=(40, 3))
    t -= np.einsum("ij,ij->i", t, a)[:, None] * a
    t /= np.linalg.norm(t, axis=1)[:, None]
    ratio = rng.uniform(0.5, 1.5, 40)
    ratio[:4] = [1.0, 1.0 + 1e-12, 1.0 + 1e-6, 0.0]  # on the boundary, within and beyond the slack
    f = fn[:, None] * a + (ratio * mu * np.abs(fn))[:, None] * t
    rep = grip.monitor(g, f)
    assert rep.status == grip.Status.Ok
    f_n = np.einsum("ij,ij->i", f, a)
    f_t = f - f_n[:, None] * a
    margin = mu * f_n - np.linalg.norm(f_t, axis=1)
    assert np.allclose(rep.normal_force, f_n, rtol=0, atol=1e-14 * 3)
    assert np.allclose(rep.tangential_force, f_t, rtol=0, atol=1e-14 * 3)
    pushing = f_n > 0
    assert np.allclose(rep.margin[pushing], margin[pushing], rtol=0, atol=1e-13)
    rel = 1 - np.linalg.norm(f_t, axis=1) / (mu * f_n)
    assert np.allclose(rep.relative_margin[pushing], rel[pushing], rtol=1e-12, atol=1e-12)
    slack = 1e-9 * f_n
    expected = np.where(f_n <= 0, int(grip.ContactMode.Separating),
                        np.where(margin < -slack, int(grip.ContactMode.Sliding), int(grip.ContactMode.Sticking)))
    assert np.array_equal(rep.mode, expected)
    assert rep.sticking == np.sum(expected == 0) and rep.sliding == np.sum(expected == 1)
    assert rep.separating == np.sum(expected == 2) and not rep.stable
    # A stricter monitor (negative slack) calls the boundary forces sliding.
    strict = grip.monitor(g, f, relative_tolerance=-1e-9)
    assert strict.mode[0] == int(grip.ContactMode.Sliding) or f_n[0] <= 0


def test_the_constrained_optimum_sticks_and_the_free_one_may_slip():
    p = np.array([[0.04, 0, 0], [-0.02, 0.0346, 0], [-0.02, -0.0346, 0]])
    a = -p / np.linalg.norm(p, axis=1)[:, None]
    g = grip.Grasp(p, a, 0.3, squeeze=1.0)
    w = np.array([0, 0, -9.81, 0, 0, 0])
    free = grip.solve_range_space(g, w)
    held = grip.solve_constrained(g, w)
    assert not grip.monitor(g, free.forces).stable  # 3.27 N of friction each against 0.3 x 1 N
    rep = grip.monitor(g, held.forces)
    assert rep.stable and rep.sticking == 3 and rep.min_margin >= -1e-9 * np.max(rep.normal_force)


def test_soft_finger_margin_is_the_elliptic_cone():
    rng = np.random.default_rng(13)
    c = random_contacts(rng, 10)
    g = make(c, grip.Model.SoftFinger)
    a, mu, mut = c["normals"], c["friction"], c["torsional_friction"]
    f = np.hstack([2.0 * a + 0.3 * rng.normal(size=(10, 3)), 0.01 * rng.normal(size=(10, 1))])
    rep = grip.monitor(g, f)
    fn = np.einsum("ij,ij->i", f[:, :3], a)
    ft = np.linalg.norm(f[:, :3] - fn[:, None] * a, axis=1)
    margin = mu * (fn - np.sqrt(ft ** 2 / mu ** 2 + f[:, 3] ** 2 / mut ** 2))
    assert np.allclose(rep.margin, margin, rtol=1e-12, atol=1e-13)
    assert np.allclose(rep.moment, f[:, 3], rtol=0, atol=0)


def test_at_bound_marks_the_contacts_whose_normal_force_reaches_its_bound():
    rng = np.random.default_rng(14)
    c = random_contacts(rng, 12)
    bounds = rng.uniform(1.0, 3.0, 12)
    bounds[:3] = np.inf  # no bound: never at it
    g = grip.Grasp(c["positions"], c["normals"], c["friction"], squeeze=c["squeeze"], max_normal_force=bounds)
    a = c["normals"]
    fn = np.minimum(bounds, 5.0) * rng.choice([0.5, 1.0 - 1e-12, 1.0, 1.0 + 1e-6, 1.0 - 1e-6], 12)
    for relative, absolute in ((1e-9, 0.0), (1e-9, 1e-5), (0.0, 0.0)):
        rep = grip.monitor(g, fn[:, None] * a, relative_tolerance=relative, absolute_tolerance=absolute)
        finite = np.isfinite(bounds)
        expected = np.zeros(12, dtype=bool)
        expected[finite] = fn[finite] >= bounds[finite] - absolute - relative * bounds[finite]
        assert rep.at_bound.dtype == bool and np.array_equal(rep.at_bound, expected), (relative, absolute)
        assert rep.at_bound_count == expected.sum()
    # Without bounds, nothing is at one.
    free = grip.monitor(make(c, grip.Model.HardFinger), fn[:, None] * a)
    assert not free.at_bound.any() and free.at_bound_count == 0


def test_monitor_checks_its_input():
    g = grip.Grasp(np.eye(3) * 0.04, -np.eye(3), 0.5)
    with pytest.raises(ValueError, match=r"forces must have shape \(3, 3\)"):
        grip.monitor(g, np.zeros((3, 4)))
    with pytest.raises(ValueError, match=r"forces\[1\] is not finite"):
        grip.monitor(g, [[1, 0, 0], [0, np.nan, 0], [0, 0, 1]])
