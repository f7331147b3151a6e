"""Complex input is refused, never cast to its real part: every array and number the bindings
and grip.batch take raises TypeError naming the argument when given complex values (as a
complex128 or complex64 array, a list of Python complex numbers, or a complex scalar), and
the same call with real values works."""

import re

import numpy as np
import pytest

import grip

ANGLES = np.radians([0, 120, 240])
P = 0.04 * np.stack([np.cos(ANGLES), np.sin(ANGLES), np.zeros(3)], axis=1)
A = -P / 0.04
W = np.array([0.0, 0.0, -4.9, 0.0, 0.0, 0.0])
GRASP = grip.Grasp(P, A, 0.5, squeeze=2.0)
SOFT = grip.Grasp(P, A, 0.5, torsional_friction=0.01, model=grip.Model.SoftFinger)
SHAPE = grip.Shape([grip.sphere(0.05)])
# A closed tetrahedron, its triangles counter-clockwise seen from outside.
VERTICES = 0.05 * np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
TRIANGLES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
MESH = grip.Mesh.from_arrays(VERTICES, TRIANGLES)
LOOP = grip.HapticLoop(position=(0.0, 0.0, 0.0))
K, N = 4, 3
BP = np.broadcast_to(P, (K, N, 3)).copy()
BA = np.broadcast_to(A, (K, N, 3)).copy()


def case(call, kwargs, *names):
    """One pytest case per argument in `names`: call(**kwargs) works, and complex values for
    that argument raise TypeError naming it."""
    return [pytest.param(call, kwargs, name, id=f"{call.__name__}-{name}") for name in names]


def grasp(**k):
    return grip.Grasp(**k)


def solve_range_space(**k):
    return grip.solve_range_space(GRASP, **k)


def solve_kkt(**k):
    return grip.solve_kkt(GRASP, **k)


def solve_constrained(**k):
    return grip.solve_constrained(GRASP, **k)


def kkt_rhs(**k):
    return GRASP.kkt_rhs(**k)


def monitor(**k):
    return grip.monitor(SOFT, **k)


def decompose_forces(**k):
    return grip.decompose_forces(GRASP, **k)


def grasp_quality(**k):
    return grip.grasp_quality(GRASP, **k)


def epsilon(**k):
    return grip.epsilon(GRASP, **k)


def constrained_settings(**k):
    s = grip.ConstrainedSettings()
    for name, value in k.items():
        setattr(s, name, value)
    return s


def analysis_settings(**k):
    s = grip.ConicAnalysisSettings()
    for name, value in k.items():
        setattr(s, name, value)
    return s


def evaluate_batch(**k):
    return grip.evaluate_batch(**k)


def solve_batch(**k):
    return grip.solve_batch(**k)


def forward_kinematics(**k):
    return grip.forward_kinematics(**k)


def point_jacobian(**k):
    return grip.point_jacobian(**k)


def hand_dimensions(**k):
    return grip.HandDimensions.standard(**k)


def hand_dimensions_set(**k):
    d = grip.HandDimensions.standard()
    for name, value in k.items():
        setattr(d, name, value)
    return d


def contribution_table(**k):
    return grip.ContributionTable(**k)


def finger_total(**k):
    return grip.contribution_table().finger_total(**k)


def sphere(**k):
    return grip.sphere(**k)


def box(**k):
    return grip.box(**k)


def cylinder(**k):
    return grip.cylinder(**k)


def capsule(**k):
    return grip.capsule(**k)


def shape_distance(**k):
    return SHAPE.distance(**k)


def hand_contacts(**k):
    return grip.hand_contacts(SHAPE, **k)


def mesh_from_arrays(**k):
    return grip.Mesh.from_arrays(**k)


def mesh_distance(**k):
    return MESH.distance(**k)


def octree(**k):
    return grip.SphericalOctree(MESH, **k)


def haptic_loop(**k):
    return grip.HapticLoop(**k)


def haptic_step(**k):
    return LOOP.step(**k)


def close_hand(**k):
    return LOOP.close_hand(**k)


