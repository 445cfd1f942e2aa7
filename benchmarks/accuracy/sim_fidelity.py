"""Fidelity of the simulators: every figure docs/results/simulators.md quotes in "Fidelity".

The same checks as the acceptance tests (tests/simulators/test_physics.py), with the
measured values printed instead of pass/fail:

* Voting Theorem: on random pushes whose line passes more than 2 px from the
  CoM, how often ``comcore.vt.predicted_sense`` (true CoM, true ``mu_contact``)
  predicts the sense of rotation: the initial sense (first 3 steps) and the
  sense of the returned ``Motion`` (what estimators see), the theorem applied
  at the disc's real contact and at the point-pusher contact of
  ``comcore.geometry.contacts``; per cone and per engine.
* A push along the normal through the CoM: the largest ``|theta|`` and the travel.
* Mirror symmetry, orientation independence, determinism, rotation growing with
  the lever arm, and the instantaneous rotation against a brute-force limit surface.

    python benchmarks/accuracy/sim_fidelity.py                       # the doc's figures (< 1 min)
    python benchmarks/accuracy/sim_fidelity.py --pushes 3 --objects Obj1 --engines quasistatic
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import argparse
import math
import time

import numpy as np

import comcore
import simulators
from simulators import ENGINES, EngineSettings, MassDistribution, ObjectShape, PushSimulator

VT_OBJECTS = ("Obj1", "Obj5", "Obj7", "Obj12", "Obj16", "Obj19")
NORMAL_OBJECTS = ("Obj1", "Obj5", "Obj11", "Obj13", "Obj8")
CONES = (0.0, 0.5)
RECT = [(-0.04, -0.025), (0.04, -0.025), (0.04, 0.025), (-0.04, 0.025)]


def voting_theorem(objects, cone, n, settings):
    """Agreement counts of the Voting Theorem with the simulated sense of rotation."""
    total = initial = final = point_initial = point_final = 0
    for k, name in enumerate(objects):
        for friction in ("low", "high"):
            sim = simulators.random_simulator(name, friction=friction, rng=k, settings=settings)
            actions = comcore.sample_pushes(sim.mask, n, cone=cone, rng=100 + k)
            com = np.asarray(sim.com_px)
            distance = comcore.geometry.signed_line_distance([com], actions)[0]
            actions = actions[np.abs(distance) > 2.0]
            if not len(actions):
                continue
            point = comcore.geometry.contacts(sim.mask, actions)
            for i, res in enumerate(sim.push_many(actions, record=True)):
                if res.contact_px is None:
                    continue
                push_dir = actions[i, 2:] - actions[i, :2]
                early = res.trajectory[min(3, len(res.trajectory) - 1), 2] - res.trajectory[0, 2]
                early, late = np.sign(early), np.sign(res.motion.theta)
                disc = comcore.vt.predicted_sense(
                    com, res.contact_px, res.normal_px, push_dir, sim.mu_contact
                )
                total += 1
                initial += disc == early
                final += disc == late
                if point.hit[i]:
                    vt = comcore.vt.predicted_sense(
                        com, point.point[i], point.normal[i], push_dir, sim.mu_contact
                    )
                    point_initial += vt == early
                    point_final += vt == late
    return total, initial, final, point_initial, point_final


def normal_pushes(seeds):
    """Largest |theta| (deg) and the travel range (px) of normal pushes through the CoM."""
    thetas, travels = [], []
    for name in NORMAL_OBJECTS:
        for seed in range(seeds):
            sim = simulators.random_simulator(name, friction=("low", "high")[seed % 2], rng=seed)
            motions = sim.push_motions(simulators.normal_pushes_through_com(sim))
            thetas.append(np.abs(motions[:, 0]))
            travels.append(np.hypot(motions[:, 1], motions[:, 2]))
    theta, travel = np.concatenate(thetas), np.concatenate(travels)
    return len(theta), math.degrees(theta.max()), travel.min(), travel.max()


def mirror_error():
    """Largest deviation (rad, m) of a mirrored push's pose change from the mirror image."""
    sim = PushSimulator.from_polygon(RECT, mu_contact=0.4)
    cx, cy = sim.com_px
    actions = np.array([(cx - 30, cy - 5, cx - 8, cy - 7), (cx - 4, cy - 30, cx + 3, cy - 9)])
    mirrored = actions.copy()
    mirrored[:, [1, 3]] = 2 * cy - actions[:, [1, 3]]
    start = np.asarray(sim.initial_pose)
    err = 0.0
    for a, b in zip(sim.push_many(actions), sim.push_many(mirrored)):
        da, db = np.asarray(a.pose) - start, np.asarray(b.pose) - start
        err = max(err, np.abs(db - da * (1, -1, -1)).max())
    return err


