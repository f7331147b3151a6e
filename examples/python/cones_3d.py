#!/usr/bin/python3
"""Three fingers hold a 4 cm ball against gravity and a sideways push: the friction cones at
the contacts and the forces that the optimum inside the cones applies, in 3-D. Writes
cones_3d.png.

    python3 examples/python/cones_3d.py [output.png]
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import grip  # noqa: E402

R = 0.04


def main(out="cones_3d.png"):
    angles = np.radians([90, 210, 330])
    positions = R * np.stack([np.cos(angles), np.sin(angles), [0.3, -0.2, -0.2]], axis=1)
    positions = R * positions / np.linalg.norm(positions, axis=1)[:, None]
    normals = -positions / R
    mu = np.array([0.6, 0.5, 0.7])
    g = grip.Grasp(positions, normals, mu, squeeze=3.0)
    w = np.array([2.0, 0.0, -0.3 * 9.81, 0.0, 0.0, 0.0])
    s = grip.solve_constrained(g, w)
    assert s.status == grip.Status.Ok, s.status

    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="3d")
    u, v = np.mgrid[0:2 * np.pi:30j, 0:np.pi:15j]
    ax.plot_surface(R * np.cos(u) * np.sin(v), R * np.sin(u) * np.sin(v), R * np.cos(v), color="0.85", alpha=0.3)
    scale = 0.008  # m per N
    for p, a, m, f in zip(positions, normals, mu, s.forces):
        t1 = np.cross(a, [0, 0, 1.0]) if abs(a[2]) < 0.9 else np.cross(a, [1.0, 0, 0])
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(a, t1)
        h = 0.03  # the cone's height, m: it opens outwards from the contact, against the normal
        th = np.linspace(0, 2 * np.pi, 40)
        rim = p - h * a + (h * m) * (np.cos(th)[:, None] * t1 + np.sin(th)[:, None] * t2)
        for q in rim[::5]:
            ax.plot(*zip(p, q), color="tab:blue", lw=0.6)
        ax.plot(*rim.T, color="tab:blue", lw=0.8)
        # the force the contact applies ON the ball (inside its cone, pointing inwards)
        ax.quiver(*(p - scale * f), *(scale * f), color="tab:red", lw=2.5)
    ax.set_title("Friction cones and the optimal contact forces (red)")
    ax.set_box_aspect((1, 1, 1))
    lim = 0.08
    ax.set(xlim=(-lim, lim), ylim=(-lim, lim), zlim=(-lim, lim), xlabel="x (m)", ylabel="y (m)", zlabel="z (m)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