WRIST = np.eye(4)
CASES = (
    case(grasp, dict(positions=P, normals=A, friction=0.5, torsional_friction=0.01, squeeze=2.0, weights=1.0,
                     max_normal_force=100.0),
         "positions", "normals", "friction", "torsional_friction", "squeeze", "weights", "max_normal_force")
    + case(grasp, dict(positions=P, normals=A, friction=np.full(3, 0.5), squeeze=np.full(3, 2.0)),
           "friction", "squeeze")
    + case(solve_range_space, dict(w_ext=W), "w_ext")
    + case(solve_kkt, dict(w_ext=W), "w_ext")
    + case(solve_constrained, dict(w_ext=W, warm_start=np.zeros(6), warm_certificate=np.zeros(6)), "w_ext",
           "warm_start", "warm_certificate")
    + case(kkt_rhs, dict(w_ext=W), "w_ext")
    + case(monitor, dict(forces=np.zeros((3, 4)), relative_tolerance=1e-9, absolute_tolerance=0.0),
           "forces", "relative_tolerance", "absolute_tolerance")
    + case(decompose_forces, dict(forces=np.ones((3, 3))), "forces")
    + case(grasp_quality, dict(lever_length=0.05), "lever_length")
    + case(epsilon, dict(lever_length=0.05, sides=8), "lever_length", "sides")
    + case(constrained_settings, dict(tolerance=1e-7, certificate_tolerance=1e-7, least_residual_weight=1e-8,
                                      max_iterations=30, newton_passes=4),
           "tolerance", "certificate_tolerance", "least_residual_weight", "max_iterations", "newton_passes")
    + case(analysis_settings, dict(tolerance=1e-5, max_iterations=30), "tolerance", "max_iterations")
    + case(evaluate_batch, dict(positions=BP, normals=BA, friction=np.full((K, N), 0.5), torsional_friction=0.01,
                                squeeze=np.full(N, 1.0), weights=1.0, lever_length=0.05, sides=8, threads=1),
           "positions", "normals", "friction", "torsional_friction", "squeeze", "weights", "lever_length", "sides",
           "threads")
    + case(solve_batch, dict(positions=BP, normals=BA, friction=0.5, w_ext=np.tile(W, (K, 1)),
                             max_normal_force=np.full(N, 50.0), method="constrained", threads=1),
           "positions", "normals", "friction", "w_ext", "max_normal_force", "threads")
    + case(solve_batch, dict(positions=BP, normals=BA, friction=0.5, w_ext=W), "w_ext")
    + case(forward_kinematics, dict(wrist=WRIST, angles=np.zeros(14)), "wrist", "angles")
    + case(forward_kinematics, dict(wrist=WRIST, angles=np.zeros(20)), "angles")
    + case(point_jacobian, dict(wrist=WRIST, angles=np.zeros(20), body=3, point=np.zeros(3)), "wrist", "angles",
           "body", "point")
    + case(hand_dimensions, dict(hand_length=0.2), "hand_length")
    + case(hand_dimensions_set, dict(base=grip.HandDimensions.standard().base,
                                     thumb_cmc=grip.HandDimensions.standard().thumb_cmc), "base", "thumb_cmc")
    + case(contribution_table, dict(share=grip.contribution_table().share, palm=0.1), "share", "palm")
    + case(finger_total, dict(finger=1), "finger")
    + case(sphere, dict(radius=0.05, center=np.zeros(3)), "radius", "center")
    + case(box, dict(half_extents=np.full(3, 0.02), center=np.zeros(3), rotation=np.eye(3)),
           "half_extents", "center", "rotation")
    + case(cylinder, dict(radius=0.03, half_length=0.05, center=np.zeros(3), rotation=np.eye(3)),
           "radius", "half_length", "center", "rotation")
    + case(capsule, dict(radius=0.03, half_length=0.05, center=np.zeros(3), rotation=np.eye(3)),
           "radius", "half_length", "center", "rotation")
    + case(shape_distance, dict(points=np.zeros((2, 3))), "points")
    + case(hand_contacts, dict(wrist=WRIST, angles=np.zeros(14), object_pose=np.eye(4), per_phalanx=2),
           "wrist", "angles", "object_pose", "per_phalanx")
    + case(mesh_from_arrays, dict(vertices=VERTICES, triangles=TRIANGLES), "vertices", "triangles")
    + case(mesh_distance, dict(points=np.zeros((2, 3))), "points")
    + case(octree, dict(max_depth=3), "max_depth")
    + case(haptic_loop, dict(position=np.zeros(3), rotation=np.eye(3), radius=0.035, half_length=0.06, mass=0.4,
                             friction=0.8, stiffness=np.full(14, 3e4), device_limit=10.0, dt=1e-3, max_iterations=40,
                             obstacle_stiffness=2e4, obstacle_damping=50.0),
           "position", "rotation", "radius", "half_length", "mass", "friction", "stiffness", "device_limit", "dt",
           "max_iterations", "obstacle_stiffness", "obstacle_damping")
    + case(haptic_step, dict(wrist=WRIST, angles=np.zeros(14), linear_velocity=np.zeros(3),
                             angular_velocity=np.zeros(3), linear_acceleration=np.zeros(3),
                             angular_acceleration=np.zeros(3)),
           "wrist", "angles", "linear_velocity", "angular_velocity", "linear_acceleration", "angular_acceleration")
    + case(close_hand, dict(wrist=WRIST, depth=0.002), "wrist", "depth")
)


def complex_forms(value):
    """value with imaginary parts, as each kind of complex input: arrays of complex128 and
    complex64, a list of Python complex numbers; for a scalar also NumPy's and Python's
    complex scalars."""
    z = np.asarray(value, dtype=float) + 0.5j
    forms = [z, z.astype(np.complex64), z.tolist()]
    if z.ndim == 0:
        forms += [np.complex128(z), np.complex64(z), complex(z)]
    return forms


