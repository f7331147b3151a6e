"""The hand's kinematics, the shapes' distances and the hand's contacts, against their
definitions evaluated in NumPy."""

import numpy as np
import pytest

import grip

FIRST = [0, 2, 5, 8, 11]  # first phalanx of each digit (thumb: 2 phalanges, fingers: 3)
COUNT = [2, 3, 3, 3, 3]


def rodrigues(axis, angle):
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def random_pose(rng):
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.linalg.det(q))
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = q, rng.normal(scale=0.2, size=3)
    return t


def test_forward_kinematics_chains_the_rotations_of_each_digit():
    rng = np.random.default_rng(14)
    d = grip.HandDimensions.standard(0.18)
    for _ in range(5):
        wrist = random_pose(rng)
        q = rng.uniform(0, 1.2, 14)
        fk = grip.forward_kinematics(wrist, q, d)
        for f in range(5):
            p = d.base[f].copy()
            total = 0.0
            for j in range(COUNT[f]):
                k = FIRST[f] + j
                total += q[k]
                tip = p + d.length[k] * rodrigues(d.flexion_axis[f], total) @ d.rest_direction[f]
                for got, want in ((fk["base"][k], p), (fk["tip"][k], tip)):
                    assert np.allclose(got, wrist[:3, :3] @ want + wrist[:3, 3], rtol=0, atol=1e-14)
                assert fk["radius"][k] == d.radius[k]
                p = tip


def test_shape_distances_are_the_primitives_exact_distances():
    rng = np.random.default_rng(15)
    pts = rng.uniform(-0.1, 0.1, size=(500, 3))
    c = np.array([0.01, -0.02, 0.005])
    d, n = grip.Shape([grip.sphere(0.04, c)]).distance(pts)
    r = np.linalg.norm(pts - c, axis=1)
    assert np.allclose(d, r - 0.04, atol=1e-15) and np.allclose(n, (pts - c) / r[:, None], atol=1e-12)
    h = np.array([0.03, 0.02, 0.05])
    d, _ = grip.Shape([grip.box(h)]).distance(pts)
    q = np.abs(pts) - h
    box = np.linalg.norm(np.maximum(q, 0), axis=1) + np.minimum(q.max(axis=1), 0)
    assert np.allclose(d, box, atol=1e-15)
    d, _ = grip.Shape([grip.cylinder(0.035, 0.06)]).distance(pts)
    q = np.stack([np.linalg.norm(pts[:, :2], axis=1) - 0.035, np.abs(pts[:, 2]) - 0.06], axis=1)
    cyl = np.linalg.norm(np.maximum(q, 0), axis=1) + np.minimum(q.max(axis=1), 0)
    assert np.allclose(d, cyl, atol=1e-15)
    d, _ = grip.Shape([grip.capsule(0.02, 0.03)]).distance(pts)
    seg = np.stack([np.zeros(500), np.zeros(500), np.clip(pts[:, 2], -0.03, 0.03)], axis=1)
    assert np.allclose(d, np.linalg.norm(pts - seg, axis=1) - 0.02, atol=1e-15)
    # A union is the least of its parts.
    u, _ = grip.Shape([grip.sphere(0.04, c), grip.box(h)]).distance(pts)
    assert np.allclose(u, np.minimum(r - 0.04, box), atol=1e-15)


@pytest.mark.parametrize("depth", [0.0005, 0.002, 0.004])
def test_a_sphere_pressed_on_a_phalanx_gives_its_depth_point_and_normal(depth):
    rng = np.random.default_rng(16)
    wrist = random_pose(rng)
    q = np.zeros(14)
    fk = grip.forward_kinematics(wrist, q)
    k = 4  # index distal
    mid = 0.5 * (fk["base"][k] + fk["tip"][k])
    down = -wrist[:3, 2]  # the hand frame's -z: palmar side
    R = 0.05
    centre = mid + (fk["radius"][k] + R - depth) * down
    pose = np.eye(4)
    pose[:3, 3] = centre  # the sphere's frame: centred at its centre
    got = grip.hand_contacts(grip.Shape([grip.sphere(R)]), wrist, q, pose)
    assert got["status"] == grip.Status.Ok
    mine = np.flatnonzero(got["phalanx"] == k)
    assert len(mine) == 1
    i = mine[0]
    # The deepest point of the capsule: its axis point nearest the centre, at depth r + R - |c - x|.
    assert got["depth"][i] == pytest.approx(depth, abs=1e-7)
    assert np.allclose(got["normal"][i], down, atol=1e-6)  # into the object: from the finger towards the centre
    assert np.allclose(got["point"][i], centre - R * down, atol=1e-6)
    assert abs(got["axis_parameter"][i] - 0.5) < 1e-3


