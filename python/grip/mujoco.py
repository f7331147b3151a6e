"""grip inside MuJoCo's Python package: a hand's contacts with an object as a grip grasp.

The pure-Python twin of the C++ adapter (include/grip/mujoco/adapter.hpp and
object_wrench.hpp), for the PyPI ``mujoco`` package, whose ABI differs from the MuJoCo C
library the C++ component is built on. After ``mujoco.mj_forward`` or ``mujoco.mj_step``,
``Adapter.update(data)`` turns the contacts between the mapped hand bodies and one object
body into a ``grip.Grasp`` and the object's state into its external wrench w_ext;
``Adapter.solve()`` solves the grasp and sums what each of grip's 19 hand bodies feels.

Classes of the object's contacts (skipped: ``exclude != 0`` or no constraint row,
``efc_address < 0``):

- with a body of the map: a contact of the grasp, in MuJoCo's order;
- with another body of the hand (same root body as the map's bodies, not in the map):
  ignored, and counted;
- with anything else (a table, an obstacle, the world): an external force, MuJoCo's own
  contact force (``mujoco.mj_contactForce``), added to w_ext when ``obstacles`` is set.

A grasp contact: position = MuJoCo's contact point minus the object's centre of mass
(``xipos``), world axes (m); normal = the contact frame's first row, turned to point INTO
the object; friction = min(friction[0], friction[1]) for condim >= 3, else 0; torsional
friction = friction[2] (m) for condim >= 4, else 0; squeeze = d K max(0, -dist) (N), d the
contact's grip body's contribution (default: grip's cylindrical power grip table,
``grip.contribution_table(grip.GraspType.CylindricalPower)``), K its stiffness (N/m).

Units: metres, newtons, newton metres, seconds; world axes; moments about the object's
centre of mass. Forces are those the contacts apply ON the object; the hand feels -f.

``import grip`` does not import this module, and this module imports ``mujoco`` only when
an Adapter is built or a function that reads MuJoCo's state is called.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ._grip import (
    ContributionTable,
    Grasp,
    GraspType,
    Model,
    Status,
    contribution_table,
    hand_body_names,
    max_contacts,
    solve_constrained,
)

__all__ = [
    "ALLEGRO_LEFT",
    "ALLEGRO_RIGHT",
    "Adapter",
    "Felt",
    "GRIP_HAND",
    "HAND_BODY_COUNT",
    "ObjectWrench",
    "SHADOW_LEFT",
    "SHADOW_RIGHT",
    "Update",
    "contact_force_on_geom2",
    "contact_wrench",
    "free_body_wrench",
    "grip_hand_bodies",
]

HAND_BODY_COUNT = 19
"""grip's hand bodies: 14 phalanges (0..13) then 5 metacarpals (14..18), docs/hand.md."""


def _mujoco():
    """The ``mujoco`` package, imported on first use (ImportError saying what to install)."""
    try:
        import mujoco
    except ImportError as error:  # pragma: no cover - exercised only without mujoco
        raise ImportError("grip.mujoco needs MuJoCo's Python package: pip install mujoco") from error
    return mujoco


# ----------------------------------------------------------------------------------------
# Body maps: {MuJoCo body name: grip body index}.


def grip_hand_bodies(prefix=""):
    """The body map of grip's own hand as ``grip.hand_mjcf(prefix=prefix)`` writes it:
    ``{prefix + hand_body_names()[k]: k}``."""
    return {prefix + name: k for k, name in enumerate(hand_body_names())}


GRIP_HAND = grip_hand_bodies()
"""grip's hand written by ``grip.hand_mjcf()`` (no prefix): each of its 19 bodies."""


def _shadow(side):
    m = {}
    for finger, (proximal, middle, distal) in {"ff": (2, 3, 4), "mf": (5, 6, 7), "rf": (8, 9, 10),
                                               "lf": (11, 12, 13)}.items():
        m.update({f"{side}_{finger}knuckle": proximal, f"{side}_{finger}proximal": proximal,
                  f"{side}_{finger}middle": middle, f"{side}_{finger}distal": distal})
    m.update({f"{side}_lfmetacarpal": 18, f"{side}_palm": 16, f"{side}_thbase": 14, f"{side}_thproximal": 14,
              f"{side}_thhub": 14, f"{side}_thmiddle": 0, f"{side}_thdistal": 1})
    return m


