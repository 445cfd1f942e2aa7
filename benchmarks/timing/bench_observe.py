"""What ``ActiveSession.observe(mask)`` costs on a 1280 x 720 camera, resolution by resolution.

Run: ``PYTHONPATH=. python benchmarks/timing/bench_observe.py [--resolutions 2.5,1,0.5,0.25]
[--objects Obj1,Obj3,Obj7] [--pushes 3] [--repeats 3] [--camera 1280x720] [--profile MM]``.

For each resolution (millimetres per pixel) and object (high friction, ``rng=1``), a
``simulators.SimulatedRobot`` sees the object with 0.1 m of table round it, its image
placed in the middle of a ``--camera`` image (padded, or cut where larger): the session
sees a camera frame of that size, with its defaults (``ActiveSession(mask,
pusher_radius=...)``), a mask only, no frames. The session asks for ``--pushes`` pushes;
the robot makes each, and the session's ``observe(mask)`` of the mask after it is timed
(wall, ``time.perf_counter``, and CPU, ``time.process_time``). Each of ``--repeats``
repeats plays the session anew (same seeds, same pushes, new masks: nothing cached). A
session stops early when the object reaches the camera image's edge (at 0.25 mm per pixel
a 1280 x 720 camera sees 32 x 18 cm).
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

#: Table round the object's bounding disc in the robot's image, metres.
ROBOT_MARGIN = 0.1


def placed(mask: comcore.Mask, camera: tuple[int, int]) -> tuple[comcore.Mask, np.ndarray]:
    """The robot's image centred on the camera's (padded or cut), and where it went (x, y)."""
    (h, w), (ch, cw) = mask.shape, camera
    row, col = (ch - h) // 2, (cw - w) // 2
    data = np.zeros(camera, bool)
    data[max(row, 0) : row + h, max(col, 0) : col + w] = mask.data[
        max(-row, 0) : ch - row, max(-col, 0) : cw - col
    ]
    return comcore.Mask(data, resolution=mask.resolution), np.array([col, row], float)


def touches_border(mask: comcore.Mask) -> bool:
    """Whether the object reaches the camera image's edge (part of it out of view)."""
    d = mask.data
    return bool(d[0].any() or d[-1].any() or d[:, 0].any() or d[:, -1].any())


def session_times(name, resolution, args, camera, profiler=None) -> list[tuple[float, float]]:
    """Wall and CPU seconds of each ``observe`` of one object's sessions, all repeats."""
    times = []
    for _ in range(args.repeats):
        sim = simulators.random_simulator(name, friction="high", rng=1)
        robot = simulators.SimulatedRobot(
            sim, resolution=resolution, camera_margin=ROBOT_MARGIN, rng=1
        )
        first, offset = placed(robot.camera_mask(), camera)
        session = comcore.ActiveSession(first, pusher_radius=sim.pusher_radius, rng=0)
        for _ in range(args.pushes):
            action = session.next_push()
            robot.execute(comcore.Action(*(np.asarray(action) - np.tile(offset, 2))))
            after, _ = placed(robot.camera_mask(), camera)
            if touches_border(after):  # out of the camera's view: the session would refuse it
                break
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
    print("| resolution (mm/px) | observes timed | median (ms) | p90 (ms) | median CPU (ms) |")
    print("|---|---|---|---|---|")
    for mm in (float(v) for v in args.resolutions.split(",")):
        times = []
        for name in args.objects.split(","):
            times += session_times(name, mm / 1000, args, camera)
        wall, cpu = np.array(times).T * 1e3
        print(
            f"| {mm:g} | {len(wall)} | {np.median(wall):.0f} | "
            f"{np.percentile(wall, 90):.0f} | {np.median(cpu):.0f} |"
        )
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
