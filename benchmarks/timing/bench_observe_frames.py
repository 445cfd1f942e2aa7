"""What the frames of a push cost ``ActiveSession.observe``: with and without them.

Run: ``PYTHONPATH=. python benchmarks/timing/bench_observe_frames.py [--objects Obj1,Obj3,...]
[--frames 30] [--resolution 0.001] [--margin 0.3] [--camera 1280x720] [--push 1]
[--repeats 3]``.

For each object (high friction, ``rng=1``), a ``simulators.SimulatedRobot`` at
``--resolution`` metres per pixel with ``--margin`` metres of table round the object
(0.3 m at 1 mm/px: a camera image of about 700 x 700 pixels) makes the session's first
push with the camera's frames at the rate that gives about ``--frames`` of them. The
same push is observed by fresh sessions with the end mask alone and with the frames
too (``observe(mask, frames=push.path)``: each frame's mask registered, the path
scored by the limit-surface model); ``observe`` is timed (wall, ``time.perf_counter``)
``--repeats`` times each, each on fresh copies of the masks (a mask's fields are cached
per Mask object). ``--camera WxH`` places every image (and the pusher's positions) on a
camera image of that size, the robot's image in its middle (``--margin`` must then leave
the robot's image no larger): the session sees a 1280 x 720 camera, as the issue's target
names it. ``--push n`` times the session's n-th push (the pushes before it played and
observed the same way, with or without frames): the first pays once for what a session
keeps for its mask (the pressure table of the motion model), later ones see a narrower
posterior. Printed: per object the frames given and read, the medians, and the
median over all. The machine's load shows in the wall times.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import comcore
import simulators


def fresh(mask: comcore.Mask) -> comcore.Mask:
    """A new Mask object of the same pixels (nothing cached)."""
    return comcore.Mask(mask.data.copy(), resolution=mask.resolution)


class Canvas:
    """The robot's camera image placed in the middle of a larger one (``shape`` rows, cols)."""

    def __init__(self, inner: tuple[int, int], shape: tuple[int, int] | None):
        self.shape = inner if shape is None else shape
        if self.shape[0] < inner[0] or self.shape[1] < inner[1]:
            raise SystemExit(
                f"--camera {self.shape[1]}x{self.shape[0]} is smaller than the robot's image "
                f"{inner[1]}x{inner[0]}: use a smaller --margin"
            )
        self.row = (self.shape[0] - inner[0]) // 2
        self.col = (self.shape[1] - inner[1]) // 2

    def mask(self, mask: comcore.Mask) -> comcore.Mask:
        data = np.zeros(self.shape, bool)
        h, w = mask.shape
        data[self.row : self.row + h, self.col : self.col + w] = mask.data
        return comcore.Mask(data, resolution=mask.resolution)

    def point(self, xy, sign: float = 1.0) -> np.ndarray:
        """A pixel (x, y) of the robot's image on the canvas (``sign`` -1: back)."""
        return np.asarray(xy, float) + sign * np.array([self.col, self.row], float)

    def frames(self, frames) -> list:
        return [comcore.PushFrame(self.point(f.pusher), self.mask(f.view)) for f in frames]


def time_observe(name, args, canvas_shape, with_frames: bool) -> tuple[list, list]:
    """Wall times (s) of the ``--push``-th ``observe`` on fresh sessions, and the frames read.

    Each repeat plays a new session (and robot, same seeds) from the start: the pushes
    before the timed one are observed as it is (with its frames or without), so the
    session's caches (the first mask's pressure table, ...) are those of a session at
    that push. The timed call gets fresh copies of the masks.
    """
    times, kept = [], []
    for _ in range(args.repeats):
        sim = simulators.random_simulator(name, friction="high", rng=1)
        robot = simulators.SimulatedRobot(
            sim, resolution=args.resolution, camera_margin=args.margin, rng=1
        )
        inner = robot.camera_mask()
        canvas = Canvas(inner.shape, canvas_shape)
        session = comcore.ActiveSession(canvas.mask(inner), pusher_radius=sim.pusher_radius, rng=0)
        for n in range(1, args.push + 1):
            action = session.next_push()
            seconds = action.length * robot.resolution / robot.speed
            ends = np.concatenate([canvas.point(action[:2], -1), canvas.point(action[2:], -1)])
            push = robot.execute(comcore.Action(*ends), frame_rate=args.frames / seconds)
            after = canvas.mask(robot.camera_mask())
            frames = canvas.frames(push.path) if with_frames else None
            if n < args.push:
                session.observe(after, frames=frames)
                continue
            if frames is not None:
                frames = [comcore.PushFrame(f.pusher, fresh(f.view)) for f in frames]
            end = fresh(after)
            start = time.perf_counter()
            session.observe(end, frames=frames)
            times.append(time.perf_counter() - start)
            kept.append((len(push.path), len(session.estimate().pushes[-1].path)))
    return times, kept


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", default="Obj1,Obj3,Obj7,Obj11,Obj19")
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--resolution", type=float, default=0.001)
    parser.add_argument("--margin", type=float, default=0.3)
    parser.add_argument("--camera", default=None, help="WxH, e.g. 1280x720 (default: the robot's)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--push", type=int, default=1, help="time the session's n-th push")
    args = parser.parse_args(argv)
    camera = None
    if args.camera is not None:
        width, height = (int(v) for v in args.camera.lower().split("x"))
        camera = (height, width)
    plain_all, framed_all = [], []
    print(f"push {args.push} of a session, {args.repeats} repeats")
    print("| object | image | frames given / read | observe, end mask (ms) | with frames (ms) |")
    print("|---|---|---|---|---|")
    for name in args.objects.split(","):
        plain, _ = time_observe(name, args, camera, False)
        framed, kept = time_observe(name, args, camera, True)
        plain_all += plain
        framed_all += framed
        shape = camera or simulators.SimulatedRobot(
            simulators.random_simulator(name, friction="high", rng=1),
            resolution=args.resolution, camera_margin=args.margin, rng=1,
        ).camera_mask().shape  # fmt: skip
        print(
            f"| {name} | {shape[1]} x {shape[0]} | {kept[0][0]} / {kept[0][1]} | "
            f"{1e3 * np.median(plain):.0f} | {1e3 * np.median(framed):.0f} |"
        )
    print(
        f"| median | | | {1e3 * np.median(plain_all):.0f} | {1e3 * np.median(framed_all):.0f} |"
    )


if __name__ == "__main__":
    main()