SHADOW_RIGHT = _shadow("rh")
"""MuJoCo Menagerie's Shadow Hand, ``shadow_hand/right_hand.xml``: each finger's knuckle and
proximal link as grip's proximal phalanx, middle and distal as theirs; the little finger's
metacarpal link as grip's (18); the palm as the long finger's metacarpal (16, the palm's
middle); the thumb's base, proximal link and hub as its metacarpal (14), its middle and
distal links as its proximal (0) and distal (1) phalanges. The forearm and wrist are not
mapped: their contacts with the object are ignored (same root body)."""

SHADOW_LEFT = _shadow("lh")
"""As SHADOW_RIGHT for ``shadow_hand/left_hand.xml`` (names lh_*)."""


def _allegro():
    m = {"palm": 16}
    for finger, (proximal, middle, distal) in {"ff": (2, 3, 4), "mf": (5, 6, 7), "rf": (8, 9, 10)}.items():
        m.update({f"{finger}_base": proximal, f"{finger}_proximal": proximal, f"{finger}_medial": middle,
                  f"{finger}_distal": distal, f"{finger}_tip": distal})
    m.update({"th_base": 14, "th_proximal": 14, "th_medial": 0, "th_distal": 1, "th_tip": 1})
    return m


ALLEGRO_RIGHT = _allegro()
"""MuJoCo Menagerie's Wonik Allegro Hand, ``wonik_allegro/right_hand.xml``: index (ff), long
(mf) and ring (rf) fingers, base and proximal link as grip's proximal phalanx, medial as the
middle, distal and tip as the distal; the thumb's base and proximal link as its metacarpal
(14), medial as its proximal phalanx (0), distal and tip as its distal (1); the palm as 16.
The Allegro hand has no little finger."""

ALLEGRO_LEFT = _allegro()
"""As ALLEGRO_RIGHT for ``wonik_allegro/left_hand.xml`` (the same body names)."""


# ----------------------------------------------------------------------------------------
# MuJoCo's state: contact forces and a free body's wrench.


def contact_force_on_geom2(model, data, i):
    """(force (3,), torque (3,)): what contact ``i`` of ``data`` applies to the body holding its
    geom2 (N; N m, world axes): ``mujoco.mj_contactForce`` turned out of the contact frame
    (frame^T f; the normal, frame[0:3], points from geom1 to geom2). The torque is the
    contact's torsional and rolling torques only, about the contact point (zero for condim 1
    and 3). geom1's body feels the opposite."""
    mujoco = _mujoco()
    local = np.zeros(6)
    mujoco.mj_contactForce(model, data, i, local)
    frame = np.asarray(data.contact.frame[i], dtype=float).reshape(3, 3)
    return frame.T @ local[:3], frame.T @ local[3:]


def _contact_bodies(model, data, i):
    """The bodies of contact i's geom1 and geom2 (-1 for a side that is not a geom: a flex)."""
    g1, g2 = int(data.contact.geom1[i]), int(data.contact.geom2[i])
    b1 = int(model.geom_bodyid[g1]) if g1 >= 0 else -1
    b2 = int(model.geom_bodyid[g2]) if g2 >= 0 else -1
    return b1, b2


def contact_wrench(model, data, i, body, about):
    """MuJoCo's own wrench (6,) of contact ``i`` on body id ``body``, one of its two geoms'
    bodies: [f; (p - about) x f + torque] with p the contact point (N; N m, world axes, the
    moment about the world point ``about`` (3,), m). Zero when neither geom belongs to
    ``body``."""
    b1, b2 = _contact_bodies(model, data, i)
    w = np.zeros(6)
    if body not in (b1, b2):
        return w
    f, t = contact_force_on_geom2(model, data, i)
    if b2 != body:
        f, t = -f, -t
    r = np.asarray(data.contact.pos[i], dtype=float) - np.asarray(about, dtype=float)
    w[:3] = f
    w[3:] = np.cross(r, f) + t
    return w


