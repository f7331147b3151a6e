#!/usr/bin/python3
"""The haptic loop from Python: a scripted 1 kHz glove session (the one of the C++ example
06_haptic_loop) drives grip.HapticLoop. A 0.4 kg cylinder lies on a table; the hand closes on
it (Table 1's power grip), lifts it, holds it, shakes it, swings it into the table's edge and
lets go. Plots what each finger feels over time (the magnitude of the force on its phalanges,
summed) with the phases shaded, and prints when the object was held. Writes
haptic_forces.png.

    python3 examples/python/haptic_forces.py [output.png]
"""

import sys

import numpy as np

import grip

RATE, DURATION, MASS, RADIUS, HALF_LENGTH = 1000.0, 6.5, 0.4, 0.035, 0.06
PHASES = [("close", 0.0, 0.7), ("lift", 0.7, 1.5), ("hold", 1.5, 2.2), ("shake", 2.2, 3.4), ("to edge", 3.4, 4.3),
          ("impact", 4.3, 4.9), ("back", 4.9, 5.6), ("let go", 5.6, 6.5)]
FINGERS = [("thumb", [0, 1]), ("index", [2, 3, 4]), ("long", [5, 6, 7]), ("ring", [8, 9, 10]), ("little", [11, 12, 13])]


def ramp(t, a, b):
    """Smooth 0 -> 1 over [a, b] (minimum jerk)."""
    u = np.clip((t - a) / (b - a), 0.0, 1.0)
    return u ** 3 * (10 - 15 * u + 6 * u ** 2)


def object_path(t):
    p = np.array([-0.15, 0.0, RADIUS])
    p[2] += 0.15 * ramp(t, 0.7, 1.5)
    shake = ramp(t, 2.2, 2.45) * (1 - ramp(t, 3.15, 3.4))
    p[2] += 0.015 * shake * np.sin(2 * np.pi * 4 * (t - 2.2))
    p[0] += 0.25 * ramp(t, 3.4, 3.85) - 0.25 * ramp(t, 5.15, 5.6)
    p[2] += -0.205 * ramp(t, 3.85, 4.3) + 0.205 * ramp(t, 4.9, 5.15)
    p[0] += -0.068 * ramp(t, 4.3, 4.55) + 0.068 * ramp(t, 4.65, 4.9)
    return p


def closure(t):
    return ramp(t, 0.15, 0.6) * (1 - ramp(t, 5.75, 6.0))


def session(**options):
    """Runs the session; returns the times and the HapticFrames. options: more keywords of
    grip.HapticLoop (max_iterations, bound_by_device=False: the forces unbounded, the device
    clipping what it cannot render)."""
    hand = grip.HandDimensions.standard()
    base = hand.base
    base[0, 1] = -0.005  # the thumb opposes the long finger (power-grip posture)
    hand.base = base
    cmc = hand.thumb_cmc
    cmc[1] = -0.005
    hand.thumb_cmc = cmc
    stiffness = np.full(14, 1.5e4)
    limit = np.full(14, 12.0)
    limit[:2] = 25.0
    table = grip.contribution_table(grip.GraspType.CylindricalPower)
    share = table.share
    share[0] = (0.5, 0.0, 0.7)  # a firmer thumb than the table's 0.15 and 0.25, as example 06
    rotation = np.column_stack([[0, 0, 1.0], [1.0, 0, 0], [0, 1.0, 0]])  # body x -> world z, y -> x, z (axis) -> y
    loop = grip.HapticLoop(radius=RADIUS, half_length=HALF_LENGTH, mass=MASS, position=object_path(0.0), rotation=rotation,
                           boxes=[((-0.8, -0.5, -0.75), (0.0, 0.5, 0.0))], hand=hand, stiffness=stiffness,
                           device_limit=limit, contribution=grip.ContributionTable(share, palm=table.palm),
                           obstacle_stiffness=4000.0, obstacle_damping=20.0, **options)
    offset = np.array([0.374 * hand.hand_length + 0.03, 0.0, -(RADIUS + 0.045 * hand.hand_length - 0.002)])

    def wrist(t):
        w = np.eye(4)
        w[:3, 3] = object_path(t) - offset
        return w

    closed, touching, status = loop.close_hand(wrist(0.0), 0.002)
    assert status == grip.Status.Ok and touching > 0
    h = 1e-4
    times = np.arange(0.0, DURATION, 1.0 / RATE)
    frames = []
    for t in times:
        p0, p1, p2 = (wrist(s)[:3, 3] for s in (t - h, t, t + h))
        frames.append(loop.step(wrist(t), closure(t) * closed, linear_velocity=(p2 - p0) / (2 * h),
                                linear_acceleration=(p2 - 2 * p1 + p0) / h ** 2))
    return times, frames


def main(out="haptic_forces.png"):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    times, frames = session()
    force = np.array([f.force for f in frames])  # (frames, 14, 3)
    held = np.array([f.held for f in frames])
    fig, ax = plt.subplots(figsize=(10, 4))
    for k, (name, start, end) in enumerate(PHASES):
        ax.axvspan(start, end, color="0.92" if k % 2 else "white", zorder=0)
        ax.text((start + end) / 2, 1.0, name, transform=ax.get_xaxis_transform(), ha="center", va="bottom", fontsize=8)
    for name, phalanges in FINGERS:
        ax.plot(times, np.linalg.norm(force[:, phalanges], axis=2).sum(axis=1), label=name, lw=1)
    ax.set(xlabel="time (s)", ylabel="force felt, summed over the finger's phalanges (N)", xlim=(0, DURATION))
    ax.legend(loc="upper right", ncol=5, fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}: held in {np.mean(held):.0%} of {len(frames)} frames, "
          f"{sum(f.status == grip.Status.Ok for f in frames)} frames Ok")


if __name__ == "__main__":
    main(*sys.argv[1:2])
