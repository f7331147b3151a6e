#!/usr/bin/env python3
"""A robot hand in MuJoCo closes on an object, and grip says what each finger feels.

Loads a MuJoCo Menagerie hand scene (the Shadow Hand or the Allegro Hand, chosen by the
model's folder name: shadow_hand or wonik_allegro; left or right by its file name), whose
body "object" (a small ellipsoid) falls onto the palm; or, with --model grip, grip's own hand
written by grip.hand_mjcf(), palm up and cupped, a 100 g ball dropped into it. After 0.5 s the fingers' flexion
actuators move their targets linearly to the upper ends of their ctrlrange over 1 s, and the
hand holds. Every step, grip.mujoco.Adapter turns the hand's contacts with the object into a
grip grasp (update) and solves it (solve, grip.solve_constrained): the forces that balance the
object's weight and inertia, nearest the squeezes its penetrations ask for, inside the
friction cones. Plots each digit's felt force magnitude over time (|sum of -f| over the digit's
grip bodies, N; the palm's bodies together) to an SVG and prints a small table.

Needs MuJoCo's Python package (pip install mujoco) and matplotlib. The models are not part of
grip: take them from MuJoCo Menagerie (github.com/google-deepmind/mujoco_menagerie).

    python3 examples/python/mujoco_hand.py --model SCENE.xml [--duration 2.5] [output.svg]
    python3 examples/python/mujoco_hand.py --model mujoco_menagerie/wonik_allegro/scene_right.xml
    python3 examples/python/mujoco_hand.py --model grip
"""

import argparse
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import grip  # noqa: E402
import grip.mujoco as gm  # noqa: E402

try:
    import mujoco
except ImportError:
    sys.exit("this example needs MuJoCo's Python package: pip install mujoco")

DIGITS = [("thumb", [0, 1, 14]), ("index", [2, 3, 4]), ("long", [5, 6, 7]), ("ring", [8, 9, 10]),
          ("little", [11, 12, 13]), ("palm", [15, 16, 17, 18])]
CLOSE_START, CLOSE_TIME = 0.5, 1.0  # s

# grip's own hand, fixed in the world palm up (the hand frame turned half a turn about its x
# axis, since the palm faces the hand frame's -z) and tipped 0.2 rad fingers down, so that the
# ball rolls towards the fingers; the hand starts cupped (GRIP_CUP of its closed posture) and a
# 7 cm, 100 g ball is dropped into it over the fingers' bases. The closed posture: the thumb's
# CMC at 0.8 rad in both axes and its MCP and IP at 0.5; each finger's MCP, PIP and DIP at 0.9,
# 1.0 and 0.6 rad, abduction 0 (each within its joint's range).
_tip = 0.2
GRIP_WRIST = np.array([[np.cos(_tip), 0, np.sin(_tip), 0], [0, 1, 0, 0], [-np.sin(_tip), 0, np.cos(_tip), 0],
                       [0, 0, 0, 1]]) @ np.diag([1.0, -1.0, -1.0, 1.0])
GRIP_OBJECT = ('<body name="object" pos="0.075 -0.005 0.045"><freejoint/>'
               '<geom type="sphere" size="0.035" mass="0.1" condim="3" friction="1 0.005 0.0001"/></body>')
GRIP_CLOSED = np.array([0.8, 0.8, 0.5, 0.5] + [0.0, 0.9, 1.0, 0.6] * 4)
GRIP_CUP = 0.4


def grip_scene():
    """(model, body map, the actuators that close the hand, their targets, the share of the
    targets the hand starts at) for grip's hand; its 20 joints come first in qpos."""
    xml = grip.hand_mjcf(wrist=GRIP_WRIST, mocap=False, servo_gain=5.0, worldbody=GRIP_OBJECT)
    m = mujoco.MjModel.from_xml_string(xml)
    upper = np.minimum(m.actuator_ctrlrange[:, 1], GRIP_CLOSED)
    return m, gm.GRIP_HAND, list(grip.hand_joint_names()), upper, GRIP_CUP


