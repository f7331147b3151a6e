"""grip.mujoco (the adapter over MuJoCo's Python package) and grip.hand_mjcf on scenes MuJoCo
simulates: the scenes of tests/mujoco/adapter.test.cpp (a box squeezed between two pads of a
tracker-driven rig, held, lifted, resting on a table, touched by a pad outside the map), grip's
own hand written as MJCF against forward_kinematics, and MuJoCo Menagerie's Shadow and Allegro
hands when ../shared/models is there. References are MuJoCo's own: the object's acceleration
from mj_objectAcceleration (after mj_rnePostConstraint: an accelerometer's path, not the
adapter's qacc), its mass, and its contact forces from mj_contactForce. Skipped without the
mujoco package."""

from pathlib import Path

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import grip  # noqa: E402
import grip.mujoco as gm  # noqa: E402

BOX_MASS = 0.2
PADS = {"pad_a": 4, "pad_b": 1}  # index distal, thumb distal
MODELS = Path(__file__).resolve().parents[3] / "shared" / "models"


def scene(rig_z, c_offset, table_top):
    """A box (6 cm, 0.2 kg) between two pads 1 mm inside its faces, on a rig welded to a mocap
    target; a third pad at c_offset along y (0.035 touches the box's +y face, 0.2 keeps clear);
    a table whose top is at table_top; a fixed sphere far away (a body without a free joint)."""
    pad = '<geom type="box" size="0.005 0.02 0.02" friction="1 0.005 0.0001" condim="3"/>'
    return (
        '<mujoco><option timestep="0.001" cone="elliptic" impratio="10"/><worldbody>'
        f'<geom name="table" type="box" pos="0 0 {table_top - 0.05:.6f}" size="0.3 0.3 0.05"/>'
        f'<body name="target" mocap="true" pos="0 0 {rig_z:.6f}"/>'
        f'<body name="rig" pos="0 0 {rig_z:.6f}"><freejoint/>'
        '<inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>'
        f'<body name="pad_a" pos="0.034 0 0">{pad}</body>'
        f'<body name="pad_b" pos="-0.034 0 0">{pad}</body>'
        f'<body name="pad_c" pos="0 {c_offset:.6f} 0" euler="0 0 1.5707963267948966">{pad}</body></body>'
        f'<body name="box" pos="0 0 {rig_z:.6f}"><freejoint/>'
        f'<geom type="box" size="0.03 0.03 0.03" mass="{BOX_MASS:.6f}" condim="3"/></body>'
        '<body name="fixed" pos="0.5 0 0.05"><geom type="sphere" size="0.01"/></body>'
        '</worldbody><equality><weld body1="target" body2="rig" solref="0.01 1"/></equality></mujoco>'
    )


def sim(xml):
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    return m, d


def body_id(m, name):
    return mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, name)


def mujoco_wrench(m, d, body, other=None):
    """MuJoCo's own wrench (6,) on `body` from its contacts with `other` (every other body for
    None), about the body's centre of mass: mj_contactForce turned out of the contact frame,
    written here independently of grip.mujoco."""
    com = d.xipos[body].copy()
    w = np.zeros(6)
    for i in range(d.ncon):
        c = d.contact[i]
        b1, b2 = m.geom_bodyid[c.geom1], m.geom_bodyid[c.geom2]
        if body not in (b1, b2) or (other is not None and other not in (b1, b2)):
            continue
        local = np.zeros(6)
        mujoco.mj_contactForce(m, d, i, local)
        frame = c.frame.reshape(3, 3)
        f, t = frame.T @ local[:3], frame.T @ local[3:]
        if b2 != body:
            f, t = -f, -t
        w[:3] += f
        w[3:] += np.cross(c.pos - com, f) + t
    return w


def accelerometer_force(m, d, body):
    """m (a - g) of `body` by MuJoCo's accelerometer path (mj_objectAcceleration reads a - g)."""
    mujoco.mj_rnePostConstraint(m, d)
    acc = np.zeros(6)
    mujoco.mj_objectAcceleration(m, d, mujoco.mjtObj.mjOBJ_BODY, body, acc, 0)
    return m.body_mass[body] * acc[3:]


