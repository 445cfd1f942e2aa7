"""What the simulated robots' frames during a push cost: ``execute(action, frame_rate=...)``.

Run: ``python benchmarks/timing/bench_push_frames.py [--robots quasistatic,pymunk,mujoco]
[--pushes 3] [--repeats 5] [--rate 10] [--travel 0.03] [--camera 320x240] [--object Obj3]
[--seed 1] [--mask-noise 0] [--shadow-size 4096]``.

For each robot (``SimulatedRobot`` on the quasi-static and the pymunk engine, at its
default speed; ``MujocoRobot`` with a ``--camera`` camera, at ``MujocoSettings``'
speed) the object ``random_simulator(--object, "high", rng=--seed)`` is pushed
``--pushes`` times, each from its start pose, along a push of
``comcore.sample_pushes`` (``--travel`` metres after contact, the standoff before it),
without frames and at ``--rate`` Hz, in turn (``SimulatedRobot``: ``--repeats``
times each, its pushes take milliseconds; ``MujocoRobot``: once each). The wall times
(``time.perf_counter``) of the ``execute`` calls give the push's cost with and without
its frames; their difference over the frames taken is a frame's cost. The medians over
the pushes are printed in a table, with the frames per push. For the MuJoCo robot one more push
measures what the pusher in the picture does to the frames' masks: each frame is
rendered again with the pusher moved out of view, and the pixels where the two masks
differ are counted (mean and largest per frame). ``--shadow-size`` sets the MuJoCo
light's shadow map (``CameraSettings.shadow_size``); other than the default, the masks
after each push are compared with the default's (pixels that differ). MuJoCo renders offscreen
(``MUJOCO_GL=egl``); without a GPU it is Mesa's software renderer, which the frames'
cost then mostly is. Robots whose extra (pymunk, mujoco) is missing are skipped, saying so.
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # before mujoco is first imported
os.environ.setdefault("EGL_PLATFORM", "surfaceless")

import argparse
import importlib.util
import time

import numpy as np

import comcore
import simulators

ROBOTS = ("quasistatic", "pymunk", "mujoco")
NEEDS = {"pymunk": "pymunk", "mujoco": "mujoco"}
#: simulators.CameraSettings' shadow map (texels): the scene the MuJoCo benchmarks render.
DEFAULT_SHADOW = simulators.CameraSettings().shadow_size


def shadow_effect(robot, sim, camera, actions) -> list[int]:
    """Pixels where each push's end mask differs from the default shadow map's (MuJoCo)."""
    reference = make_robot("mujoco", sim, camera, 0.0)
    diffs = []
    try:
        for action in actions:
            masks = []
            for r in (robot, reference):
                r.place(None)
                r.execute(action)
                masks.append(r.camera_mask().data)
            diffs.append(int(np.count_nonzero(masks[0] ^ masks[1])))
    finally:
        reference.close()
    return diffs


def make_robot(kind, sim, camera, mask_noise, shadow_size=DEFAULT_SHADOW):
    """The robot of a row of the table."""
    if kind == "mujoco":
        settings = simulators.CameraSettings(camera, shadow_size=shadow_size)
        return simulators.MujocoRobot(sim, camera=settings)
    return simulators.SimulatedRobot(sim, engine=kind, mask_noise=mask_noise, rng=0)


def timed_push(robot, action, rate):
    """Wall seconds of one push from the start pose, and the push."""
    robot.place(None)
    t0 = time.perf_counter()
    push = robot.execute(action, frame_rate=rate)
    return time.perf_counter() - t0, push


def pusher_effect(robot, action, rate):
    """Per frame of one MuJoCo push: pixels where the pusher in the picture changes the mask."""
    render, bare = robot.camera_frame, []

    def both():  # the frame, and the same instant with the pusher out of view
        image = render()
        q = robot.data.qpos[7:9].copy()
        robot.data.qpos[7:9] = 0.0  # the parked position (qpos is relative to PARK_XY)
        robot._mj.mj_kinematics(robot.model, robot.data)
        bare.append(render())
        robot.data.qpos[7:9] = q
        robot._mj.mj_kinematics(robot.model, robot.data)
        return image

    robot.camera_frame = both
    try:
        _, push = timed_push(robot, action, rate)
    finally:
        del robot.camera_frame
    to_image, shape = robot.homography_grid_to_image(), robot.simulator.image_shape
    diffs = []
    for frame, image in zip(push.path, bare):
        warped = simulators.warp_to_grid(image, to_image, shape)
        without = comcore.mask_from_image(warped, resolution=robot.resolution, object="bright")
        diffs.append(int((frame.view.data ^ without.data).sum()))
    return diffs


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", default=",".join(ROBOTS))
    parser.add_argument("--pushes", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=5, help="per push, SimulatedRobot")
    parser.add_argument("--rate", type=float, default=10.0, help="frames per second (Hz)")
    parser.add_argument("--travel", type=float, default=0.03, help="metres after contact")
    parser.add_argument("--camera", default="320x240", help="MuJoCo frame, WIDTHxHEIGHT")
    parser.add_argument("--object", default="Obj3")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--mask-noise", type=float, default=0.0)
    parser.add_argument(
        "--shadow-size", type=int, default=DEFAULT_SHADOW, help="MuJoCo's shadow map, texels"
    )
    args = parser.parse_args(argv)
    robots = [r.strip() for r in args.robots.split(",") if r.strip()]
    unknown = sorted(set(robots) - set(ROBOTS))
    assert not unknown, f"unknown robot(s) {unknown}: choose from {', '.join(ROBOTS)}"
    assert args.pushes >= 1 and args.repeats >= 1, "--pushes and --repeats must be >= 1"
    camera = tuple(int(v) for v in args.camera.lower().split("x"))
    sim = simulators.random_simulator(args.object, friction="high", rng=args.seed)
    print(
        f"{args.object} (seed {args.seed}), {args.pushes} pushes of {args.travel * 100:g} cm "
        f"after contact, frames at {args.rate:g} Hz, mask_noise {args.mask_noise:g}; "
        "wall times, medians over the pushes"
    )
    print("| robot | camera | speed (m/s) | frames per push | ms per push, no frames "
          "| ms per push with frames | ms per frame |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- |")
    notes = []
    for kind in robots:
        if kind in NEEDS and importlib.util.find_spec(NEEDS[kind]) is None:
            notes.append(f"{kind}: skipped, {NEEDS[kind]} is not installed")
            continue
        robot = make_robot(kind, sim, camera, args.mask_noise, args.shadow_size)
        first = robot.camera_mask()
        actions = comcore.sample_pushes(first, args.pushes, travel=args.travel, rng=args.seed)
        if kind != "mujoco":  # untimed: builds the engine (camera_mask built the renderer)
            timed_push(robot, actions[0], None)
        plain, framed, counts, per_frame = [], [], [], []
        for action in actions:
            for _ in range(1 if kind == "mujoco" else args.repeats):
                t_plain, _ = timed_push(robot, action, None)
                t_framed, push = timed_push(robot, action, args.rate)
                plain.append(t_plain)
                framed.append(t_framed)
                counts.append(len(push.path))
                per_frame.append((t_framed - t_plain) / max(len(push.path), 1))
        h, w = robot.simulator.image_shape
        if kind == "mujoco":
            cw, ch = robot.camera.image_size
            view, speed = f"{cw} x {ch} rendered, {w} x {h} grid", robot.settings.speed
        else:
            view, speed = f"{w} x {h} mask", robot.speed
        print(
            f"| {kind} | {view} | {speed:g} | {np.median(counts):g} | "
            f"{1e3 * np.median(plain):.1f} | {1e3 * np.median(framed):.1f} | "
            f"{1e3 * np.median(per_frame):.2f} |"
        )
        if kind == "mujoco":
            diffs = pusher_effect(robot, actions[0], args.rate)
            notes.append(
                f"mujoco: the pusher in the picture changes a frame's mask by "
                f"{np.mean(diffs):.2f} px on average, {max(diffs)} px at most ({len(diffs)} "
                f"frames; the object's mask holds {first.area_px} px)"
            )
            if args.shadow_size != DEFAULT_SHADOW:
                diffs = shadow_effect(robot, sim, camera, actions)
                notes.append(
                    f"mujoco: with a {args.shadow_size} shadow map the masks after the pushes "
                    f"differ from the {DEFAULT_SHADOW} map's by {diffs} px"
                )
            robot.close()
    for note in notes:
        print(note)


if __name__ == "__main__":
    main()
