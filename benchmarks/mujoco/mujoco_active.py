"""comcore's active session against MuJoCo (docs/results/simulators.md, "comcore against MuJoCo").

``active-robot`` as in ``comcore bench --conditions`` (a ``comcore.ActiveSession``
with its defaults and the robot's pusher radius, the object never reset, the
session measuring each pose from the mask it is handed), with the world played by:

* ``mujoco``: :class:`simulators.MujocoRobot`, masks from rendered frames
  (warped to the grid with the camera's homography, then ``comcore.mask_from_image``);
* ``mujoco-truth-mask``: the same MuJoCo physics, masks rasterised from the polygon
  at MuJoCo's true pose (swaps the camera for the truth: what the mask costs);
* ``mujoco-vt``: rendered masks, the session without its motion model (``model=None``,
  the Voting Theorem alone): what comcore's motion model costs or gains on MuJoCo;
* ``exact`` / ``pymunk``: :class:`simulators.SimulatedRobot` on comcore's exact
  engine / pymunk, noise-free masks (the realism table's engines, same trials here).

Trials: ``accepted_random_simulator(object, friction, rng=[seed, k, trial])`` (k the
object's index), the session's stream ``[seed, k, trial, 7]``: every engine sees the
same objects, masses, friction and session seed. A frame ``mask_from_image`` refuses
is counted and reported to the session as a failed push (``observe(failed=True)``).

    PYTHONPATH=. python benchmarks/mujoco/mujoco_active.py --trials 1            # docs' table
    PYTHONPATH=. python benchmarks/mujoco/mujoco_active.py --objects Obj1 --trials 1 \\
        --engines mujoco
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("EGL_PLATFORM", "surfaceless")

import argparse
import json
import time

import numpy as np

import comcore
import simulators

ENGINES = ("mujoco", "mujoco-truth-mask", "mujoco-vt", "exact", "pymunk")
#: Run by default (``mujoco-vt`` on request: ``--engines mujoco-vt``).
DEFAULT_ENGINES = ("mujoco", "mujoco-truth-mask", "exact", "pymunk")
#: Failed pushes (refused actions or frames) after which a run gives up, as the benchmark.
MAX_FAILURES = 5


def _robot(sim, engine, rng):
    if engine.startswith("mujoco"):
        return simulators.MujocoRobot(sim)
    return simulators.SimulatedRobot(sim, engine="pymunk" if engine == "pymunk" else None, rng=rng)


def _mask(robot, engine):
    if engine == "mujoco-truth-mask":
        return robot.simulator.mask_at(robot.world_pose)
    return robot.camera_mask()


def run(sim, engine, session_rng, robot_rng):
    """One session on ``sim``; a dict of what the table reports."""
    robot = _robot(sim, engine, robot_rng)
    t0 = time.perf_counter()
    frames = refused = failures = 0
    first = _mask(robot, engine)
    frames += 1
    model = {"model": None} if engine == "mujoco-vt" else {}
    session = comcore.ActiveSession(
        first, pusher_radius=sim.pusher_radius, rng=session_rng, **model
    )
    while not session.done:
        action = session.next_push()
        try:
            robot.execute(action)
        except ValueError:
            failures += 1
            session.observe(failed=True)
        else:
            frames += 1
            try:
                mask = _mask(robot, engine)
            except ValueError:
                refused += 1
                failures += 1
                session.observe(failed=True)
            else:
                session.observe(mask)
        if failures >= MAX_FAILURES:
            break
    est = session.estimate()
    truth = robot.true_com_px
    error_cm = est.error_px(truth) * robot.resolution * 100
    if hasattr(robot, "close"):
        robot.close()
    return {
        "engine": engine,
        "error_cm": float(error_cm),
        "pushes": int(robot.pushes),
        "status": est.status,
        "covered": bool(est.region_holds(truth)),
        "push_failures": failures - refused,
        "frames": frames,
        "refused": refused,
        "seconds": time.perf_counter() - t0,
    }


def summarise(rows, engine):
    r = [x for x in rows if x["engine"] == engine]
    if not r:
        return None
    err = np.array([x["error_cm"] for x in r])
    return {
        "engine": engine,
        "runs": len(r),
        "mean_error_cm": float(err.mean()),
        "median_error_cm": float(np.median(err)),
        "mean_pushes": float(np.mean([x["pushes"] for x in r])),
        "region_holds": float(np.mean([x["covered"] for x in r])),
        "ok_over_1cm": int(sum(x["status"] == "ok" and x["error_cm"] > 1 for x in r)),
        "push_failures": int(sum(x["push_failures"] for x in r)),
        "frames_refused": float(sum(x["refused"] for x in r) / sum(x["frames"] for x in r)),
        "statuses": {s: sum(x["status"] == s for x in r) for s in sorted({x["status"] for x in r})},
        "seconds_per_run": float(np.median([x["seconds"] for x in r])),
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", nargs="+", default=list(simulators.BENCHMARK_OBJECTS))
    parser.add_argument("--friction", nargs="+", default=["low", "high"])
    parser.add_argument("--trials", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--engines", nargs="+", default=list(DEFAULT_ENGINES), choices=ENGINES)
    parser.add_argument("--json", help="write the rows and the table here")
    args = parser.parse_args(argv)
    rows, t0 = [], time.time()
    for k, name in enumerate(args.objects):
        k = simulators.BENCHMARK_OBJECTS.index(name) if name in simulators.BENCHMARK_OBJECTS else k
        for friction in args.friction:
            for trial in range(args.trials):
                sim = simulators.accepted_random_simulator(
                    name, friction, rng=[args.seed, k, trial]
                )
                for engine in args.engines:
                    row = run(sim, engine, [args.seed, k, trial, 7], [args.seed, k, trial, 8])
                    row.update(object=name, friction=friction, trial=trial)
                    rows.append(row)
                    print(
                        f"{name} {friction} {trial} {engine:18s} {row['error_cm']:.3f} cm "
                        f"{row['pushes']} pushes {row['status']:12s} covered {row['covered']} "
                        f"refused {row['refused']} ({row['seconds']:.1f} s)",
                        flush=True,
                    )
    table = [s for s in (summarise(rows, e) for e in args.engines) if s]
    print(f"\nseed {args.seed}, {len(args.objects)} objects x {len(args.friction)} friction x "
          f"{args.trials} trials, {time.time() - t0:.0f} s")  # fmt: skip
    print("| engine | runs | mean error (cm) | median | mean pushes | region holds the CoM "
          "| ok > 1 cm | push failures | frames refused | statuses |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|")
    for s in table:
        print(
            f"| {s['engine']} | {s['runs']} | {s['mean_error_cm']:.3f} | "
            f"{s['median_error_cm']:.3f} | {s['mean_pushes']:.2f} | {s['region_holds']:.0%} | "
            f"{s['ok_over_1cm']} | {s['push_failures']} | {s['frames_refused']:.1%} | "
            f"{', '.join(f'{k} {v}' for k, v in s['statuses'].items())} |"
        )
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"args": vars(args), "rows": rows, "table": table}, f, indent=1)
    return table


if __name__ == "__main__":
    main()