def in_cones(update, felt):
    """Every solved force inside its exact cone: f . a >= 0 and |f_t| <= mu f_n (relative 1e-9)."""
    for f, a, mu in zip(felt.forces, update.normals, update.friction):
        fn = f @ a
        ft = np.linalg.norm(f - fn * a)
        if not (fn >= -1e-9 * np.linalg.norm(f) and ft <= mu * fn + 1e-9 * np.linalg.norm(f)):
            return False
    return True


def test_held_and_lifted_box_felt_sum_is_m_g_minus_a_with_mujocos_own_contact_wrench():
    m, d = sim(scene(0.2, 0.2, 0.0))
    a = gm.Adapter(m, "box", PADS)
    box = a.object
    assert box == body_id(m, "box")
    checked = 0
    for step in range(600):
        # Hold still for 0.3 s, then lift at 3 m/s^2.
        t = step * m.opt.timestep
        lift = max(0.0, t - 0.3)
        d.mocap_pos[0, 2] = 0.2 + 0.5 * 3.0 * lift * lift
        mujoco.mj_step(m, d)
        if step % 50 != 49:
            continue
        u = a.update(d)
        assert u.status == grip.Status.Ok
        assert u.grasp is not None and len(u.contacts) >= 2
        assert u.ignored == 0 and u.obstacles == 0
        assert set(u.grip_bodies) <= {1, 4}
        felt = a.solve(grip.solve_constrained)
        assert felt.status == grip.Status.Ok
        assert felt.in_contact[4] and felt.in_contact[1]
        assert felt.in_contact.sum() == 2
        # The hand feels m (g - a): -m (a - g) from MuJoCo's accelerometer.
        expected = -accelerometer_force(m, d, box)
        total = felt.felt.sum(axis=0)
        assert np.linalg.norm(total - expected) <= 1e-6 * (1 + np.linalg.norm(expected)), (step, total, expected)
        # grip's contacts apply the wrench MuJoCo's contacts apply (the same Newton-Euler).
        grip_wrench = np.zeros(6)
        for r, f in zip(u.positions, felt.forces):
            grip_wrench += np.concatenate([f, np.cross(r, f)])
        mj = mujoco_wrench(m, d, box)
        assert np.linalg.norm(grip_wrench - mj) <= 1e-6 * (1 + np.linalg.norm(mj))
        assert np.linalg.norm(grip_wrench + u.w_ext) <= 1e-9 * (1 + np.linalg.norm(mj))
        assert in_cones(u, felt)
        # The felt points are the contacts' force-weighted points, on the pads' side of the box.
        assert felt.points[4, 0] > d.xipos[box, 0] and felt.points[1, 0] < d.xipos[box, 0]
        if t > 0.35:
            assert expected[2] < -BOX_MASS * (9.81 + 1.0)  # lifted: heavier than m g
        if 0.2 < t < 0.3:
            assert abs(expected[2] + BOX_MASS * 9.81) < 0.05 * BOX_MASS * 9.81
        checked += 1
    assert checked == 12