@dataclass
class ObjectWrench:
    """The terms of a free body's external wrench (6,) each: force (N) then moment (N m) about
    its centre of mass, world axes. ``total()`` is grip's w_ext (G x + w_ext = 0)."""

    gravity: np.ndarray = field(default_factory=lambda: np.zeros(6))    #: [m g; 0]
    inertial: np.ndarray = field(default_factory=lambda: np.zeros(6))   #: [-m a; -(I alpha + w x I w)]
    applied: np.ndarray = field(default_factory=lambda: np.zeros(6))    #: the body's xfrc_applied
    obstacles: np.ndarray = field(default_factory=lambda: np.zeros(6))  #: contacts outside the hand

    def total(self):
        """The sum of the four terms (6,)."""
        return self.gravity + self.inertial + self.applied + self.obstacles


def free_body_wrench(model, data, body):
    """The gravity, inertial and applied terms of body id ``body``'s external wrench (an
    ObjectWrench whose ``obstacles`` is zero), read from MuJoCo's state after mj_forward or
    mj_step. The body must have one joint, a free one. Its centre of mass accelerates at
    a = a_o + alpha x r + w x (w x r): a_o = qacc[dof:dof+3] the body origin's acceleration
    (world), alpha = xmat qacc[dof+3:dof+6] (qacc holds it in body axes), w = cvel[body][0:3]
    (world), r = xipos - xpos; I = ximat diag(body_inertia) ximat^T."""
    dof = int(model.jnt_dofadr[model.body_jntadr[body]])
    mass = float(model.body_mass[body])
    g = np.asarray(model.opt.gravity, dtype=float)
    R = np.asarray(data.xmat[body], dtype=float).reshape(3, 3)    # body frame -> world
    Ri = np.asarray(data.ximat[body], dtype=float).reshape(3, 3)  # inertial frame -> world
    r = np.asarray(data.xipos[body], dtype=float) - np.asarray(data.xpos[body], dtype=float)
    omega = np.asarray(data.cvel[body][:3], dtype=float)
    qacc = np.asarray(data.qacc[dof:dof + 6], dtype=float)
    alpha = R @ qacc[3:]
    a = qacc[:3] + np.cross(alpha, r) + np.cross(omega, np.cross(omega, r))
    inertia = Ri @ np.diag(np.asarray(model.body_inertia[body], dtype=float)) @ Ri.T
    w = ObjectWrench()
    w.gravity[:3] = mass * g
    w.inertial[:3] = -mass * a
    w.inertial[3:] = -(inertia @ alpha + np.cross(omega, inertia @ omega))
    w.applied[:] = np.asarray(data.xfrc_applied[body], dtype=float)
    return w


# ----------------------------------------------------------------------------------------
# The adapter.


@dataclass
class Update:
    """What ``Adapter.update(data)`` read: the grasp (None without hand contact), w_ext and
    its terms, and per grasp contact (n of them) its MuJoCo contact index, hand body id and
    grip body. status: Ok, or OutOfRange when the hand touched the object at more than
    grip.max_contacts points (the grasp holds the first ones; ``dropped`` counts the rest)."""

    status: Status
    grasp: Grasp | None
    wrench: ObjectWrench
    center_of_mass: np.ndarray  #: (3,) the object's centre of mass (m, world)
    positions: np.ndarray       #: (n, 3) contact point - centre of mass (m, world)
    normals: np.ndarray         #: (n, 3) unit, into the object
    friction: np.ndarray        #: (n,) tangential coefficient
    torsional_friction: np.ndarray  #: (n,) m
    squeeze: np.ndarray         #: (n,) N
    contacts: np.ndarray        #: (n,) int, index in data.contact
    bodies: np.ndarray          #: (n,) int, the hand body's MuJoCo id
    grip_bodies: np.ndarray     #: (n,) int, its grip body 0..18
    ignored: int = 0            #: contacts with unmapped hand bodies
    obstacles: int = 0          #: contacts whose force is in w_ext
    dropped: int = 0            #: hand contacts beyond grip.max_contacts

    @property
    def w_ext(self):
        """The object's external wrench (6,) (N; N m about its centre of mass, world)."""
        return self.wrench.total()


