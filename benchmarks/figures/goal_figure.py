"""Draw docs/img/goal_run.png: a comcore.GoalSession pushing a benchmark object to a goal pose.

One run of the ``learn`` strategy of benchmarks/accuracy/goal_bench.py (the planner from no
estimate, learning from every push) on ``simulators.SimulatedRobot``: the object's outline
after every push (light to dark), the pushes as the session asked for them (camera pixels,
numbered), the goal's outline (dashed) and the CoM estimated at the end against the true
one. The title gives the status, the pushes and the final errors.

Run: ``PYTHONPATH=. python benchmarks/figures/goal_figure.py [--out docs/img/goal_run.png]``
(needs comcore[sim,plot]). The tests run it with a small goal into a temporary folder.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import comcore
import simulators
from comcore.camera._pose_tracking import moved_mask  # the first mask moved to the goal pose


def run(args):
    """The session's run: first mask, masks after each push, pushes, goal mask, robot, session."""
    sim = simulators.accepted_random_simulator(args.object, args.friction, rng=args.seed)
    robot = simulators.SimulatedRobot(sim, camera_margin=args.distance + 0.08, rng=args.seed)
    first = robot.camera_mask()
    angle = math.radians(args.direction)
    goal = comcore.Goal(
        displacement=(args.distance * math.cos(angle), args.distance * math.sin(angle)),
        orientation=math.radians(args.turn),
    )
    session = comcore.GoalSession(first, goal, pusher_radius=sim.pusher_radius, rng=0)
    masks, pushes = [first], []
    while not session.done:
        push = session.next_push()
        robot.execute(push)
        mask = robot.camera_mask()
        session.observe(mask)
        masks.append(mask)
        pushes.append(push)
    target = goal.target_px(first)
    goal_mask = moved_mask(first, comcore.Motion(goal.orientation, *target))
    return first, masks, pushes, goal_mask, robot, session


def draw(args) -> str:
    """Draw the figure to ``args.out``; returns the title."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    first, masks, pushes, goal_mask, robot, session = run(args)
    truth = robot.pose
    target = session.goal.target_px(first)
    pos_cm = 100 * math.hypot(truth.tx - target[0], truth.ty - target[1]) * first.resolution
    ang = math.degrees(abs(truth.theta - session.goal.orientation))
    title = (
        f"{args.object} ({args.friction} friction): {session.status} after {len(pushes)} "
        f"pushes, {pos_cm:.1f} cm and {ang:.1f} deg from the goal"
    )
    fig, ax = plt.subplots(figsize=(7, 6))
    shades = plt.cm.Blues(np.linspace(0.3, 1.0, len(masks)))
    for mask, shade in zip(masks, shades):
        ax.contour(mask.data.astype(float), levels=[0.5], colors=[shade], linewidths=1.2)
    ax.contour(goal_mask.data.astype(float), levels=[0.5], colors="tab:green",
               linestyles="dashed", linewidths=2)  # fmt: skip
    for k, push in enumerate(pushes, 1):
        ax.annotate("", xy=push.end, xytext=push.start,
                    arrowprops={"arrowstyle": "->", "color": "tab:red", "lw": 1.2})  # fmt: skip
        ax.text(*push.start, str(k), color="tab:red", fontsize=7)
    com = session.estimate().com
    now = comcore.apply_motion([com], truth.theta, (truth.tx, truth.ty), first.centroid)[0]
    ax.plot(*robot.com_in_camera, "k+", ms=10, label="true CoM (now)")
    ax.plot(*now, "rx", ms=8, label="estimated CoM (now)")
    ax.plot([], [], color="tab:green", ls="--", label="goal")
    ax.plot([], [], color=shades[-1], label="object after each push")
    rows, cols = np.nonzero(np.any([m.data for m in [*masks, goal_mask]], axis=0))
    ax.set_xlim(cols.min() - 15, cols.max() + 15)
    ax.set_ylim(rows.max() + 15, rows.min() - 15)  # rows down, as the camera
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)
    ax.legend(loc="best", fontsize=7)
    ax.set_xlabel("x (pixels)")
    ax.set_ylabel("y (pixels, down)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    plt.close(fig)
    return title


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--object", default="Obj8")
    parser.add_argument("--friction", default="low")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--distance", type=float, default=0.2, help="metres")
    parser.add_argument("--direction", type=float, default=30.0, help="degrees, camera frame")
    parser.add_argument("--turn", type=float, default=60.0, help="degrees, CCW on screen")
    parser.add_argument("--out", default="docs/img/goal_run.png")
    args = parser.parse_args(argv)
    print(draw(args))


if __name__ == "__main__":
    main()