def test_the_table_is_an_external_force_and_a_pad_outside_the_map_is_ignored_and_counted():
    # The box rests on the table (its bottom 1 mm into it) between the pads; pad_c touches +y.
    m, d = sim(scene(0.029, 0.034, 0.0))
    a = gm.Adapter(m, "box", PADS)
    for _ in range(200):
        mujoco.mj_step(m, d)
    u = a.update(d)
    assert u.status == grip.Status.Ok
    assert u.obstacles >= 1
    assert u.ignored >= 1
    box, pad_c = a.object, body_id(m, "pad_c")
    assert np.linalg.norm(u.wrench.obstacles - mujoco_wrench(m, d, box, 0)) <= 1e-9
    # contact_wrench is MuJoCo's own force of one contact.
    for i in range(d.ncon):
        c = d.contact[i]
        if box in (m.geom_bodyid[c.geom1], m.geom_bodyid[c.geom2]):
            other = m.geom_bodyid[c.geom2] if m.geom_bodyid[c.geom1] == box else m.geom_bodyid[c.geom1]
            if sum(1 for j in range(d.ncon) if other in (m.geom_bodyid[d.contact[j].geom1],
                                                         m.geom_bodyid[d.contact[j].geom2])) == 1:
                assert np.allclose(gm.contact_wrench(m, d, i, box, d.xipos[box]), mujoco_wrench(m, d, box, other),
                                   atol=1e-12)
    assert not gm.contact_wrench(m, d, 0, body_id(m, "fixed"), np.zeros(3)).any()
    # The mapped pads' MuJoCo wrench balances w_ext minus the ignored pad's.
    hand = mujoco_wrench(m, d, box, body_id(m, "pad_a")) + mujoco_wrench(m, d, box, body_id(m, "pad_b"))
    rest = u.w_ext + mujoco_wrench(m, d, box, pad_c)
    assert np.linalg.norm(hand + rest) <= 1e-6 * (1 + np.linalg.norm(hand))
    # Without obstacles the table's force is left out of w_ext (and not counted).
    b = gm.Adapter(m, "box", PADS, obstacles=False)
    v = b.update(d)
    assert v.obstacles == 0 and not v.wrench.obstacles.any()
    assert np.allclose(v.w_ext, u.w_ext - u.wrench.obstacles)
    felt = a.solve()
    assert felt.status in (grip.Status.Ok, grip.Status.Infeasible)
    assert felt.obstacles == u.obstacles and felt.ignored == u.ignored


def test_no_contact_gives_singular_and_zero_forces_and_a_free_fall_has_no_external_wrench():
    m, d = sim(scene(0.2, 0.2, 0.0))
    a = gm.Adapter(m, "box", PADS)
    assert a.solve().status == grip.Status.Singular  # before any update
    for _ in range(20):
        mujoco.mj_step(m, d)
    a.update(d)
    assert a.solve(grip.solve_constrained).status == grip.Status.Ok
    a.update(d)
    assert a.solve(grip.solve_range_space).status == grip.Status.Ok
    # The rig (and its target) 1 m higher: the box falls free.
    rig = body_id(m, "rig")
    d.qpos[m.jnt_qposadr[m.body_jntadr[rig]] + 2] += 1.0
    d.mocap_pos[0, 2] += 1.0
    mujoco.mj_forward(m, d)
    u = a.update(d)
    assert u.status == grip.Status.Ok
    assert u.grasp is None and len(u.contacts) == 0
    felt = a.solve(grip.solve_constrained)
    assert felt.status == grip.Status.Singular
    assert felt.forces.shape == (0, 3)
    assert not felt.felt.any() and not felt.in_contact.any() and not felt.points.any()
    # Falling free: w_ext is about zero (gravity and inertia cancel).
    assert np.linalg.norm(u.w_ext) <= 1e-6
    # Statics only: w_ext is the weight.
    s = gm.Adapter(m, "box", PADS, inertial=False).update(d)
    assert np.allclose(s.w_ext, [0, 0, -9.81 * BOX_MASS, 0, 0, 0])


