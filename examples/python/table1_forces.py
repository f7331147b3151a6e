#!/usr/bin/python3
"""The paper's Table 1 power grip of a cylinder (radius 35 mm, 0.4 kg, axis vertical), held
by the twelve finger phalanges, the thumb and the palm: per phalanx, the squeeze that eq. 8
predicts (s_i = d_i times the grip force) against the normal force that the optimum inside
the friction cones applies, holding still and shaking. Writes table1_forces.png.

    python3 examples/python/table1_forces.py [output.png]
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import grip  # noqa: E402

RADIUS, MASS, GRIP_FORCE, MU = 0.035, 0.4, 30.0, 0.8
PALM = None
# name, azimuth around the axis (degrees; the palm at 180), height (m), digit (0 thumb .. 4
# little, PALM) and phalanx (0 proximal, 1 middle, 2 distal). Each share d_i is the cylindrical
# power grip's: Table 1 for the fingers, grip's choice for the thumb and palm (Table 1 gives none).
SITES = [("index prox.", 110, 0.030, 1, 0), ("index mid.", 40, 0.030, 1, 1), ("index dist.", -30, 0.030, 1, 2),
         ("long prox.", 110, 0.010, 2, 0), ("long mid.", 40, 0.010, 2, 1), ("long dist.", -30, 0.010, 2, 2),
         ("ring prox.", 110, -0.010, 3, 0), ("ring mid.", 40, -0.010, 3, 1), ("ring dist.", -30, -0.010, 3, 2),
         ("little prox.", 110, -0.030, 4, 0), ("little mid.", 40, -0.030, 4, 1), ("little dist.", -30, -0.030, 4, 2),
         ("thumb prox.", -150, 0.035, 0, 0), ("thumb dist.", -105, 0.040, 0, 2), ("palm", 180, 0.0, PALM, 0)]


def power_grip():
    table = grip.contribution_table(grip.GraspType.CylindricalPower)
    az = np.radians([s[1] for s in SITES])
    positions = np.stack([RADIUS * np.cos(az), RADIUS * np.sin(az), [s[2] for s in SITES]], axis=1)
    normals = np.stack([-np.cos(az), -np.sin(az), np.zeros(len(SITES))], axis=1)
    share = [table.palm if digit is PALM else table.share[digit, phalanx] for _, _, _, digit, phalanx in SITES]
    squeeze = GRIP_FORCE * np.array(share)
    return grip.Grasp(positions, normals, MU, squeeze=squeeze), squeeze


def main(out="table1_forces.png"):
    g, predicted = power_grip()
    gravity = np.array([0.0, 0.0, -9.81 * MASS, 0.0, 0.0, 0.0])
    shake = gravity - MASS * np.array([6.0, 0.0, 15.0, 0.0, 0.0, 0.0])  # inertia -m a of a = (6, 0, 15) m/s^2
    bars = [("predicted s_i (eq. 8)", predicted)]
    for label, w in (("solved, holding", gravity), ("solved, shaking", shake)):
        s = grip.solve_constrained(g, w)
        assert s.status == grip.Status.Ok, s.status
        bars.append((label, np.einsum("ij,ij->i", s.forces, g.normals)))
    x = np.arange(len(SITES))
    fig, ax = plt.subplots(figsize=(11, 4.2))
    for k, (label, values) in enumerate(bars):
        ax.bar(x + (k - 1) * 0.27, values, 0.27, label=label)
    ax.set_xticks(x, [s[0] for s in SITES], rotation=45, ha="right")
    ax.set_ylabel("normal force (N)")
    ax.set_title("Power grip of a 0.4 kg cylinder (Table 1 shares): predicted squeeze and solved normal forces")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