@dataclass
class Felt:
    """What ``Adapter.solve()`` found: the solver's status; the forces (n, 3) the grasp's
    contacts apply ON the object (N, world); per grip body (19): ``felt`` (19, 3) the sum of
    -f over its contacts (N, what the hand feels), ``points`` (19, 3) their force-weighted
    point (m, world; a body in contact whose forces are all zero: the mean of its contact
    points; a body without contact: zeros), ``weight`` (19,) the sum of |f| (N),
    ``in_contact`` (19,) bool; and the update's w_ext, counts, MuJoCo contact indices
    ``contacts`` (n,), hand body ids ``bodies`` (n,) and grip bodies ``grip_bodies`` (n,).
    ``solution`` is the solver's own result (None without contact)."""

    status: Status
    forces: np.ndarray
    felt: np.ndarray
    points: np.ndarray
    weight: np.ndarray
    in_contact: np.ndarray
    w_ext: np.ndarray
    ignored: int
    obstacles: int
    contacts: np.ndarray
    bodies: np.ndarray
    grip_bodies: np.ndarray
    solution: object = None


def _real_array(value, name):
    value = np.asarray(value)
    if value.dtype.kind == "c":
        raise TypeError(f"{name}: complex values are not accepted (imaginary parts would be dropped)")
    if value.dtype.kind not in "biuf":
        raise TypeError(f"{name} must be numbers, not {value.dtype}")
    return np.asarray(value, dtype=float)


def _per_body(value, name, least, strict=False):
    """A number per grip body (19,): a scalar for all, or (19,); finite and >= (or >) least."""
    a = _real_array(value, name)
    if a.shape not in ((), (HAND_BODY_COUNT,)):
        raise ValueError(f"{name} must be a number or have shape ({HAND_BODY_COUNT},), not {a.shape}")
    a = np.broadcast_to(a, (HAND_BODY_COUNT,)).copy()
    bad = ~np.isfinite(a) | ((a <= least) if strict else (a < least))
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        label = name if np.ndim(value) == 0 else f"{name}[{k}]"
        raise ValueError(f"{label} must be finite and {'>' if strict else '>='} {least:g}, not {a[k]}")
    return a


def _contributions(contribution):
    """d per grip body (19,) from None (the cylindrical power grip), a GraspType, a
    ContributionTable, a number or a (19,) array."""
    if contribution is None:
        contribution = GraspType.CylindricalPower
    if isinstance(contribution, GraspType):
        contribution = contribution_table(contribution)
    if isinstance(contribution, ContributionTable):
        return np.concatenate([np.asarray(contribution.by_phalanx, dtype=float),
                               np.full(HAND_BODY_COUNT - 14, contribution.palm / 5.0)])
    return _per_body(contribution, "contribution", 0.0)