def test_set_up_errors_name_the_problem():
    m, d = sim(scene(0.2, 0.2, 0.0))
    with pytest.raises(ValueError, match="pad_x"):
        gm.Adapter(m, "box", {"pad_a": 4, "pad_x": 1})
    with pytest.raises(ValueError, match="out of range"):
        gm.Adapter(m, "box", {"pad_a": 19})
    with pytest.raises(ValueError, match="out of range"):
        gm.Adapter(m, "box", {"pad_a": -1})
    with pytest.raises(ValueError, match="int grip body"):
        gm.Adapter(m, "box", {"pad_a": 4.0})
    with pytest.raises(TypeError, match="complex"):
        gm.Adapter(m, "box", {"pad_a": 4j})
    with pytest.raises(ValueError, match="world body"):
        gm.Adapter(m, "box", {"world": 4})
    with pytest.raises(ValueError, match="non-empty"):
        gm.Adapter(m, "box", {})
    with pytest.raises(ValueError, match="'boxx' is not a body"):
        gm.Adapter(m, "boxx", PADS)
    with pytest.raises(ValueError, match="'fixed' has no free joint"):
        gm.Adapter(m, "fixed", PADS)
    with pytest.raises(ValueError, match="'pad_a' is one of the hand's bodies"):
        gm.Adapter(m, "pad_a", PADS)
    with pytest.raises(ValueError, match="stiffness"):
        gm.Adapter(m, "box", PADS, stiffness=-1.0)
    with pytest.raises(ValueError, match=r"weight\[3\]"):
        gm.Adapter(m, "box", PADS, weight=np.r_[np.ones(3), 0.0, np.ones(15)])
    with pytest.raises(TypeError, match="contribution: complex"):
        gm.Adapter(m, "box", PADS, contribution=0.1j)
    with pytest.raises(ValueError, match="shape"):
        gm.Adapter(m, "box", PADS, contribution=np.ones(14))
    m.opt.gravity[2] = np.nan
    with pytest.raises(ValueError, match="gravity"):
        gm.Adapter(m, "box", PADS)
    m.opt.gravity[2] = -9.81
    m.opt.timestep = 0.0
    with pytest.raises(ValueError, match="timestep"):
        gm.Adapter(m, "box", PADS)
    m.opt.timestep = 0.001
    a = gm.Adapter(m, "box", PADS)
    # A state that is not finite: ValueError.
    box = body_id(m, "box")
    d.qacc[m.jnt_dofadr[m.body_jntadr[box]] + 2] = np.inf
    with pytest.raises(ValueError, match="not finite"):
        a.update(d)


def test_contributions_stiffness_and_the_contact_numbers_follow_the_documented_rules():
    m, d = sim(scene(0.2, 0.2, 0.0))
    for _ in range(50):
        mujoco.mj_step(m, d)
    table = grip.contribution_table(grip.GraspType.CylindricalPower)
    a = gm.Adapter(m, "box", PADS)
    assert np.array_equal(a.contribution[:14], table.by_phalanx)
    assert np.all(a.contribution[14:] == table.palm / 5)
    u = a.update(d)
    for n, i, r, normal, mu, mut, s, k in zip(range(len(u.contacts)), u.contacts, u.positions, u.normals,
                                              u.friction, u.torsional_friction, u.squeeze, u.grip_bodies):
        c = d.contact[i]
        assert np.allclose(r + d.xipos[a.object], c.pos, atol=1e-15)
        into = 1.0 if m.geom_bodyid[c.geom2] == a.object else -1.0
        assert np.array_equal(normal, into * c.frame[:3])
        assert mu == min(c.friction[0], c.friction[1]) and mut == 0.0  # condim 3
        assert s == pytest.approx(table.by_phalanx[k] * 1e4 * max(0.0, -c.dist), rel=1e-15)
        assert u.bodies[n] == m.geom_bodyid[c.geom2 if into < 0 else c.geom1]
    # A flat contribution, a grasp type, a per-body stiffness; SoftFinger and FrictionlessPoint.
    flat = gm.Adapter(m, "box", PADS, contribution=0.5, stiffness=2e3).update(d)
    assert np.allclose(flat.squeeze, 0.5 * 2e3 * np.maximum(0, -d.contact.dist[flat.contacts]))
    pinch = gm.Adapter(m, "box", PADS, contribution=grip.GraspType.TipPinch)
    assert np.array_equal(pinch.contribution[:14], grip.contribution_table(grip.GraspType.TipPinch).by_phalanx)
    for model in (grip.Model.SoftFinger, grip.Model.FrictionlessPoint):
        b = gm.Adapter(m, "box", PADS, contact_model=model)
        v = b.update(d)
        assert v.grasp.model == model
        felt = b.solve(grip.solve_range_space)
        assert felt.forces.shape == (len(v.contacts), 3)
        assert np.allclose(felt.felt.sum(axis=0), -felt.forces.sum(axis=0))