def orientation_error(angles=(0.4, 1.3, 2.9, -2.0), pushes=4):
    """Largest relative change of rotation and translation when object and push turn."""
    import shapely

    base = simulators.random_simulator("Obj13", friction="low", rng=5)
    com = np.asarray(base.com_m)
    outline = base.shape.polygon()
    rot_err = move_err = 0.0
    for angle in angles:
        c, s = math.cos(angle), math.sin(angle)
        rot = np.array([[c, -s], [s, c]])
        shape = ObjectShape((base.shape.vertices_m - com) @ rot.T + com)
        mass = MassDistribution(
            (base.mass.points_m - com) @ rot.T + com, base.mass.masses, base.mass.cell_size_m
        )
        turned = PushSimulator(shape, mass, mu_contact=base.mu_contact)
        rng = np.random.default_rng(0)
        done = 0
        while done < pushes:
            vertex = base.outline_at()[rng.integers(len(base.shape.vertices_m))]
            direction = rng.normal(size=2)
            start = vertex * 0.8 + com * 0.2 - 0.06 * direction / np.linalg.norm(direction)
            if shapely.contains_xy(outline, *start):
                continue
            done += 1
            a = base.push(simulators.action_from_world(base, start, direction, travel_m=0.06))
            b = turned.push(
                simulators.action_from_world(
                    turned, (start - com) @ rot.T + com, rot @ direction, 0.06
                )
            )
            da = np.asarray(a.pose) - base.initial_pose
            db = np.asarray(b.pose) - turned.initial_pose
            rot_err = max(rot_err, abs(db[2] - da[2]) / abs(da[2]))
            move_err = max(move_err, np.linalg.norm(db[:2] - rot @ da[:2]) / np.linalg.norm(da[:2]))
    return len(angles) * pushes, rot_err, move_err


def determinism():
    """Bit-identical repeats; largest difference across order and batch (px or rad)."""
    sims = [simulators.random_simulator("Obj12", friction="high", rng=7) for _ in range(2)]
    actions = comcore.sample_pushes(sims[0].mask, 30, cone=0.4, rng=3)
    first = sims[0].push_motions(actions)
    identical = np.array_equal(first, sims[1].push_motions(actions)) and np.array_equal(
        first, sims[0].push_motions(actions)
    )
    order = np.abs(first[::-1] - sims[0].push_motions(actions[::-1])).max()
    single = np.array([sims[0].push(a).motion for a in actions[:5]])
    return identical, order, np.abs(first[:5] - single).max()


def lever_arm():
    """Whether |theta| grows strictly with the lever arm of normal pushes on a box."""
    sim = PushSimulator.from_polygon(RECT, mu_contact=0.3)
    cx, cy = sim.com_px
    actions = np.array([(cx - 25, cy - k, cx - 4, cy - k) for k in range(9)], float)
    theta = sim.push_motions(actions)[:, 0]
    return bool(np.all(np.diff(np.abs(theta)) > 0))


def brute_force_error(levers=(0.0075, 0.015)):
    """Relative error of the instantaneous rotation against a 200 x 200 support grid."""
    from scipy.optimize import minimize_scalar

    g = (np.arange(200) + 0.5) / 200
    x, y = np.meshgrid(-0.04 + 0.08 * g, -0.025 + 0.05 * g)
    sim = PushSimulator.from_polygon(RECT, mu_contact=0.9)
    cx, cy = sim.com_px
    worst = 0.0
    for lever in levers:
        c = np.array([-0.04, lever])

        def power(w, c=c):
            return np.hypot(1 - w * (y - c[1]), w * (x - c[0])).sum()

        exact = minimize_scalar(power, bounds=(-100, 100), method="bounded").x
        k = lever / sim.resolution
        res = sim.push((cx - 25, cy - k, cx - 16 + 0.4, cy - k), record=True)
        omega = (res.trajectory[-1, 2] - res.trajectory[0, 2]) / 0.001
        worst = max(worst, abs(omega / exact - 1))
    return worst


def _pct(k, n):
    return f"{100.0 * k / n:.2f} %" if n else "-"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pushes", type=int, default=40, help="pushes per trial and cone")
    parser.add_argument("--objects", nargs="+", default=list(VT_OBJECTS), help="VT objects")
    parser.add_argument("--engines", nargs="+", default=list(ENGINES), choices=ENGINES)
    parser.add_argument("--seeds", type=int, default=3, help="trials per object, normal pushes")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    print(
        f"Voting Theorem: {args.pushes} pushes per trial on {', '.join(args.objects)} "
        "(low and high friction), lines more than 2 px from the CoM"
    )
    for engine in args.engines:
        for cone in CONES:
            n, ini, fin, p_ini, p_fin = voting_theorem(
                args.objects, cone, args.pushes, EngineSettings(engine=engine)
            )
            print(
                f"  {engine:11s} cone {cone:.1f}: {n} pushes; disc contact: initial sense "
                f"{_pct(ini, n)}, returned motion {_pct(fin, n)}; comcore.geometry.contacts: "
                f"initial {_pct(p_ini, n)}, returned motion {_pct(p_fin, n)}"
            )
    n, theta, lo, hi = normal_pushes(args.seeds)
    print(
        f"normal push through the CoM ({n} pushes): max |theta| {theta:.3g} deg, "
        f"travel {lo:.3f}-{hi:.3f} px"
    )
    print(f"mirror symmetry: max error {mirror_error():.3g} (rad or m)")
    n, rot, move = orientation_error()
    print(
        f"orientation independence ({n} pushes): rotation rel. error {rot:.3g}, "
        f"translation rel. error {move:.3g}"
    )
    identical, order, single = determinism()
    print(
        f"determinism: bit-identical on repeat {identical}, max difference reversed order "
        f"{order:.3g}, batch vs one at a time {single:.3g}"
    )
    print(f"rotation strictly growing with the lever arm: {lever_arm()}")
    error = brute_force_error()
    print(f"instantaneous rotation vs brute-force limit surface: rel. error {error:.3g}")
    print(f"({time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
