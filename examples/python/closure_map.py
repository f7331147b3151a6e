#!/usr/bin/python3
"""A force-closure map: a puck (radius 5 cm, 2 cm thick) pinched at its rim by two fingers at
0 and 150 degrees, pressing towards the axis, and pressed on its top face by a third finger
placed at every point of a grid; the colour is the closure margin of the three (friction
0.5; grip.evaluate_batch over every placement at once, on all cores). Writes closure_map.png.

    python3 examples/python/closure_map.py [output.png] [grid]
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import grip  # noqa: E402

R, HALF_THICKNESS, MU = 0.05, 0.01, 0.5


def main(out="closure_map.png", grid=121):
    grid = int(grid)
    xs = np.linspace(-R, R, grid)
    X, Y = np.meshgrid(xs, xs)
    inside = X ** 2 + Y ** 2 < (0.98 * R) ** 2
    k = int(np.sum(inside))
    fixed = np.radians([0, 150])
    positions = np.zeros((k, 3, 3))
    normals = np.zeros((k, 3, 3))
    for i, a in enumerate(fixed):  # on the rim, pressing towards the axis
        d = np.array([np.cos(a), np.sin(a), 0.0])
        positions[:, i] = R * d
        normals[:, i] = -d
    positions[:, 2] = np.stack([X[inside], Y[inside], np.full(k, HALF_THICKNESS)], axis=1)  # on the top face
    normals[:, 2] = [0.0, 0.0, -1.0]
    r = grip.evaluate_batch(positions, normals, MU, squeeze=1.0, epsilon_l1=False)
    margin = np.full(X.shape, np.nan)
    margin[inside] = np.where(r["status"] == int(grip.Status.Ok), r["closure_margin"], np.nan)

    fig, ax = plt.subplots(figsize=(5.8, 4.8))
    m = ax.pcolormesh(X * 100, Y * 100, margin, cmap="RdYlGn", vmin=-0.15, vmax=0.15, shading="auto")
    ax.contour(X * 100, Y * 100, np.nan_to_num(margin, nan=-1.0), levels=[1e-8], colors="k", linewidths=1)
    ax.plot(100 * R * np.cos(fixed), 100 * R * np.sin(fixed), "ks", ms=8, label="rim fingers")
    ax.add_patch(plt.Circle((0, 0), 100 * R, fill=False, color="0.3"))
    ax.set_aspect("equal")
    ax.set(xlabel="x (cm)", ylabel="y (cm)", title="Closure margin by the top finger's placement")
    fig.colorbar(m, label="margin (> 0: force closure)")
    ax.legend(loc="lower left")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}: {int(np.sum(r['closure']))} of {k} placements in force closure")


if __name__ == "__main__":
    main(*sys.argv[1:3])