def test_more_hand_contacts_than_the_grasp_holds_gives_out_of_range_and_counts_them(monkeypatch):
    m, d = sim(scene(0.2, 0.2, 0.0))
    a = gm.Adapter(m, "box", PADS)
    mujoco.mj_step(m, d)
    hand = sum(1 for i in range(d.ncon)
               if {m.geom_bodyid[d.contact[i].geom1], m.geom_bodyid[d.contact[i].geom2]} & {body_id(m, "pad_a"),
                                                                                           body_id(m, "pad_b")})
    assert hand > 3
    monkeypatch.setattr(gm, "max_contacts", 3)
    u = a.update(d)
    assert u.status == grip.Status.OutOfRange
    assert len(u.contacts) == 3 and u.dropped == hand - 3


# ---------------------------------------------------------------------------------------------
# grip's hand as MJCF


def test_hand_mjcf_loads_with_grips_names_order_and_limits():
    names, joints = grip.hand_body_names(), grip.hand_joint_names()
    assert len(names) == 19 and len(set(names)) == 19 and names[0] == "thumb_proximal"
    assert len(joints) == 20 and len(set(joints)) == 20 and joints[4] == "index_abduction"
    assert gm.GRIP_HAND == {n: k for k, n in enumerate(names)}
    dims = grip.HandDimensions.standard()
    for mocap in (True, False):
        m = mujoco.MjModel.from_xml_string(grip.hand_mjcf(mocap=mocap))
        assert m.nq == 20 + (7 if mocap else 0) and m.nu == 20
        assert m.opt.timestep == 0.001
        for k, n in enumerate(names):
            assert body_id(m, n) > 0
        for i, n in enumerate(joints):
            j = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, n)
            assert m.jnt_qposadr[j] == i + (7 if mocap else 0)
            assert tuple(m.jnt_range[j]) == (dims.joint_lower[i], dims.joint_upper[i])
            assert tuple(m.actuator_ctrlrange[i]) == (dims.joint_lower[i], dims.joint_upper[i])
            assert m.actuator_gainprm[i, 0] == 2.0
    m = mujoco.MjModel.from_xml_string(grip.hand_mjcf(prefix="r_", servo_gain=0.0, condim=4, friction=0.5,
                                                      timestep=0.002, model="two"))
    assert m.nu == 0 and m.opt.timestep == 0.002
    assert body_id(m, "r_index_distal") > 0 and body_id(m, "r_hand_target") > 0
    assert np.all(m.geom_condim == 4) and np.all(m.geom_friction[:, 0] == 0.5)
    # worldbody and extra land in the document.
    xml = grip.hand_mjcf(worldbody='<body name="ball" pos="0.1 0 0"><freejoint/><geom size="0.02"/></body>',
                         extra='<contact><exclude body1="hand" body2="ball"/></contact>')
    m = mujoco.MjModel.from_xml_string(xml)
    assert body_id(m, "ball") > 0 and m.nexclude == 1


def test_hand_mjcf_errors_name_the_option():
    with pytest.raises(ValueError, match="condim"):
        grip.hand_mjcf(condim=2)
    with pytest.raises(ValueError, match="prefix"):
        grip.hand_mjcf(prefix="a b")
    with pytest.raises(ValueError, match="timestep"):
        grip.hand_mjcf(timestep=0.0)
    with pytest.raises(ValueError, match="friction"):
        grip.hand_mjcf(friction=-1.0)
    with pytest.raises(ValueError, match="servo_gain"):
        grip.hand_mjcf(servo_gain=np.nan)
    with pytest.raises(ValueError, match="wrist"):
        grip.hand_mjcf(wrist=np.eye(3))
    mirror = np.diag([1.0, 1.0, -1.0, 1.0])
    with pytest.raises(ValueError, match="wrist"):
        grip.hand_mjcf(wrist=mirror)
    with pytest.raises(ValueError, match="wrist"):
        grip.hand_mjcf(wrist=np.diag([1.0 + 1e-6, 1.0, 1.0, 1.0]))
    with pytest.raises(TypeError, match="servo_gain: complex"):
        grip.hand_mjcf(servo_gain=1j)
    with pytest.raises(TypeError, match="wrist: complex"):
        grip.hand_mjcf(wrist=np.eye(4, dtype=complex))
    with pytest.raises(TypeError):
        grip.hand_mjcf(None, "r_")  # everything but dims is keyword-only


