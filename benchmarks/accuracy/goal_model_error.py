"""The motion model's rotation error against an engine, by push travel and lever.

What the goal planner's model-error term (comcore/goal/_costs.py) is fitted
on: for each benchmark object and friction class, pushes from the object's
first pose along 8 directions at 12 offsets across it (through and around the
true CoM), each for several travels after contact, predicted by the planner's
model (comcore.LimitSurfaceModel, every hypothesis integrated) with the TRUE
CoM and contact friction and executed by the engine. The error of the
predicted rotation is tabulated by travel and by the CoM's lever about the
push line (median, 80th percentile), and the planner's form is fitted to the
80th percentile over 1.28 (a normal's)::

    sigma(lever, travel) = a + b / (1 + (lever / l)^2) * (travel / 5 cm)^p

Example (the fit in comcore/goal/_costs.py: seed 1, 8 objects, about 2 min)::

    PYTHONPATH=. python benchmarks/accuracy/goal_model_error.py --seed 1 \\
        --objects Obj1 Obj5 Obj8 Obj11 Obj14 Obj15 Obj3 Obj18
"""

from __future__ import annotations

import argparse
import itertools

import numpy as np
from scipy.optimize import least_squares

import comcore
import simulators
from comcore.goal._translation import _cross_offsets, line_pushes, planning_model, predict_motions

LEVERS = (0.0, 0.0025, 0.005, 0.01, 0.015, 0.02, 0.03, 0.04, 0.06, 1.0)


def measure(name, friction, j, args):
    """``(travel m, lever m, predicted rad, true rad)`` rows of one object and friction."""
    key = [args.seed, simulators.BENCHMARK_OBJECTS.index(name), j, 0, 0]
    sim = simulators.accepted_random_simulator(name, friction, rng=lambda a, key=key: [*key, a])
    engine = "quasistatic" if args.engine == "exact" else args.engine
    robot = simulators.SimulatedRobot(sim, camera_margin=0.40, engine=engine, rng=0)
    first = robot.camera_mask()
    com = np.array(robot.true_com_px)
    hyps = comcore.goal.CoMHypotheses(com[None], np.array([sim.mu_contact]), np.ones(1))
    directions = np.linspace(0, 2 * np.pi, args.directions, endpoint=False)
    offsets = np.stack([_cross_offsets(first, a, hyps, 7) for a in directions])
    lengths = np.asarray(args.travels) / first.resolution
    start = comcore.Motion.identity()
    actions, meta = line_pushes(first, start, directions, offsets, lengths, sim.pusher_radius)
    predicted = predict_motions(planning_model(sim.pusher_radius), first, actions, hyps)[0]
    rows = []
    for action, m, p in zip(actions, meta, predicted):
        robot.place()
        truth = robot.execute(action).motion.theta
        d = (action[2:] - action[:2]) / np.hypot(*(action[2:] - action[:2]))
        lever = abs((com - action[:2]) @ np.array([-d[1], d[0]])) * first.resolution
        rows.append((m[2] * first.resolution, lever, p[0], truth))
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--objects", nargs="+", default=list(simulators.BENCHMARK_OBJECTS))
    parser.add_argument("--friction", nargs="+", default=["low", "high"])
    parser.add_argument("--engine", default="exact", choices=["exact", "pymunk"])
    parser.add_argument("--directions", type=int, default=8)
    parser.add_argument("--travels", type=float, nargs="+", default=[0.005, 0.0125, 0.025, 0.05])
    args = parser.parse_args(argv)
    rows = []
    for name in args.objects:
        for j, friction in enumerate(["low", "high"]):
            if friction in args.friction:
                rows += measure(name, friction, j, args)
    travel, lever, pred, truth = np.array(rows, float).T
    err = np.abs(truth - pred)
    print(f"{len(rows)} pushes; rotation error (deg) by travel and lever")
    print("| travel cm | lever cm | pushes | median | 80 % |\n|---|---|---|---|---|")
    bins = []
    for t in np.unique(np.round(travel, 4)):
        for lo, hi in itertools.pairwise(LEVERS):
            s = (np.round(travel, 4) == t) & (lever >= lo) & (lever < hi)
            if s.sum() < 20:  # too few to read a percentile
                continue
            q80 = np.quantile(err[s], 0.8)
            bins.append((t, np.median(lever[s]), q80 / 1.28))
            print(
                f"| {100 * t:.2f} | {100 * lo:.2f}-{100 * hi:.2f} | {s.sum()} | "
                f"{np.degrees(np.median(err[s])):.2f} | {np.degrees(q80):.2f} |"
            )
    if len(bins) < 4:
        print("too few pushes to fit the form (4 bins of 20 at least)")
        return
    b = np.array(bins)

    def form(x, t, lev):
        return x[0] + x[1] / (1 + (lev / x[2]) ** 2) * (t / 0.05) ** x[3]

    fit = least_squares(
        lambda x: np.log(form(x, b[:, 0], b[:, 1]) / b[:, 2]),
        [0.01, 0.13, 0.0375, 2.0],
        bounds=([1e-4, 0, 1e-3, 0.5], [0.1, 1, 0.2, 4]),
    ).x
    print(
        f"fit: sigma = {fit[0]:.4f} + {fit[1]:.3f} / (1 + (lever / {100 * fit[2]:.2f} cm)^2) "
        f"* (travel / 5 cm)^{fit[3]:.2f} rad"
    )


if __name__ == "__main__":
    main()