def hand_of(path):
    """(body map, names of the actuators that close the hand) for a Menagerie scene file."""
    folder, left = path.resolve().parent.name, "left" in path.name
    if folder == "shadow_hand":
        side = "lh" if left else "rh"
        fingers = [f"{side}_A_{f}J{j}" for f in ("FF", "MF", "RF", "LF") for j in (3, 0)]
        thumb = [f"{side}_A_THJ{j}" for j in (5, 4, 1)]
        return (gm.SHADOW_LEFT if left else gm.SHADOW_RIGHT), fingers + thumb
    if folder == "wonik_allegro":
        fingers = [f"{f}a{j}" for f in ("ff", "mf", "rf") for j in (1, 2, 3)]
        return (gm.ALLEGRO_LEFT if left else gm.ALLEGRO_RIGHT), fingers + [f"tha{j}" for j in range(4)]
    sys.exit(f"unknown hand folder {folder!r}: expected shadow_hand or wonik_allegro")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", nargs="?", default="mujoco_hand.svg", help="the SVG to write")
    parser.add_argument("--model", required=True,
                        help="a Menagerie hand scene (shadow_hand or wonik_allegro) with a free body 'object', "
                             "or 'grip' for grip's own hand (grip.hand_mjcf)")
    parser.add_argument("--duration", type=float, default=2.5, help="simulated time (s)")
    args = parser.parse_args()
    if args.model == "grip":
        m, bodies, closing, upper, cupped = grip_scene()
        name = "grip's hand (grip.hand_mjcf)"
    else:
        model = Path(args.model)
        if not model.is_file():
            sys.exit(f"{model} not found: give a MuJoCo Menagerie hand scene with --model, or --model grip")
        bodies, closing = hand_of(model)
        m = mujoco.MjModel.from_xml_path(str(model))
        upper, cupped = None, 0.0
        name = f"{model.parent.name}/{model.name}"
    d = mujoco.MjData(m)
    if cupped > 0:  # grip's hand: its joints first in qpos, at the starting share of the targets
        d.qpos[:len(upper)] = cupped * upper
        mujoco.mj_forward(m, d)
    adapter = gm.Adapter(m, "object", bodies)
    actuators = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, n) for n in closing]
    if upper is None:
        upper = m.actuator_ctrlrange[actuators, 1]
    weight = m.body_mass[adapter.object] * np.linalg.norm(m.opt.gravity)

    steps = int(round(args.duration / m.opt.timestep))
    t = np.arange(1, steps + 1) * m.opt.timestep
    felt = np.zeros((steps, len(DIGITS)))
    status = []
    contacts = np.zeros(steps, dtype=int)
    start = time.perf_counter()
    for step in range(steps):
        ramp = np.clip((step * m.opt.timestep - CLOSE_START) / CLOSE_TIME, 0.0, 1.0)
        d.ctrl[actuators] = (cupped + (1 - cupped) * ramp) * upper
        mujoco.mj_step(m, d)
        u = adapter.update(d)
        result = adapter.solve(grip.solve_constrained)
        felt[step] = [np.linalg.norm(result.felt[ks].sum(axis=0)) for _, ks in DIGITS]
        status.append(result.status)
        contacts[step] = len(u.contacts)
    elapsed = time.perf_counter() - start

    print(f"{name}: {steps} steps of {m.opt.timestep * 1e3:g} ms ({args.duration:g} s simulated) with "
          f"update + solve each in {elapsed:.2f} s ({elapsed / steps * 1e6:.0f} us per step)")
    print(f"object {m.body_mass[adapter.object] * 1e3:.1f} g (weight {weight:.3f} N); felt force per digit (N):")
    print(f"{'t (s)':>6} {'status':>10} {'contacts':>8} " + " ".join(f"{n:>7}" for n, _ in DIGITS))
    for when in np.arange(0.5, args.duration + 1e-9, 0.5):
        i = min(steps - 1, int(round(when / m.opt.timestep)) - 1)
        print(f"{t[i]:6.2f} {status[i].name:>10} {contacts[i]:8d} " + " ".join(f"{x:7.3f}" for x in felt[i]))
    counts = {s.name: status.count(s) for s in set(status)}
    print("statuses over the run: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))

    fig, ax = plt.subplots(figsize=(8, 4.2))
    ax.axvspan(CLOSE_START, CLOSE_START + CLOSE_TIME, color="0.92", label="closing")
    for (label, _), series in zip(DIGITS, felt.T):
        ax.plot(t, series, lw=1.3, label=label)
    ax.axhline(weight, color="k", ls="--", lw=0.8, label="object's weight")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("felt force |sum of -f| (N)")
    ax.set_title(f"{name}: what each digit feels (grip.mujoco, solve_constrained)")
    ax.set_xlim(0, args.duration)
    ax.set_ylim(bottom=0)
    ax.legend(loc="upper left", fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
