"""The adapter of docs/how-to/your-robot.md with MuJoCo as the cell (docs/results/simulators.md).

MuJoCo plays a real cell: a camera tilted ``--tilt`` degrees off vertical renders
``--camera`` frames of a wood-grain table, the arm (drawn on the pusher) waits in
view between pushes at the work area's far corner, and each object is pushed from
wherever the last push left it (never reset). The cell is driven only through
``benchmarks/mujoco/cell_adapter.py``, the how-to's adapter (the same file):
calibrated once from four table points whose pixels are where the camera sees
them plus ``--click-noise`` pixels of noise (a user's clicks), the board at the
height of the objects' top face (the how-to's answer to parallax), one empty-table
frame, a box around the object at the start; pushes go out in table metres
(:meth:`simulators.MujocoRobot.execute_table`). The camera hands the adapter its
green channel by default (``--channel``: where the yellow objects differ most
from the wood; ``rgb`` gives the colour frame, comcore takes its luma). Default
session settings, the robot's pusher radius, the session's stream ``[seed, k, 7]``.

Reported per run: the CoM's error (cm, table metres against MuJoCo's CoM at the
first frame), pushes, whether the 90 % region holds the CoM, failed pushes (frames
the segmentation refused, pushes the arm could not make); then the means and the
refusals' reasons. Objects: ``accepted_random_simulator(object, friction, rng=[seed,
k])``, ``k`` the object's index in ``simulators.BENCHMARK_OBJECTS``.

    PYTHONPATH=. python benchmarks/mujoco/mujoco_cell.py --seed 0 --workers 2
    PYTHONPATH=. python benchmarks/mujoco/mujoco_cell.py --objects Obj2 --friction low
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("EGL_PLATFORM", "surfaceless")

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

import simulators
from benchmarks.mujoco.cell_adapter import CellAdapter, find_com

#: Ten benchmark objects, the first five with low friction, the last five with high.
OBJECTS = ("Obj1", "Obj2", "Obj3", "Obj4", "Obj5", "Obj6", "Obj7", "Obj8", "Obj9", "Obj10")
#: Where the arm waits between pushes: this far (m) in from the work area's far corner.
REST_INSET_M = 0.03
#: The camera's channels (``--channel``): the colour frame (comcore takes its luma) or one.
CHANNELS = {"rgb": None, "red": 0, "green": 1, "blue": 2}
#: Margin (m) of the user's first box around the object.
BOX_MARGIN_M = 0.02


class CountingAdapter(CellAdapter):
    """The adapter, counting the frames the segmentation refuses (and why, first words)."""

    refusals: list

    def mask(self, frame, reach=60):
        try:
            return super().mask(frame, reach)
        except ValueError as e:
            self.refusals.append(str(e).split(":")[0])
            raise


def board(robot, cell, click_noise, rng, height="top"):
    """Four table points (the work area's corners, 4 cm in) and their noisy pixels.

    The board lies at the objects' top face (``height="top"``) or on the table.
    """
    x0, y0, x1, y1 = robot.camera_setup.bounds_m
    table = np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)]) + 0.04 * np.array(
        [(1, 1), (-1, 1), (-1, -1), (1, -1)]
    )
    to_image = cell.top_to_image if height == "top" else cell.table_to_image
    seen = np.column_stack([table, np.ones(4)]) @ to_image.T
    clicks = seen[:, :2] / seen[:, 2:] + rng.normal(0.0, click_noise, (4, 2))
    return clicks, table


def run(name, friction, seed, k, args):
    """One session on one object through the adapter; a dict of what the table reports."""
    sim = simulators.accepted_random_simulator(name, friction, rng=[seed, k])
    camera = simulators.CameraSettings(
        tuple(args.camera), tilt=math.radians(args.tilt), table="wood", arm=True
    )
    robot = simulators.MujocoRobot(sim, camera=camera)
    t0 = time.perf_counter()
    cell = robot.cell_frame()
    work_area = robot.camera_setup.bounds_m
    clicks, table = board(
        robot, cell, args.click_noise, np.random.default_rng([seed, k, 1]), args.board
    )
    outline = cell.outline_m
    box = (*(outline.min(axis=0) - BOX_MARGIN_M), *(outline.max(axis=0) + BOX_MARGIN_M))
    channel = CHANNELS[args.channel]
    empty = robot.empty_table_frame()
    empty = empty if channel is None else empty[..., channel]
    adapter = CountingAdapter(clicks, table, [empty], work_area, box)
    adapter.refusals, arm_failures = [], []
    rest = (work_area[2] - REST_INSET_M, work_area[3] - REST_INSET_M)

    def camera_frame():
        frame = robot.camera_frame()
        return frame if channel is None else frame[..., channel]

    def arm(push_m):
        try:
            robot.execute_table(push_m, rest=rest)
        except ValueError as e:  # starts inside the object as it is now, or too long
            arm_failures.append(str(e))
            return False
        return True

    est = find_com(adapter, camera_frame, arm, sim.pusher_radius, rng=[seed, k, 7])
    truth_px = adapter.view.pixels_from_table(cell.com_m)
    com_m = adapter.view.table_from_pixels(est.com)
    robot.close()
    return {
        "object": name,
        "friction": friction,
        "error_cm": float(np.hypot(*(com_m - cell.com_m)) * 100),
        "pushes": robot.pushes,
        "covered": bool(est.region_holds(tuple(truth_px))),
        "status": est.status,
        "failed": sum(p.outcome == "failed" for p in est.pushes),
        "refused": adapter.refusals,
        "arm_failures": len(arm_failures),
        "seconds": time.perf_counter() - t0,
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", nargs="+", default=list(OBJECTS))
    parser.add_argument("--friction", choices=("low", "high"), help="one class for every "
                        "object (default: low for the first half of the objects, high for the "
                        "rest)")  # fmt: skip
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--tilt", type=float, default=28.0, help="degrees off vertical")
    parser.add_argument("--camera", type=int, nargs=2, default=(640, 480), metavar=("W", "H"))
    parser.add_argument("--channel", choices=CHANNELS, default="green")
    parser.add_argument("--board", choices=("top", "table"), default="top", help="where the "
                        "calibration board lies: at the objects' top face or on the table "
                        "(parallax uncorrected)")  # fmt: skip
    parser.add_argument("--click-noise", type=float, default=0.5, help="pixels (std)")
    args = parser.parse_args(argv)
    half = (len(args.objects) + 1) // 2
    jobs = [
        (name, args.friction or ("low" if i < half else "high"),
         args.seed, simulators.BENCHMARK_OBJECTS.index(name), args)
        for i, name in enumerate(args.objects)
    ]  # fmt: skip
    t0 = time.time()
    with ProcessPoolExecutor(args.workers) as pool:
        rows = list(pool.map(run, *zip(*jobs)))
    print("| object | friction | error (cm) | pushes | region holds the CoM | failed: frame "
          "refused, arm | status |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['object']} | {r['friction']} | {r['error_cm']:.3f} | {r['pushes']} | "
              f"{r['covered']} | {r['failed']}: {len(r['refused'])}, {r['arm_failures']} | "
              f"{r['status']} |")  # fmt: skip
    err = np.array([r["error_cm"] for r in rows])
    print(f"| **mean** ({len(rows)} runs) | | **{err.mean():.3f}** | "
          f"{np.mean([r['pushes'] for r in rows]):.1f} | "
          f"**{np.mean([r['covered'] for r in rows]):.0%}** | "
          f"{sum(r['failed'] for r in rows)} | |")
    reasons = [why for r in rows for why in r["refused"]]
    for why in sorted(set(reasons)):
        print(f"frames refused, {why}: {reasons.count(why)}")  # fmt: skip
    print(f"seed {args.seed}, tilt {args.tilt:g} deg, {args.camera[0]}x{args.camera[1]} camera, "
          f"{args.channel} channel, board at the {args.board}, "
          f"{time.time() - t0:.0f} s, load {os.getloadavg()[0]:.1f}")  # fmt: skip
    return rows


if __name__ == "__main__":
    main()