def test_hand_and_shape_inputs_are_checked():
    with pytest.raises(ValueError, match=r"angles must have shape \(14,\)"):
        grip.forward_kinematics(np.eye(4), np.zeros(13))
    bad = np.eye(4)
    bad[0, 0] = 2
    with pytest.raises(ValueError, match="wrist must be rigid"):
        grip.forward_kinematics(bad, np.zeros(14))
    with pytest.raises(ValueError, match="invalid sphere"):
        grip.sphere(-1.0)
    with pytest.raises(ValueError, match="a shape has 1 to 4 primitives"):
        grip.Shape([])
    with pytest.raises(ValueError, match="per_phalanx must be 1, 2 or 4"):
        grip.hand_contacts(grip.Shape([grip.sphere(0.05)]), np.eye(4), np.zeros(14), per_phalanx=3)


def test_grasp_type_tables_follow_the_shares_convention():
    # Table 1, typed from the paper (index..little; proximal, middle, distal).
    table1 = np.array([[0.115, 0.021, 0.159], [0.126, 0.023, 0.176], [0.088, 0.016, 0.122], [0.060, 0.011, 0.083]])
    cyl = grip.contribution_table(grip.GraspType.CylindricalPower)
    assert np.allclose(cyl.share[1:], table1, rtol=0, atol=1e-12)
    assert np.allclose(cyl.share[0], [0.15, 0.0, 0.25]) and cyl.palm == pytest.approx(0.40)
    assert np.array_equal(grip.contribution_table().share, cyl.share)  # the default grasp type
    seen = set()
    for g in (grip.GraspType.CylindricalPower, grip.GraspType.SphericalPower, grip.GraspType.TipPinch,
              grip.GraspType.Tripod, grip.GraspType.LateralPinch):
        t = grip.contribution_table(g)
        assert t.share.shape == (5, 3) and (t.share >= 0).all() and t.palm >= 0 and t.share[0, 1] == 0
        assert abs(t.share[1:].sum() - 1.0) <= 0.002  # the four fingers sum to 1 (docs/hand.md)
        assert t.four_finger_total() == pytest.approx(t.share[1:].sum())
        assert t.total() == pytest.approx(t.share.sum() + t.palm)
        assert t.finger_total(2) == pytest.approx(t.share[2].sum())
        # by_phalanx: the 14 phalanges in hand order (thumb proximal, distal, then 3 per finger).
        assert np.allclose(t.by_phalanx, np.r_[t.share[0, [0, 2]], t.share[1:].ravel()])
        seen.add((tuple(t.share.ravel()), t.palm))
    assert len(seen) == 5
    tip = grip.contribution_table(grip.GraspType.TipPinch)
    assert tip.share[0, 2] == tip.share[1, 2] == 1.0


def test_contribution_table_from_arrays_is_checked():
    share = np.zeros((5, 3))
    share[0, 2] = share[1, 2] = 1.0
    t = grip.ContributionTable(share, palm=0.25)
    assert np.array_equal(t.share, share) and t.palm == 0.25
    t.share[0, 0] = 5.0  # a copy: the table does not change
    assert t.share[0, 0] == 0.0
    bad = share.copy()
    bad[0, 1] = 0.1
    for args in ((np.zeros((4, 3)),), (bad,), (-share,), (share, -1.0), (share * np.nan,)):
        with pytest.raises(ValueError):
            grip.ContributionTable(*args)
    with pytest.raises(ValueError):
        t.finger_total(5)