def random_wrist(rng):
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, q)
    wrist = np.eye(4)
    wrist[:3, :3] = rot.reshape(3, 3)
    wrist[:3, 3] = rng.uniform(-0.5, 0.5, 3)
    return wrist, q


@pytest.mark.parametrize("mocap", [True, False])
def test_mujoco_moves_grips_hand_exactly_as_forward_kinematics(mocap):
    rng = np.random.default_rng(7)
    for left in (False, True):
        dims = grip.HandDimensions.standard(0.19, left)
        lower, upper = np.array(dims.joint_lower), np.array(dims.joint_upper)
        wrist, quat = random_wrist(rng)
        m = mujoco.MjModel.from_xml_string(grip.hand_mjcf(dims, wrist=wrist, mocap=mocap))
        d = mujoco.MjData(m)
        ids = [body_id(m, n) for n in grip.hand_body_names()]
        for _ in range(20 if not left else 5):
            q = rng.uniform(lower, upper)
            if mocap:
                # The hand's free joint first (its pose: the wrist), then the 20 joints in grip's order.
                d.qpos[:3], d.qpos[3:7] = wrist[:3, 3], quat
                d.mocap_pos[0], d.mocap_quat[0] = wrist[:3, 3], quat
                d.qpos[7:] = q
            else:
                d.qpos[:] = q
            mujoco.mj_kinematics(m, d)
            fk = grip.forward_kinematics(wrist, q, dims)
            assert np.abs(d.xpos[ids] - fk["base"]).max() <= 1e-12
            # The capsules join the bodies' bases to their tips (MuJoCo may turn a capsule's axis).
            for k, b in enumerate(ids):
                g = m.body_geomadr[b]
                half = d.geom_xmat[g].reshape(3, 3)[:, 2] * m.geom_size[g, 1]
                e1, e2 = d.geom_xpos[g] - half, d.geom_xpos[g] + half
                worst = min(max(np.abs(e1 - fk["base"][k]).max(), np.abs(e2 - fk["tip"][k]).max()),
                            max(np.abs(e2 - fk["base"][k]).max(), np.abs(e1 - fk["tip"][k]).max()))
                assert worst <= 1e-12, (k, worst)
                assert m.geom_size[g, 0] == fk["radius"][k]


def test_an_adapter_on_grips_own_hand_closing_on_a_ball():
    ball = ('<body name="ball" pos="0.075 -0.01 -0.045"><freejoint/>'
            '<geom type="sphere" size="0.035" mass="0.1" condim="3" friction="1 0.005 0.0001"/></body>')
    m = mujoco.MjModel.from_xml_string(grip.hand_mjcf(worldbody=ball, mocap=False, servo_gain=5.0))
    d = mujoco.MjData(m)
    m.opt.gravity[:] = 0.0
    a = gm.Adapter(m, "ball", gm.GRIP_HAND)
    upper = m.actuator_ctrlrange[:, 1]
    seen = set()
    for step in range(400):
        d.ctrl[:] = np.minimum(upper, 0.5) * min(1.0, step / 200)
        mujoco.mj_step(m, d)
        if step % 20 == 19:
            u = a.update(d)
            felt = a.solve()
            assert felt.status in (grip.Status.Ok, grip.Status.Singular, grip.Status.Infeasible)
            assert np.isfinite(felt.felt).all()
            assert u.ignored == 0  # every hand body is mapped
            seen |= set(u.grip_bodies.tolist())
    assert seen  # the hand touched the ball


# ---------------------------------------------------------------------------------------------
# MuJoCo Menagerie's hands (not the project's: found next to the repository, else skipped)