class Adapter:
    """The adapter for a hand (a body map) and one object body of a ``mujoco.MjModel``.

    bodies: {MuJoCo body name: grip body index 0..18} (GRIP_HAND, SHADOW_RIGHT,
    ALLEGRO_RIGHT, ... or your own); several MuJoCo bodies may stand for one grip body.
    object: the object body's name; it must have exactly one joint, a free one.
    contact_model: grip.Model of the grasp. stiffness K (N/m), contribution d and weight w
    per grip body: a number or (19,) each; contribution None is grip's cylindrical power grip
    table (a grip.GraspType or grip.ContributionTable picks another), the metacarpals sharing
    its palm's share (palm / 5 each, as the C++ ContactParameters). inertial: add the object's
    inertial wrench (False: gravity statics). obstacles: add the contacts with bodies outside
    the hand to w_ext.

    ValueError names the problem: the model's timestep not finite and positive or its gravity
    not finite; an empty map, a name not in the model, the world body, a grip index outside
    0..18; the object missing, one of the map's bodies, or without a single free joint.
    """

    def __init__(self, model, object, bodies, *, contact_model=Model.HardFinger, stiffness=1e4,
                 contribution=None, weight=1.0, inertial=True, obstacles=True):
        mujoco = _mujoco()
        timestep = float(model.opt.timestep)
        gravity = np.asarray(model.opt.gravity, dtype=float)
        if not (math.isfinite(timestep) and timestep > 0):
            raise ValueError(f"the model's timestep must be finite and > 0, not {timestep}")
        if not np.isfinite(gravity).all():
            raise ValueError(f"the model's gravity must be finite, not {gravity}")
        if not isinstance(bodies, Mapping) or len(bodies) == 0:
            raise ValueError("bodies must be a non-empty dict {MuJoCo body name: grip body index 0..18}")
        body_type = mujoco.mjtObj.mjOBJ_BODY
        self._grip_of = np.full(model.nbody, -1, dtype=int)
        roots = set()
        for name, k in bodies.items():
            if not isinstance(name, str):
                raise ValueError(f"bodies: the name {name!r} is not a str")
            if isinstance(k, complex) or np.iscomplexobj(k):
                raise TypeError(f"bodies[{name!r}]: complex values are not accepted")
            if isinstance(k, (bool, np.bool_)) or not isinstance(k, numbers.Integral):
                raise ValueError(f"bodies[{name!r}] must be an int grip body index 0..18, not {k!r}")
            if not 0 <= int(k) < HAND_BODY_COUNT:
                raise ValueError(f"bodies[{name!r}]: grip body index {int(k)} is out of range 0..18")
            body = mujoco.mj_name2id(model, body_type, name)
            if body < 0:
                raise ValueError(f"bodies: {name!r} is not a body of the model")
            if body == 0:
                raise ValueError(f"bodies: {name!r} is the world body, not a hand body")
            self._grip_of[body] = int(k)
            roots.add(int(model.body_rootid[body]))
        #: The root body (child of the world) the map's bodies share, or -1 when they have several.
        self.root = roots.pop() if len(roots) == 1 else -1
        if not isinstance(object, str):
            raise ValueError(f"object must be a body name (str), not {object!r}")
        obj = mujoco.mj_name2id(model, body_type, object)
        if obj <= 0:
            raise ValueError(f"object {object!r} is not a body of the model")
        if self._grip_of[obj] >= 0:
            raise ValueError(f"object {object!r} is one of the hand's bodies (in the body map)")
        if model.body_jntnum[obj] != 1 or model.jnt_type[model.body_jntadr[obj]] != mujoco.mjtJoint.mjJNT_FREE:
            raise ValueError(f"object {object!r} has no free joint (it needs exactly one joint, a free one)")
        if not isinstance(contact_model, Model):
            raise ValueError(f"contact_model must be a grip.Model, not {contact_model!r}")
        self.model = model
        self.object = obj                     #: the object's body id
        self.object_name = object
        self.bodies = dict(bodies)
        self.contact_model = contact_model
        self.stiffness = _per_body(stiffness, "stiffness", 0.0)           #: K (19,) N/m
        self.contribution = _contributions(contribution)                    #: d (19,)
        self.weight = _per_body(weight, "weight", 1e-12, strict=False)      #: w (19,)
        self.inertial = bool(inertial)
        self.obstacles = bool(obstacles)
        self.last = None  #: the last update()'s Update

    def grip_body(self, body):
        """The grip body (0..18) of MuJoCo body id ``body``, or -1 when the map does not name it."""
        return int(self._grip_of[body]) if 0 <= body < len(self._grip_of) else -1

    def update(self, data):
        """Reads ``data`` (an MjData of the model, after mj_forward or mj_step) and returns an
        Update: the grasp of the hand's contacts with the object and the object's w_ext.
        ValueError when the state is not finite."""
        m, obj = self.model, self.object
        com = np.array(data.xipos[obj], dtype=float)
        if not np.isfinite(com).all():
            raise ValueError("the object's centre of mass (xipos) is not finite")
        wrench = free_body_wrench(m, data, obj)
        if not self.inertial:
            wrench.inertial[:] = 0.0
        contact = data.contact
        ncon = int(data.ncon)
        exclude = np.asarray(contact.exclude[:ncon])
        efc = np.asarray(contact.efc_address[:ncon])
        rows, ignored, obstacles, dropped = [], 0, 0, 0
        for i in range(ncon):
            if exclude[i] != 0 or efc[i] < 0:
                continue
            b1, b2 = _contact_bodies(m, data, i)
            if obj not in (b1, b2):
                continue
            other = b2 if b1 == obj else b1
            k = self.grip_body(other)
            if k < 0:
                if self.root >= 0 and other > 0 and int(m.body_rootid[other]) == self.root:
                    ignored += 1
                elif self.obstacles:
                    wrench.obstacles += contact_wrench(m, data, i, obj, com)
                    obstacles += 1
                continue
            if len(rows) >= max_contacts:
                dropped += 1
                continue
            rows.append((i, other, k))
        n = len(rows)
        index = np.array([r[0] for r in rows], dtype=int)
        bodies = np.array([r[1] for r in rows], dtype=int)
        grip_bodies = np.array([r[2] for r in rows], dtype=int)
        # The normal points from geom1 to geom2: into the object when the object holds geom2.
        sign = np.array([1.0 if _contact_bodies(m, data, i)[1] == obj else -1.0 for i in index])
        positions = np.asarray(contact.pos[:ncon], dtype=float).reshape(-1, 3)[index] - com
        normals = sign[:, None] * np.asarray(contact.frame[:ncon], dtype=float).reshape(-1, 9)[index, :3]
        dim = np.asarray(contact.dim[:ncon]).reshape(-1)[index]
        mu = np.asarray(contact.friction[:ncon], dtype=float).reshape(-1, 5)[index]
        friction = np.where(dim >= 3, np.minimum(mu[:, 0], mu[:, 1]), 0.0)
        torsional = np.where(dim >= 4, mu[:, 2], 0.0)
        depth = np.maximum(0.0, -np.asarray(contact.dist[:ncon], dtype=float).reshape(-1)[index])
        squeeze = self.contribution[grip_bodies] * self.stiffness[grip_bodies] * depth
        w_ext = wrench.total()
        if not np.isfinite(w_ext).all():
            raise ValueError("the object's external wrench is not finite (its state: qacc, cvel, xfrc_applied)")
        grasp = None
        if n > 0:
            grasp = Grasp(positions, normals, friction, torsional_friction=torsional, squeeze=squeeze,
                          weights=self.weight[grip_bodies], model=self.contact_model)
        self.last = Update(status=Status.OutOfRange if dropped else Status.Ok, grasp=grasp, wrench=wrench,
                           center_of_mass=com, positions=positions.reshape(n, 3), normals=normals.reshape(n, 3),
                           friction=friction, torsional_friction=torsional, squeeze=squeeze, contacts=index,
                           bodies=bodies, grip_bodies=grip_bodies, ignored=ignored, obstacles=obstacles,
                           dropped=dropped)
        return self.last

    def forces_on_object(self, forces):
        """The forces (n, 3) (N, world) on the object of a solver's unknowns ``forces`` (n, dim)
        for the last update's grasp: the first three columns for hard and soft fingers, x a_i
        for frictionless points."""
        forces = np.asarray(forces, dtype=float)
        if self.contact_model == Model.FrictionlessPoint:
            return forces.reshape(-1, 1) * self.last.normals
        return forces[:, :3].copy()

    def solve(self, solver=solve_constrained):
        """Solves the last update's grasp with ``solver`` (any callable (grasp, w_ext) ->
        result with ``status`` and ``forces``: grip.solve_constrained, solve_range_space,
        solve_kkt) and returns a Felt. With no contact (or before any update): Status.Singular
        and zero forces."""
        u = self.last
        felt = np.zeros((HAND_BODY_COUNT, 3))
        points = np.zeros((HAND_BODY_COUNT, 3))
        weight = np.zeros(HAND_BODY_COUNT)
        in_contact = np.zeros(HAND_BODY_COUNT, dtype=bool)
        empty = np.zeros(0, dtype=int)
        if u is None or u.grasp is None:
            return Felt(status=Status.Singular, forces=np.zeros((0, 3)), felt=felt, points=points, weight=weight,
                        in_contact=in_contact, w_ext=np.zeros(6) if u is None else u.w_ext,
                        ignored=0 if u is None else u.ignored, obstacles=0 if u is None else u.obstacles,
                        contacts=empty, bodies=empty, grip_bodies=empty)
        solution = solver(u.grasp, u.w_ext)
        forces = self.forces_on_object(solution.forces)
        at = u.positions + u.center_of_mass
        mean = np.zeros((HAND_BODY_COUNT, 3))
        count = np.zeros(HAND_BODY_COUNT)
        for i, k in enumerate(u.grip_bodies):
            w = float(np.linalg.norm(forces[i]))
            felt[k] -= forces[i]
            points[k] += w * at[i]
            weight[k] += w
            mean[k] += at[i]
            count[k] += 1
            in_contact[k] = True
        for k in range(HAND_BODY_COUNT):
            if weight[k] > 0:
                points[k] /= weight[k]
            elif count[k] > 0:
                points[k] = mean[k] / count[k]
        return Felt(status=solution.status, forces=forces, felt=felt, points=points, weight=weight,
                    in_contact=in_contact, w_ext=u.w_ext, ignored=u.ignored, obstacles=u.obstacles,
                    contacts=u.contacts, bodies=u.bodies, grip_bodies=u.grip_bodies, solution=solution)
