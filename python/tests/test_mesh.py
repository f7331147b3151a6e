"""Meshes and octrees from Python: a cube mesh against the box's closed-form distance, the
test meshes of the C++ suite, refused meshes, and the hand's contacts with a mesh (by the
octree and directly) against those with the analytic box."""

import os

import numpy as np
import pytest

import grip

MESHES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "data", "meshes")
H = np.array([0.03, 0.02, 0.025])


def cube(h=H):
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * h
    # counter-clockwise seen from outside: two triangles per face
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    t = []
    for a, b, c, d in faces:
        t += [(a, b, c), (a, c, d)]
    return v, np.array(t)


def box_distance(p, h=H):
    q = np.abs(p) - h
    return np.linalg.norm(np.maximum(q, 0), axis=1) + np.minimum(q.max(axis=1), 0)


def test_a_cube_mesh_has_the_box_distance():
    m = grip.Mesh.from_arrays(*cube())
    assert m.triangle_count == 12 and m.components == 1 and not m.flipped
    assert m.volume == pytest.approx(8 * np.prod(H), rel=1e-12)
    p = np.random.default_rng(17).uniform(-0.06, 0.06, size=(400, 3))
    d, n = m.distance(p)
    assert np.allclose(d, box_distance(p), atol=1e-12)
    assert np.allclose(np.linalg.norm(n, axis=1), 1, atol=1e-12)


def test_the_test_meshes_load_and_inside_points_are_negative():
    for name in ("tetrahedron.stl", "mug.stl", "blob.obj"):
        m = grip.Mesh.load(os.path.join(MESHES, name))
        assert m.triangle_count > 0 and m.volume > 0
        centroid = m.vertices.mean(axis=0)
        far = centroid + 10 * np.ptp(m.vertices, axis=0)
        d, _ = m.distance(np.array([far]))
        assert d[0] > 0
    blob = grip.Mesh.load(os.path.join(MESHES, "blob.obj"))
    assert blob.distance(blob.vertices.mean(axis=0)[None])[0][0] < 0  # the blob is star-shaped about its centroid


def test_refused_meshes_raise_value_error_naming_the_issue():
    v, t = cube()
    with pytest.raises(ValueError, match="not closed"):
        grip.Mesh.from_arrays(v, t[:-1])
    with pytest.raises(ValueError, match=r"vertices\[3\] is not finite"):
        bad = v.copy()
        bad[3, 0] = np.nan
        grip.Mesh.from_arrays(bad, t)
    # Vertex indices given as floats: whole numbers are indices, a fraction is refused (a cast
    # to an integer would silently truncate it).
    assert grip.Mesh.from_arrays(v, t.astype(float)).triangle_count == len(t)
    frac = t.astype(float)
    frac[5, 1] += 0.5
    with pytest.raises(ValueError, match=r"triangles\[5\] must hold integers"):
        grip.Mesh.from_arrays(v, frac)
    nan = t.astype(float)
    nan[2, 0] = np.nan
    with pytest.raises(ValueError, match=r"triangles\[2\] must hold integers"):
        grip.Mesh.from_arrays(v, nan)
    # A binary STL that declares 4 facets and holds 2.
    facet = np.zeros(12, dtype="<f4").tobytes() + b"\0\0"
    with pytest.raises(ValueError, match="truncated"):
        grip.Mesh.from_bytes(b"\0" * 80 + np.array([4], dtype="<u4").tobytes() + 2 * facet, "stl")
    with pytest.raises(ValueError, match=r"malformed, line \d+"):
        grip.Mesh.from_bytes(open(os.path.join(MESHES, "tetrahedron.stl"), "rb").read()[:-20], "stl")
    with pytest.raises(ValueError, match="index out of range|malformed|refers"):
        grip.Mesh.from_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "obj")
    with pytest.raises(ValueError, match="cannot be opened"):
        grip.Mesh.load("/nonexistent/file.stl")
    with pytest.raises(ValueError, match="format must be"):
        grip.Mesh.from_bytes(b"", "ply")


def test_hand_contacts_with_a_mesh_equal_those_with_the_analytic_box():
    mesh = grip.Mesh.from_arrays(*cube())
    box = grip.Shape([grip.box(H)])
    tree = grip.SphericalOctree(mesh, 4)
    box_tree = grip.SphericalOctree(box, 4)
    q = np.zeros(14)
    rng = np.random.default_rng(18)
    checked = 0
    for _ in range(30):
        # the box under the open palm-down hand, pressed up into the fingers by 1 to 4 mm
        wrist = np.eye(4)
        pose = np.eye(4)
        pose[:3, 3] = [0.12 + rng.uniform(-0.03, 0.03), rng.uniform(-0.02, 0.02), -0.0076 - H[2] + rng.uniform(0.001, 0.004)]
        ref = grip.hand_contacts(box, wrist, q, pose)
        for got in (grip.hand_contacts(mesh, wrist, q, pose), grip.hand_contacts(mesh, wrist, q, pose, octree=tree),
                    grip.hand_contacts(box, wrist, q, pose, octree=box_tree)):
            assert got["status"] == grip.Status.Ok
            assert np.array_equal(got["phalanx"], ref["phalanx"])
            assert np.allclose(got["depth"], ref["depth"], atol=1e-9)
            assert np.allclose(got["point"], ref["point"], atol=1e-7)
            assert np.allclose(got["normal"], ref["normal"], atol=1e-7)
        checked += len(ref["depth"])
    assert checked > 30
    with pytest.raises(ValueError, match="the octree must be the one built from this field"):
        grip.hand_contacts(box, np.eye(4), q, octree=tree)


def test_octree_input_is_checked():
    with pytest.raises(ValueError, match="max_depth must be 0 .. 15"):
        grip.SphericalOctree(grip.Shape([grip.sphere(0.05)]), 16)
    with pytest.raises(ValueError, match="field must be a grip.Shape or a grip.Mesh"):
        grip.SphericalOctree(3.0, 2)