def close_fingers(m, d, adapter, names, steps=400):
    """Steps the scene with the named actuators driven linearly from 0 towards their ctrlrange's
    upper ends over the first half; update and solve every 10 steps. Returns the statuses and
    the number of grasp contacts seen."""
    ids = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, n) for n in names]
    assert min(ids) >= 0
    statuses, contacts = [], 0
    for step in range(steps):
        ramp = min(1.0, step / (steps / 2))
        for i in ids:
            d.ctrl[i] = ramp * m.actuator_ctrlrange[i, 1]
        mujoco.mj_step(m, d)
        if step % 10 == 9:
            u = adapter.update(d)
            felt = adapter.solve()
            assert np.isfinite(u.w_ext).all()
            assert np.isfinite(felt.felt).all() and np.isfinite(felt.points).all() and np.isfinite(felt.forces).all()
            statuses.append(felt.status)
            contacts += len(u.contacts)
    return statuses, contacts


@pytest.mark.parametrize("hand,scene_file,bodies,actuators", [
    ("shadow_hand", "scene_right.xml", "SHADOW_RIGHT",
     ["rh_A_FFJ3", "rh_A_FFJ0", "rh_A_MFJ3", "rh_A_MFJ0", "rh_A_RFJ3", "rh_A_RFJ0", "rh_A_LFJ3", "rh_A_LFJ0",
      "rh_A_THJ5", "rh_A_THJ4", "rh_A_THJ1"]),
    ("shadow_hand", "scene_left.xml", "SHADOW_LEFT",
     ["lh_A_FFJ3", "lh_A_FFJ0", "lh_A_MFJ3", "lh_A_MFJ0"]),
    ("wonik_allegro", "scene_right.xml", "ALLEGRO_RIGHT",
     ["ffa1", "ffa2", "ffa3", "mfa1", "mfa2", "mfa3", "rfa1", "rfa2", "rfa3", "tha0", "tha2", "tha3"]),
    ("wonik_allegro", "scene_left.xml", "ALLEGRO_LEFT", ["ffa1", "ffa2", "mfa1", "mfa2"]),
])
def test_menagerie_hands_close_on_their_object(hand, scene_file, bodies, actuators):
    path = MODELS / hand / scene_file
    if not path.is_file():
        pytest.skip(f"{path} is absent (MuJoCo Menagerie's models, next to the repository)")
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    body_map = getattr(gm, bodies)
    a = gm.Adapter(m, "object", body_map)  # every name of the map is a body of the file
    assert a.root > 0
    statuses, contacts = close_fingers(m, d, a, actuators)
    assert set(statuses) <= {grip.Status.Ok, grip.Status.Singular, grip.Status.Infeasible}
    assert contacts > 0  # the object lies on the hand


def test_the_example_closes_a_menagerie_hand_and_writes_its_svg(tmp_path):
    pytest.importorskip("matplotlib")
    import os
    import subprocess
    import sys

    model = MODELS / "wonik_allegro" / "scene_right.xml"
    if not model.is_file():
        pytest.skip(f"{model} is absent (MuJoCo Menagerie's models, next to the repository)")
    script = Path(__file__).resolve().parents[2] / "examples" / "python" / "mujoco_hand.py"
    out = tmp_path / "felt.svg"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    text = subprocess.run([sys.executable, str(script), "--model", str(model), "--duration", "2", str(out)],
                          cwd=tmp_path, env=env, check=True, capture_output=True, text=True, timeout=300).stdout
    assert f"wrote {out}" in text and "statuses over the run" in text
    assert out.read_text().lstrip().startswith("<?xml") and out.stat().st_size > 10_000


def test_the_example_cups_grips_own_hand_around_a_ball(tmp_path):
    pytest.importorskip("matplotlib")
    import os
    import subprocess
    import sys

    script = Path(__file__).resolve().parents[2] / "examples" / "python" / "mujoco_hand.py"
    out = tmp_path / "felt.svg"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    text = subprocess.run([sys.executable, str(script), "--model", "grip", "--duration", "2", str(out)],
                          cwd=tmp_path, env=env, check=True, capture_output=True, text=True, timeout=300).stdout
    assert f"wrote {out}" in text
    # The ball is still in the hand at the end: the last row of the table solved with contacts.
    last = [line.split() for line in text.splitlines() if line.strip().startswith("2.00")][-1]
    assert last[1] == "Ok" and int(last[2]) > 0, text
