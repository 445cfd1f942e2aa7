"""What the CoM estimate is worth in a task: pushing benchmark objects to goal poses.

Four strategies on the same trials, the same planner (comcore.GoalSession),
the object never reset:

* ``centroid``: the CoM fixed at the first mask's centroid (what a user
  without comcore would assume), frictions unknown, nothing learned;
* ``estimate-first``: a comcore.ActiveSession to its stop, then the planner on
  its posterior, fixed (its pushes counted apart);
* ``learn``: the planner from no estimate, learning from every push;
* ``oracle``: the true CoM and contact friction, fixed.

Goals are drawn with the seed: ``translation`` (20 cm in a random direction,
the orientation held: within 2 degrees at the end) and ``pose`` (10-30 cm
away, an orientation change of 0-90 degrees either way). Success: the true
pose within 1 cm and 3 degrees (2 degrees for ``translation``, counted apart).
The largest turn on the way is how far the true orientation, after any push
of the goal session, lay outside the band from its orientation at the
session's start to the goal's (:func:`largest_turn`: for a translation the
largest ``|orientation - start|``); ``--max-turn`` bounds it in the goals
(:attr:`comcore.Goal.max_turn`). One JSON line per (trial, strategy) goes to
``--out``; a table to stdout. ``--frame-rate HZ`` gives the ``learn`` and
``estimate-first`` sessions the camera's frames during each push besides the
mask after it (``observe(mask, frames=push.path)``: the issue of the frames).

Example::

    PYTHONPATH=. python benchmarks/accuracy/goal_bench.py --seed 0 --trials 1 --out runs/goal.jsonl
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

import comcore
import comcore.goal._session as goal_session  # to time the planner's step alone
import simulators

STRATEGIES = ("centroid", "estimate-first", "learn", "oracle")
KINDS = ("translation", "pose")
MAX_TRAVEL = 0.05
PLAN_TIMES: list[float] = []


def _timed(plan):
    def wrapper(*args, **kwargs):
        start = time.perf_counter()
        out = plan(*args, **kwargs)
        PLAN_TIMES.append(time.perf_counter() - start)
        return out

    return wrapper


goal_session.plan_push = _timed(goal_session.plan_push)


def draw_goal(kind: str, rng: np.random.Generator, max_turn=None) -> tuple[comcore.Goal, float]:
    """A goal of ``kind`` and its distance (metres); ``max_turn`` its bound (radians, or None)."""
    angle = rng.uniform(0, 2 * math.pi)
    if kind == "translation":
        dist, theta, tol = 0.20, 0.0, math.radians(2.0)
    else:
        dist = rng.uniform(0.10, 0.30)
        theta = float(rng.choice([-1.0, 1.0]) * rng.uniform(0, math.pi / 2))
        tol = math.radians(3.0)
    goal = comcore.Goal(
        displacement=(dist * math.cos(angle), dist * math.sin(angle)),
        orientation=theta,
        orientation_tolerance=tol,
        max_turn=max_turn,
    )
    return goal, dist


def _camera(robot):
    try:
        return robot.camera_mask()
    except ValueError:  # the object left the camera's view
        return None


def _drive(robot, session, loop_limit=200, frame_rate=None) -> bool:
    """Run a session (goal or active) on the robot; False when the object left the view.

    ``frame_rate`` (Hz): the camera's frames during each push are given to the
    session too (``observe(mask, frames=push.path)``); None: the end masks alone.
    """
    for _ in range(loop_limit):
        if session.done:
            return True
        action = session.next_push()
        if frame_rate is None:
            robot.execute(action)
            frames = {}
        else:
            frames = {"frames": robot.execute(action, frame_rate=frame_rate).path}
        mask = _camera(robot)
        if mask is None:
            if isinstance(session, comcore.GoalSession):
                session.observe(out_of_view=True)
            return False
        session.observe(mask, **frames)
    return True


def largest_turn(start: float, goal, thetas) -> float:
    """The largest turn on the way (radians): how far the orientation left the band it need cross.

    The band runs from the orientation at the goal session's start to the
    goal's (just the start where the goal leaves the orientation free); the
    turn after each push is the true orientation's distance outside it, 0
    inside. For a translation (goal = start) it is the largest
    ``|orientation - start|``; for a pose goal, the largest overshoot past the
    goal's orientation or swing back past the start, not the turn asked for.
    """
    low, high = sorted((start, start if goal is None else goal))
    return max((max(low - t, t - high, 0.0) for t in thetas), default=0.0)


def run_strategy(strategy, sim, goal, args, robot_seed):
    """One trial of one strategy: a JSON-able row."""
    robot = simulators.SimulatedRobot(
        sim,
        camera_margin=args.margin,
        pusher_error=args.pusher_offset,
        engine="quasistatic" if args.engine == "exact" else args.engine,
        rng=robot_seed,
    )
    first = robot.camera_mask()
    options = {"travel": MAX_TRAVEL, "rng": 0}
    options["max_pushes"] = args.max_pushes
    options["pusher_radius"] = sim.pusher_radius
    est_pushes, status_est = 0, None
    if strategy == "centroid":
        prior = [first.centroid]
    elif strategy == "oracle":
        prior = comcore.goal.CoMHypotheses(
            np.array([robot.true_com_px]), np.array([sim.mu_contact]), np.ones(1)
        )
    elif strategy == "estimate-first":
        active = comcore.ActiveSession(first, pusher_radius=sim.pusher_radius, rng=0)
        in_view = _drive(robot, active, frame_rate=args.frame_rate)
        est_pushes, status_est = len(active.actions), active.status
        prior = active if in_view else None
    else:
        prior = None
    start_rotations = len(robot.history)
    start_theta = robot.pose.theta
    learning = 0
    if strategy == "estimate-first" and prior is None:
        status, pushes = "lost", 0
    else:
        if args.learning_pushes is not None:
            options["learning_pushes"] = args.learning_pushes
        session = comcore.GoalSession(
            first, goal, prior=prior, learn=strategy == "learn", **options
        )
        _drive(robot, session, frame_rate=args.frame_rate)
        status, pushes = session.status, len(session.pushes) + (session.status == "lost")
        learning = session.push_kinds.count("learn")
    truth = robot.pose
    target = goal.target_px(first)
    pos_err = math.hypot(truth.tx - target[0], truth.ty - target[1]) * first.resolution
    ang_err = abs(truth.theta - goal.orientation)
    pushed = robot.history[start_rotations:]
    turned = sum(abs(p.motion.theta) for p in pushed)
    widest = largest_turn(start_theta, goal.orientation, [p.pose.theta for p in pushed])
    return {
        "strategy": strategy,
        "status": status,
        "pushes": pushes,
        "estimate_pushes": est_pushes,
        "learning_pushes": learning,
        "estimate_status": status_est,
        "pos_err_cm": 100 * pos_err,
        "ang_err_deg": math.degrees(ang_err),
        "success": bool(pos_err <= 0.01 and ang_err <= math.radians(3)),
        "success_2deg": bool(pos_err <= 0.01 and ang_err <= math.radians(2)),
        "turned_deg": math.degrees(turned),
        "largest_turn_deg": math.degrees(widest),
    }


def summary(rows) -> str:
    """The markdown table of the rows, per goal kind and strategy."""
    lines = [
        "| goals | strategy | trials | success (1 cm, 3 deg) | success (1 cm, 2 deg) | pushes "
        "(median) | pushes / lower bound | pushes / oracle's | final error cm (median) | "
        "final error deg (median) | summed rotation deg (median) | largest turn on the way "
        "deg (median / max) | estimation pushes (median) |",
        "|" + "---|" * 13,
    ]
    for kind in KINDS:
        oracle = {
            r["trial_id"]: r["pushes"]
            for r in rows
            if r["kind"] == kind and r["strategy"] == "oracle"
        }
        for strategy in STRATEGIES:
            mine = [r for r in rows if r["kind"] == kind and r["strategy"] == strategy]
            if not mine:
                continue
            pushes = np.array([r["pushes"] for r in mine], float)
            widest = [r["largest_turn_deg"] for r in mine]
            bound = np.array([r["lower_bound"] for r in mine], float)
            paired = [(r["pushes"], oracle[r["trial_id"]]) for r in mine if r["trial_id"] in oracle]
            ratio = sum(p for p, _ in paired) / max(sum(o for _, o in paired), 1)
            lines.append(
                f"| {kind} | {strategy} | {len(mine)} | "
                f"{100 * np.mean([r['success'] for r in mine]):.0f} % | "
                f"{100 * np.mean([r['success_2deg'] for r in mine]):.0f} % | "
                f"{np.median(pushes):.0f} | {pushes.sum() / bound.sum():.2f} | {ratio:.2f} | "
                f"{np.median([r['pos_err_cm'] for r in mine]):.2f} | "
                f"{np.median([r['ang_err_deg'] for r in mine]):.1f} | "
                f"{np.median([r['turned_deg'] for r in mine]):.0f} | "
                f"{np.median(widest):.0f} / {np.max(widest):.0f} | "
                f"{np.median([r['estimate_pushes'] for r in mine]):.0f} |"
            )
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--objects", nargs="+", default=list(simulators.BENCHMARK_OBJECTS))
    parser.add_argument("--friction", nargs="+", default=["low", "high"])
    parser.add_argument("--trials", type=int, default=1, help="trials per object, class, kind")
    parser.add_argument("--kinds", nargs="+", default=list(KINDS), choices=KINDS)
    parser.add_argument("--strategies", nargs="+", default=list(STRATEGIES), choices=STRATEGIES)
    parser.add_argument("--engine", default="exact", choices=["exact", "pymunk"])
    parser.add_argument("--pusher-offset", type=float, default=0.0, help="std, metres")
    parser.add_argument("--max-pushes", type=int, default=30)
    parser.add_argument("--margin", type=float, default=0.40, help="camera margin, metres")
    parser.add_argument(
        "--max-turn", type=float, default=None,
        help="the goals' max_turn, degrees (default: unbounded)",
    )  # fmt: skip
    parser.add_argument(
        "--learning-pushes", type=int, default=None,
        help="GoalSession(learning_pushes=...): 0 says stuck at once (default: the session's)",
    )  # fmt: skip
    parser.add_argument(
        "--frame-rate", type=float, default=None, metavar="HZ",
        help="give the sessions the camera's frames during each push at this rate (the robot's "
        "pusher at its default speed); default: the end masks alone",
    )  # fmt: skip
    parser.add_argument("--timing", action="store_true", help="print the planner's step times")
    parser.add_argument("--out", default=None, help="JSON lines, one per trial and strategy")
    args = parser.parse_args(argv)

    rows = []
    out = open(args.out, "w") if args.out else None
    for name in args.objects:
        for j, friction in enumerate(args.friction):
            for trial in range(args.trials):
                for k, kind in enumerate(KINDS):
                    if kind not in args.kinds:
                        continue
                    key = [args.seed, simulators.BENCHMARK_OBJECTS.index(name), j, trial, k]
                    sim = simulators.accepted_random_simulator(
                        name, friction, rng=lambda attempt, key=key: [*key, attempt]
                    )
                    bound = None if args.max_turn is None else math.radians(args.max_turn)
                    goal, dist = draw_goal(kind, np.random.default_rng([*key, 99]), bound)
                    for strategy in args.strategies:
                        start = time.perf_counter()
                        row = run_strategy(strategy, sim, goal, args, robot_seed=key)
                        row.update(
                            object=name, friction=friction, trial=trial, kind=kind,
                            trial_id=f"{name}/{friction}/{trial}/{kind}",
                            lower_bound=math.ceil(dist / MAX_TRAVEL),
                            seconds=time.perf_counter() - start,
                        )  # fmt: skip
                        rows.append(row)
                        if out:
                            out.write(json.dumps(row) + "\n")
                            out.flush()
    if out:
        out.close()
    print(summary(rows))
    if args.timing and PLAN_TIMES:
        times = 1e3 * np.array(PLAN_TIMES)
        print(
            f"planning step: median {np.median(times):.0f} ms, 90 % {np.quantile(times, 0.9):.0f} "
            f"ms over {len(times)} steps"
        )


if __name__ == "__main__":
    main()
