"""What ``ActiveSession.observe(mask)`` costs on a 1280 x 720 camera, resolution by resolution.

Run: ``PYTHONPATH=. python benchmarks/timing/bench_observe.py [--resolutions 2.5,1,0.5,0.25]
[--objects Obj1,Obj3,Obj7] [--pushes 3] [--repeats 3] [--camera 1280x720] [--profile MM]``.

For each resolution (millimetres per pixel) and object (high friction, ``rng=1``), a
``simulators.SimulatedRobot`` sees the object with as much table round it as fits the
camera (at most 0.3 m), its image placed in the middle of a ``--camera`` image: the session
sees a camera frame of that size, with its defaults (``ActiveSession(mask,
pusher_radius=...)``), a mask only, no frames. The session asks for ``--pushes`` pushes;
the robot makes each, and the session's ``observe(mask)`` of the mask after it is timed
(wall, ``time.perf_counter``, and CPU, ``time.process_time``). Each of ``--repeats``
repeats plays the session anew (same seeds, same pushes, new masks: nothing cached).
Printed: per resolution, the median and 90th percentile of the wall time and the median
CPU time over all the objects' pushes and repeats; and the machine's load average.
``--profile MM`` runs cProfile over the timed calls at that resolution instead and prints
the ``--top`` most costly functions (``--sort``: cumulative, tottime).
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import time

import numpy as np

import comcore
import simulators

#: Table round the object's bounding disc tried, metres, widest first.
MARGINS = (0.3, 0.2, 0.15, 0.1, 0.07, 0.05, 0.04, 0.03, 0.02, 0.015, 0.01)


def fresh(mask: comcore.Mask) -> comcore.Mask:
    """A new Mask object of the same pixels (nothing cached)."""
    return comcore.Mask(mask.data.copy(), resolution=mask.resolution)


def robot_in_camera(name: str, resolution: float, camera: tuple[int, int]):
    """The robot with the widest margin whose image fits the camera ``(rows, cols)``."""
    sim = simulators.random_simulator(name, friction="high", rng=1)
    for margin in MARGINS:
        robot = simulators.SimulatedRobot(sim, resolution=resolution, camera_margin=margin, rng=1)
        if robot.image_shape[0] <= camera[0] and robot.image_shape[1] <= camera[1]:
            return sim, robot
    raise SystemExit(f"{name} does not fit a {camera[1]}x{camera[0]} camera at {resolution} m/px")


def placed(mask: comcore.Mask, camera: tuple[int, int]) -> tuple[comcore.Mask, np.ndarray]:
    """The mask in the middle of a camera image, and the offset (x, y) it was placed at."""
    row, col = (camera[0] - mask.shape[0]) // 2, (camera[1] - mask.shape[1]) // 2
    data = np.zeros(camera, bool)
    data[row : row + mask.shape[0], col : col + mask.shape[1]] = mask.data
    return comcore.Mask(data, resolution=mask.resolution), np.array([col, row], float)


def session_times(name, resolution, args, camera, profiler=None) -> list[tuple[float, float]]:
    """Wall and CPU seconds of each ``observe`` of one object's sessions, all repeats."""
    times = []
    for _ in range(args.repeats):
        sim, robot = robot_in_camera(name, resolution, camera)
        first, offset = placed(robot.camera_mask(), camera)
        session = comcore.ActiveSession(first, pusher_radius=sim.pusher_radius, rng=0)
        for _ in range(args.pushes):
            action = session.next_push()
            robot.execute(comcore.Action(*(np.asarray(action) - np.tile(offset, 2))))
            after, _ = placed(robot.camera_mask(), camera)
            if profiler is not None:
                profiler.enable()
            start, cpu = time.perf_counter(), time.process_time()
            session.observe(after)
            times.append((time.perf_counter() - start, time.process_time() - cpu))
            if profiler is not None:
                profiler.disable()
    return times


def main(argv=None) -> None:
    """Time ``observe`` at each resolution; print the table (or a profile)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolutions", default="2.5,1,0.5,0.25", help="mm per pixel")
    parser.add_argument("--objects", default="Obj1,Obj3,Obj7")
    parser.add_argument("--pushes", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--camera", default="1280x720", help="WxH")
    parser.add_argument("--profile", type=float, default=None, metavar="MM")
    parser.add_argument("--sort", default="cumulative", help="cProfile order (--profile)")
    parser.add_argument("--top", type=int, default=25, help="functions printed (--profile)")
    args = parser.parse_args(argv)
    width, height = (int(v) for v in args.camera.lower().split("x"))
    camera = (height, width)
    warm = comcore.Mask(np.pad(np.ones((20, 30), bool), 10), resolution=0.0025)
    comcore.ActiveSession(warm, pusher_radius=0.004).next_push()
    if args.profile is not None:
        profiler = cProfile.Profile()
        for name in args.objects.split(","):
            session_times(name, args.profile / 1000, args, camera, profiler)
        pstats.Stats(profiler).sort_stats(args.sort).print_stats(args.top)
        return
    print(f"load average before: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print(
        f"camera {width} x {height}, objects {args.objects}, {args.pushes} pushes, "
        f"{args.repeats} repeats"
    )
    print("| resolution (mm/px) | robot's image (px) | median (ms) | p90 (ms) | median CPU (ms) |")
    print("|---|---|---|---|---|")
    for mm in (float(v) for v in args.resolutions.split(",")):
        times = []
        for name in args.objects.split(","):
            times += session_times(name, mm / 1000, args, camera)
        shape = robot_in_camera(args.objects.split(",")[0], mm / 1000, camera)[1].image_shape
        wall, cpu = np.array(times).T * 1e3
        print(
            f"| {mm:g} | {shape[1]} x {shape[0]} | {np.median(wall):.0f} | "
            f"{np.percentile(wall, 90):.0f} | {np.median(cpu):.0f} |"
        )
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