def refused(name):
    return pytest.raises(TypeError, match=rf"^{re.escape(name)}: complex values are not accepted \(imaginary parts "
                                          r"would be dropped\)$")


@pytest.mark.parametrize("call, kwargs, name", CASES)
def test_complex_values_raise_type_error_naming_the_argument(call, kwargs, name):
    call(**kwargs)  # real values work
    for form in complex_forms(kwargs[name]):
        with refused(name):
            call(**dict(kwargs, **{name: form}))


def test_complex_values_with_zero_imaginary_parts_are_refused_too():
    # The dtype decides, not the values: a complex array is refused even when its numbers are real.
    with refused("positions"):
        grip.Grasp(P.astype(complex), A, 0.5)
    with refused("w_ext"):
        grip.solve_range_space(GRASP, W + 0j)
    with refused("lever_length"):
        grip.grasp_quality(GRASP, np.complex128(0.05))


def test_an_obstacle_box_with_complex_corners_is_refused_by_its_index():
    box = (np.array([0.1, -0.1, -0.1]), np.array([0.2, 0.1, 0.1]))
    grip.HapticLoop(position=np.zeros(3), boxes=[box])
    with refused("boxes[1] (lower corner)"):
        grip.HapticLoop(position=np.zeros(3), boxes=[box, (box[0] + 0.5j, box[1])])
    with refused("boxes[0] (upper corner)"):
        grip.HapticLoop(position=np.zeros(3), boxes=[(box[0], box[1] + 0.5j)])


def test_the_modules_batch_functions_refuse_complex_arrays_themselves():
    # grip.batch checks first; the C++ functions it calls check again, so that no caller of
    # the module gets imaginary parts dropped.
    f = np.full((K, N), 0.5)
    z = np.zeros((K, N))
    o = np.ones((K, N))
    real = (BP, BA, f, z, z, o)
    metrics = grip._grip._evaluate_batch(*real, grip.Model.HardFinger, 1.0, True, True, False, 8, 1, 0)
    assert metrics["status"].shape == (K,)
    names = ("positions", "normals", "friction", "torsional_friction", "squeeze", "weights")
    for i, name in enumerate(names):
        args = list(real)
        args[i] = args[i] + 0.5j
        with refused(name):
            grip._grip._evaluate_batch(*args, grip.Model.HardFinger, 1.0, True, True, False, 8, 1, 0)
    w = np.tile(W, (K, 1))
    settings = grip.ConstrainedSettings()
    grip._grip._solve_batch(*real, np.full((K, N), 50.0), grip.Model.HardFinger, w, "kkt", settings, 1, 0)
    with refused("w_ext"):
        grip._grip._solve_batch(*real, None, grip.Model.HardFinger, w + 0.5j, "kkt", settings, 1, 0)
    with refused("max_normal_force"):
        grip._grip._solve_batch(*real, np.full((K, N), 50.0 + 1j), grip.Model.HardFinger, w, "kkt", settings, 1, 0)
    with refused("lever_length"):
        grip._grip._evaluate_batch(*real, grip.Model.HardFinger, np.complex128(1.0), True, True, False, 8, 1, 0)


def test_dask_batches_refuse_complex_arrays():
    pytest.importorskip("distributed")
    da = pytest.importorskip("dask.array")
    import grip.dask

    f = np.full((K, N), 0.5)
    grip.dask.evaluate_batch(BP, BA, f, chunk_size=2)
    for name, kwargs in [("positions", dict(positions=BP + 0.5j)), ("normals", dict(normals=BA + 0.5j)),
                         ("friction", dict(friction=f + 0.5j)), ("squeeze", dict(squeeze=0.5 + 0.5j))]:
        args = dict(dict(positions=BP, normals=BA, friction=f), **kwargs)
        with refused(name):
            grip.dask.evaluate_batch(chunk_size=2, **args)
    with refused("positions"):  # a Dask array: refused by its dtype, before anything is computed
        grip.dask.evaluate_batch(da.from_array(BP + 0.5j, chunks=(2, N, 3)), BA, f, chunk_size=2)
    with refused("friction"):
        grip.dask.evaluate_batch(BP, BA, da.from_array(f + 0.5j, chunks=(2, N)), chunk_size=2)
    w = np.tile(W, (K, 1))
    grip.dask.solve_batch(BP, BA, 0.5, w, chunk_size=2)
    with refused("w_ext"):
        grip.dask.solve_batch(BP, BA, 0.5, w + 0.5j, chunk_size=2)
    with refused("w_ext"):
        grip.dask.solve_batch(BP, BA, 0.5, da.from_array(w + 0.5j, chunks=(2, 6)), chunk_size=2)
    with refused("max_normal_force"):
        grip.dask.solve_batch(BP, BA, 0.5, w, max_normal_force=50.0 + 1j, chunk_size=2)
