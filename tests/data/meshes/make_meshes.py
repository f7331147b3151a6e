#!/usr/bin/env python3
"""Writes the test meshes of tests/data/meshes/ (Python 3, standard library only).

    python3 tests/data/meshes/make_meshes.py        # rewrites the three files next to this script

Coordinates are in metres (grip's unit).

tetrahedron.stl  ASCII STL: the corner tetrahedron (0,0,0), (a,0,0), (0,a,0), (0,0,a), a = 0.05,
                 4 facets, volume a^3 / 6.
mug.stl          binary STL: a cup, 60 mm high and 40 mm in outer radius, as a surface of
                 revolution (40 sectors) of a closed profile: the bottom with a rounded outer
                 edge, the 4 mm wall, a rounded rim (a half circle), the cavity with a rounded
                 inner bottom; a closed genus-0 surface with a pole at each end of the axis. The
                 handle is its own closed component: a tube of radius 4 mm around an ellipse in
                 the xz-plane (semi-axes 10 mm along x, 18 mm along z, centre x = 55 mm,
                 z = 30 mm), whose nearest point is 1 mm from the body's wall (x = 41 mm against
                 the wall's 40 mm; every facet of the body lies within radius 40 mm and every
                 facet of the handle beyond x = 41 mm, so they never touch). 36 x 10 quads;
                 3600 triangles in all.
blob.obj         a bunny-like blob: an icosphere subdivided 4 times (5120 triangles, 2562
                 vertices) whose vertices are moved along their directions d to the radius
                 r(d) = ellipsoid(d) (1 + ripples(d)) + two ear bumps (Gaussian in the angle to
                 two directions), so the surface is star-shaped about the origin and cannot
                 intersect itself; about 78 mm long, 58 mm wide and 72 mm high.
"""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def unit(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def volume(verts, tris):
    return sum(dot(verts[a], cross(verts[b], verts[c])) for a, b, c in tris) / 6.0


def normal(verts, t):
    a, b, c = (verts[i] for i in t)
    return unit(cross(sub(b, a), sub(c, a)))


# ---------------------------------------------------------------- tetrahedron (ASCII STL)
def tetrahedron():
    a = 0.05
    verts = [(0.0, 0.0, 0.0), (a, 0.0, 0.0), (0.0, a, 0.0), (0.0, 0.0, a)]
    tris = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    assert volume(verts, tris) > 0
    lines = ["solid tetrahedron"]
    for t in tris:
        n = normal(verts, t)
        lines.append("  facet normal %.6e %.6e %.6e" % n)
        lines.append("    outer loop")
        for i in t:
            lines.append("      vertex %.6e %.6e %.6e" % verts[i])
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append("endsolid tetrahedron")
    with open(os.path.join(HERE, "tetrahedron.stl"), "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


# ---------------------------------------------------------------- mug (binary STL)
def arc(cx, cz, r, a0, a1, n):
    """Points of a circular arc in the (r, z) half-plane from angle a0 to a1 (degrees), n steps, end excluded."""
    out = []
    for i in range(n):
        a = math.radians(a0 + (a1 - a0) * i / n)
        out.append((cx + r * math.cos(a), cz + r * math.sin(a)))
    return out


def line(p0, p1, n):
    """n points from p0 towards p1, p1 excluded."""
    return [(p0[0] + (p1[0] - p0[0]) * i / n, p0[1] + (p1[1] - p0[1]) * i / n) for i in range(n)]


def mug_profile():
    """(r, z) in mm from the bottom pole around to the inner pole."""
    R, H, t, tb, rf, ri = 40.0, 60.0, 4.0, 6.0, 4.0, 5.0
    rim = t / 2
    p = []
    p += line((0.0, 0.0), (R - rf, 0.0), 4)                       # outer bottom
    p += arc(R - rf, rf, rf, -90.0, 0.0, 4)                        # outer bottom edge
    p += line((R, rf), (R, H - rim), 7)                            # outer wall
    p += arc(R - rim, H - rim, rim, 0.0, 180.0, 8)                 # rim
    p += line((R - t, H - rim), (R - t, tb + ri), 6)               # inner wall
    p += arc(R - t - ri, tb + ri, ri, 0.0, -90.0, 4)               # inner bottom edge
    p += line((R - t - ri, tb), (0.0, tb), 4)                      # inner bottom
    p.append((0.0, tb))                                            # inner pole
    return p


def revolve(profile, sectors):
    """Vertices and triangles of the surface of revolution about z of a profile whose first and
    last points lie on the axis (poles)."""
    verts = [(0.0, 0.0, profile[0][1])]
    rings = []
    for r, z in profile[1:-1]:
        ring = []
        for j in range(sectors):
            a = 2 * math.pi * j / sectors
            ring.append(len(verts))
            verts.append((r * math.cos(a), r * math.sin(a), z))
        rings.append(ring)
    top = len(verts)
    verts.append((0.0, 0.0, profile[-1][1]))
    tris = []
    for j in range(sectors):
        k = (j + 1) % sectors
        tris.append((0, rings[0][k], rings[0][j]))
        for i in range(len(rings) - 1):
            a, b = rings[i], rings[i + 1]
            tris.append((a[j], a[k], b[k]))
            tris.append((a[j], b[k], b[j]))
        tris.append((top, rings[-1][j], rings[-1][k]))
    return verts, tris


def handle(ax, az, cx, cz, rt, nu, nv):
    verts, tris = [], []
    for i in range(nu):
        u = 2 * math.pi * i / nu
        c = (cx + ax * math.cos(u), 0.0, cz + az * math.sin(u))
        n = unit((az * math.cos(u), 0.0, ax * math.sin(u)))
        b = (0.0, 1.0, 0.0)
        for j in range(nv):
            v = 2 * math.pi * j / nv
            verts.append(tuple(c[k] + rt * (math.cos(v) * n[k] + math.sin(v) * b[k]) for k in range(3)))
    for i in range(nu):
        for j in range(nv):
            a = i * nv + j
            b = ((i + 1) % nu) * nv + j
            c = ((i + 1) % nu) * nv + (j + 1) % nv
            d = i * nv + (j + 1) % nv
            tris.append((a, b, c))
            tris.append((a, c, d))
    return verts, tris


def orient_outward(verts, tris):
    return tris if volume(verts, tris) > 0 else [(a, c, b) for a, b, c in tris]


def mug():
    bv, bt = revolve(mug_profile(), 40)
    bt = orient_outward(bv, bt)
    hv, ht = handle(10.0, 18.0, 55.0, 30.0, 4.0, 36, 10)
    ht = orient_outward(hv, ht)
    assert min(v[0] for v in hv) >= 41.0 - 1e-9
    off = len(bv)
    verts = [tuple(x / 1000.0 for x in v) for v in bv + hv]
    tris = bt + [(a + off, b + off, c + off) for a, b, c in ht]
    out = bytearray(b"grip test mug: a cup of revolution and a separate handle, metres".ljust(80, b" "))
    out += struct.pack("<I", len(tris))
    for t in tris:
        out += struct.pack("<3f", *normal(verts, t))
        for i in t:
            out += struct.pack("<3f", *verts[i])
        out += struct.pack("<H", 0)
    with open(os.path.join(HERE, "mug.stl"), "wb") as f:
        f.write(out)
    return len(tris)


# ---------------------------------------------------------------- blob (OBJ)
def icosphere(levels):
    g = (1 + math.sqrt(5)) / 2
    verts = [unit(v) for v in [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g),
                               (0, -1, -g), (0, 1, -g), (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]]
    tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
            (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
            (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mids = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in mids:
                mids[key] = len(verts)
                verts.append(unit(tuple((verts[a][k] + verts[b][k]) / 2 for k in range(3))))
            return mids[key]

        nxt = []
        for a, b, c in tris:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nxt += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        tris = nxt
    return verts, tris


def blob_radius(d):
    x, y, z = d
    body = 0.030 / math.sqrt((x / 1.0) ** 2 + (y / 1.25) ** 2 + (z / 0.9) ** 2)
    ripple = 1 + 0.05 * x * y + 0.04 * math.sin(3 * x + 1) * math.cos(2 * z)
    ears = 0.0
    for e in (unit((0.35, 0.3, 1.0)), unit((-0.35, 0.3, 1.0))):
        ears += 0.022 * math.exp(-(1 - dot(d, e)) / 0.02)
    return body * ripple + ears


def blob():
    dirs, tris = icosphere(4)
    verts = [tuple(blob_radius(d) * c for c in d) for d in dirs]
    lines = ["# grip test blob: icosphere level 4 displaced radially (tests/data/meshes/make_meshes.py), metres",
             "o blob"]
    lines += ["v %.6f %.6f %.6f" % v for v in verts]
    lines.append("s off")
    lines += ["f %d %d %d" % (a + 1, b + 1, c + 1) for a, b, c in tris]
    with open(os.path.join(HERE, "blob.obj"), "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")
    return len(tris)


if __name__ == "__main__":
    tetrahedron()
    print("mug.stl:", mug(), "triangles")
    print("blob.obj:", blob(), "triangles")