def test_haptic_loop_takes_a_contribution_table():
    loop = grip.HapticLoop(position=(0.0, 0.0, 0.0), contribution=grip.contribution_table(grip.GraspType.TipPinch))
    assert loop is not None
    with pytest.raises(TypeError):
        grip.HapticLoop(position=(0.0, 0.0, 0.0), thumb_contribution=(0.15, 0.25))


def test_the_whole_hand_opens_flat_and_has_a_palm():
    fk = grip.forward_kinematics(np.eye(4), np.zeros(20))
    assert fk["base"].shape == (19, 3) and fk["radius"].shape == (19,)
    # The open hand: every body's axis on or above the palm plane (hand frame z = 0).
    assert min(fk["base"][:, 2].min(), fk["tip"][:, 2].min()) >= -1e-12
    # The paper's hand: 14 phalanges, its thumb hanging below the palm; fixed joints, zero axes.
    paper = grip.forward_kinematics(np.eye(4), np.zeros(14))
    assert paper["base"].shape == (14, 3) and paper["tip"][1, 2] < -0.05
    assert np.all(paper["joint_axis"][[0, 1, 4, 8, 12, 16]] == 0)


def test_the_left_hand_mirrors_the_right():
    rng = np.random.default_rng(21)
    right, left = grip.HandDimensions.standard(), grip.HandDimensions.standard(left=True)
    assert left.left and not right.left
    q = rng.uniform(np.array(right.joint_lower) * 0.9, np.array(right.joint_upper) * 0.9)
    a, b = grip.forward_kinematics(np.eye(4), q, right), grip.forward_kinematics(np.eye(4), q, left)
    m = np.array([1.0, -1.0, 1.0])
    np.testing.assert_allclose(b["tip"], a["tip"] * m, atol=1e-15)


def test_point_jacobians_are_the_derivatives_of_forward_kinematics():
    rng = np.random.default_rng(22)
    d = grip.HandDimensions.standard()
    for _ in range(3):
        wrist = random_pose(rng)
        q = rng.uniform(np.array(d.joint_lower) * 0.9, np.array(d.joint_upper) * 0.9)
        fk = grip.forward_kinematics(wrist, q, d)
        for body in range(19):
            J = grip.point_jacobian(wrist, q, body, fk["tip"][body], d)
            assert J.shape == (3, 20)
            h = 1e-6
            for i in range(20):
                dq = np.zeros(20)
                dq[i] = h
                num = (grip.forward_kinematics(wrist, q + dq, d)["tip"][body]
                       - grip.forward_kinematics(wrist, q - dq, d)["tip"][body]) / (2 * h)
                np.testing.assert_allclose(J[:, i], num, atol=1e-8)
    with pytest.raises(ValueError):
        grip.point_jacobian(np.eye(4), np.zeros(14), 15, [0, 0, 0])  # the paper's hand has no palm


def test_the_whole_hand_touches_an_object_with_its_palm():
    cylinder = grip.Shape([grip.cylinder(0.035, 0.07)])
    L = 0.19
    pose = np.eye(4)
    pose[:3, :3] = rodrigues(np.array([1.0, 0, 0]), np.pi / 2)  # axis across the palm
    pose[:3, 3] = [0.27 * L, -0.02, -(0.035 + 0.055 * L - 0.001)]  # 1 mm into the palm
    whole = grip.hand_contacts(cylinder, np.eye(4), np.zeros(20), pose)
    assert set(whole["phalanx"]) >= {15, 16, 17}  # the index, long and ring metacarpals
    # Each of them 1 mm deep: the cylinder's top against the palm's flat underside.
    np.testing.assert_allclose(whole["depth"][np.isin(whole["phalanx"], [15, 16])], 0.001, atol=1e-9)
    paper = grip.hand_contacts(cylinder, np.eye(4), np.zeros(14), pose)
    assert not np.any(paper["phalanx"] >= 14)
