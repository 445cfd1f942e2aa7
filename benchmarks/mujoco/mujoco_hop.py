"""Does the pushed object hop on its feet? (docs/results/simulators.md, "The settings, and why").

One push of a uniform 10 x 6 cm plate (``mu_contact`` 0.5), down onto its top edge 3 cm right
of the CoM, 3 cm of travel, under several ``MujocoSettings``: the share of time steps with
fewer than 10 feet touching the table, the range of its centre of mass's height
(micrometres), and its turn against the exact engine's.

    PYTHONPATH=. python benchmarks/mujoco/mujoco_hop.py
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("EGL_PLATFORM", "surfaceless")

import math

import mujoco
import numpy as np

import simulators
from simulators import MujocoSettings
from simulators.mujoco._scene import PARK_XY

CASES = (
    ("all contacts stiff (2 ms), 5 cm/s, dt 0.5 ms",
     dict(support_timeconst=0.002, speed=0.05, timestep=0.0005)),
    ("support 20 ms, 5 cm/s", dict(speed=0.05)),
    ("support 20 ms, 1 cm/s (the default)", {}),
    ("support 20 ms, 0.5 cm/s", dict(speed=0.005)),
)  # fmt: skip


def hop(settings):
    sim = simulators.PushSimulator.from_polygon(
        [(0, 0), (0.1, 0), (0.1, 0.06), (0, 0.06)], mu_contact=0.5
    )
    robot = simulators.MujocoRobot(sim, settings=settings)
    model, data, grid = robot.model, robot.data, robot.simulator
    action = simulators.action_from_world(grid, (0.08, 0.07), (0.0, -1.0))
    start, end = grid.to_world(np.asarray(action).reshape(2, 2))
    d = (end - start) / np.linalg.norm(end - start)
    c0, length = start - sim.pusher_radius * d, float(np.linalg.norm(end - start))
    data.qpos[7:9] = data.ctrl[:] = c0 - PARK_XY
    mujoco.mj_forward(model, data)
    step = settings.speed * model.opt.timestep
    contacts, heights = [], []
    for k in range(1, math.ceil(length / step) + 1):
        data.ctrl[:] = c0 - PARK_XY + min(k * step, length) * d
        mujoco.mj_step(model, data)
        contacts.append(data.ncon)
        heights.append(data.xipos[model.body("object").id][2])
    exact = grid.push(action).motion.theta
    turn = robot.world_pose[2] - robot._initial[2]
    return np.mean(np.array(contacts) < 10), 1e6 * np.ptp(heights), turn, exact


def main():
    for label, changes in CASES:
        airborne, height, turn, exact = hop(MujocoSettings(**changes))
        print(
            f"{label:48s} steps with < 10 feet down {airborne:6.1%}, height range "
            f"{height:5.1f} um, turn {math.degrees(turn):6.2f} deg "
            f"(exact {math.degrees(exact):.2f})"
        )


if __name__ == "__main__":
    main()
