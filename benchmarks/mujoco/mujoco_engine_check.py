"""MuJoCo against the exact engine and pymunk (docs/results/simulators.md, "Checking the MuJoCo
engine").

On the benchmark's pushes (``simulators.sample_accepted_pushes``, cone 0.3, 3 cm) of
every object in both friction classes (one trial each, ``accepted_random_simulator``
with ``rng=[seed, k]``), each push from the start pose (the object reset with
``MujocoRobot.place``), this measures:

* how often MuJoCo's rotation sense agrees with the exact engine's, and with the
  Voting Theorem for the true CoM (``comcore.vt.predicted_sense`` at the exact engine's
  contact), on pushes whose line passes more than 2 px from the CoM;
* the rotation (deg) and translation (mm, of the mask's area centroid) differences,
  median and 95th percentile, MuJoCo against exact, MuJoCo against pymunk, and pymunk
  against exact for scale;
* the same medians for a sweep of MuJoCo's settings (time step, contact stiffness,
  solver, cone, speed, number of feet) on a subset, against the finest setting;
* pushes per second (MuJoCo, wall time of ``execute`` incl. the 0.3 s settle).

    PYTHONPATH=. python benchmarks/mujoco/mujoco_engine_check.py                 # docs' figures
    PYTHONPATH=. python benchmarks/mujoco/mujoco_engine_check.py --objects Obj1 --pushes 2 \\
        --no-sweep
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("EGL_PLATFORM", "surfaceless")

import argparse
import dataclasses
import json
import time

import numpy as np

import comcore
import simulators
from simulators import EngineSettings, MujocoRobot, MujocoSettings, PushSimulator

SWEEP_OBJECTS = ("Obj1", "Obj12")
#: (label, MujocoSettings changes); the first is the reference (finest).
SWEEP = (
    ("reference: speed 0.5 cm/s (else the default)", dict(speed=0.005)),
    ("default: speed 1 cm/s, dt 1 ms, tc 2 / 20 ms, Newton, elliptic, 300 feet", {}),
    ("dt 0.5 ms", dict(timestep=0.0005)),
    ("contact tc 4 ms (pusher softer)", dict(contact_timeconst=0.004)),
    ("support tc 5 ms", dict(support_timeconst=0.005)),
    ("support tc 2 ms (all contacts stiff)", dict(support_timeconst=0.002)),
    ("solver PGS", dict(solver="PGS")),
    ("pyramidal cone", dict(cone="pyramidal")),
    ("speed 2 cm/s", dict(speed=0.02)),
    ("speed 5 cm/s", dict(speed=0.05)),
    ("speed 5 cm/s, support tc 2 ms, dt 0.5 ms (the stiff first try)",
     dict(speed=0.05, support_timeconst=0.002, timestep=0.0005)),
    ("800 feet", dict(n_feet=800)),
)  # fmt: skip


def trial_pushes(name, friction, k, seed, n_pushes, settings):
    """The trial's robot, its pushes (grid pixels) and the exact engine's results."""
    sim = simulators.accepted_random_simulator(name, friction, rng=[seed, k])
    robot = MujocoRobot(sim, settings=settings)
    grid = robot.simulator
    actions, _, _ = simulators.sample_accepted_pushes(grid, n_pushes, cone=0.3, rng=[seed, k, 1])
    return robot, actions, grid.push_many(actions)


def mujoco_motions(robot, actions):
    """MuJoCo's motions (n, 3) from the start pose, and the seconds per push."""
    out, t0 = [], time.perf_counter()
    for a in actions:
        robot.place(None)
        out.append(robot.execute(a).motion)
    return np.array(out), (time.perf_counter() - t0) / len(actions)


def pymunk_motions(robot, actions):
    grid = robot.simulator
    twin = PushSimulator(
        grid.shape, grid.mass, mu_contact=grid.mu_contact, resolution=grid.resolution,
        margin=grid.margin, pusher_radius=grid.pusher_radius, mu_floor=grid.mu_floor,
        settings=EngineSettings(engine="pymunk"),
    )  # fmt: skip
    return twin.push_motions(actions)


def differences(a, b, resolution):
    """|rotation| differences (deg) and translation differences (mm)."""
    rot = np.degrees(np.abs(a[:, 0] - b[:, 0]))
    trans = 1000 * resolution * np.hypot(a[:, 1] - b[:, 1], a[:, 2] - b[:, 2])
    return rot, trans


def _stats(v):
    return {"median": float(np.median(v)), "p95": float(np.percentile(v, 95)), "n": len(v)}


def main_check(objects, n_pushes, seed, with_pymunk):
    rows = {"sense_exact": [], "sense_vt": [], "exact_theta": [], "mj_theta": []}
    diffs = {"mj-exact": ([], []), "mj-pymunk": ([], []), "pymunk-exact": ([], [])}
    times = []
    for k, name in enumerate(objects):
        for friction in ("low", "high"):
            robot, actions, results = trial_pushes(name, friction, k, seed, n_pushes, None)
            grid = robot.simulator
            exact = np.array([r.motion for r in results])
            mj, dt = mujoco_motions(robot, actions)
            times.append(dt)
            com = np.asarray(grid.com_px)
            off = np.abs(comcore.geometry.signed_line_distance([com], actions)[0]) > 2.0
            for i, res in enumerate(results):
                if res.contact_px is None or not off[i]:
                    continue
                push_dir = actions[i, 2:] - actions[i, :2]
                vt = comcore.vt.predicted_sense(
                    com, res.contact_px, res.normal_px, push_dir, grid.mu_contact
                )
                rows["sense_exact"].append(np.sign(mj[i, 0]) == np.sign(exact[i, 0]))
                rows["sense_vt"].append(np.sign(mj[i, 0]) == vt)
                rows["exact_theta"].append(float(exact[i, 0]))
                rows["mj_theta"].append(float(mj[i, 0]))
            pairs = [("mj-exact", mj, exact)]
            if with_pymunk:
                pm = pymunk_motions(robot, actions)
                pairs += [("mj-pymunk", mj, pm), ("pymunk-exact", pm, exact)]
            for key, a, b in pairs:
                rot, trans = differences(a, b, grid.resolution)
                diffs[key][0].extend(rot)
                diffs[key][1].extend(trans)
            robot.close()
            print(f"  {name} {friction}: {len(actions)} pushes, {dt:.2f} s/push", flush=True)
    n = len(rows["sense_exact"])
    ex = np.abs(np.degrees(rows["exact_theta"]))
    agree = np.array(rows["sense_exact"])
    out = {
        "pushes_scored": n,
        "sense_agrees_exact": float(np.mean(agree)),
        "sense_agrees_vt": float(np.mean(rows["sense_vt"])),
        "disagreements_exact_abs_theta_deg": sorted(ex[~agree].round(2).tolist()),
        "seconds_per_push": float(np.median(times)),
        "pushes_per_second": float(1 / np.median(times)),
    }
    for key, (rot, trans) in diffs.items():
        if rot:
            out[key] = {"rotation_deg": _stats(rot), "translation_mm": _stats(trans)}
    return out


def sweep(n_pushes, seed):
    """Median |rotation difference| (deg) of each setting against the first, and against exact."""
    cases = []
    for k, name in enumerate(SWEEP_OBJECTS):
        for friction in ("low", "high"):
            sim = simulators.accepted_random_simulator(name, friction, rng=[seed, 100 + k])
            cases.append(sim)
    results, reference, exact_all = [], None, None
    for label, changes in SWEEP:
        settings = dataclasses.replace(MujocoSettings(), **changes)
        motions, exact, secs = [], [], []
        for k, sim in enumerate(cases):
            robot = MujocoRobot(sim, settings=settings)
            grid = robot.simulator
            actions, ex, _ = simulators.sample_accepted_pushes(
                grid, n_pushes, cone=0.3, rng=[seed, 100 + k, 1]
            )
            m, dt = mujoco_motions(robot, actions)
            motions.append(m)
            exact.append(ex)
            secs.append(dt)
            robot.close()
        m, ex = np.vstack(motions), np.vstack(exact)
        if reference is None:
            reference, exact_all = m, ex
        ref_rot, ref_trans = differences(m, reference, grid.resolution)
        ex_rot, _ = differences(m, exact_all, grid.resolution)
        row = {
            "setting": label,
            "vs_reference_rotation_deg": float(np.median(ref_rot)),
            "vs_reference_translation_mm": float(np.median(ref_trans)),
            "vs_exact_rotation_deg": float(np.median(ex_rot)),
            "sense_agrees_exact": float(np.mean(np.sign(m[:, 0]) == np.sign(exact_all[:, 0]))),
            "seconds_per_push": float(np.median(secs)),
        }
        results.append(row)
        print(
            f"  {label:66s} vs ref {row['vs_reference_rotation_deg']:5.2f} deg "
            f"{row['vs_reference_translation_mm']:5.2f} mm, vs exact "
            f"{row['vs_exact_rotation_deg']:5.2f} deg, sense {row['sense_agrees_exact']:.3f}, "
            f"{row['seconds_per_push']:.2f} s/push",
            flush=True,
        )
    return results


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", nargs="+", default=list(simulators.BENCHMARK_OBJECTS))
    parser.add_argument("--pushes", type=int, default=5, help="pushes per trial")
    parser.add_argument("--sweep-pushes", type=int, default=2, help="pushes per sweep trial")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--no-pymunk", action="store_true")
    parser.add_argument("--no-sweep", action="store_true")
    parser.add_argument("--no-check", action="store_true", help="the sweep only")
    parser.add_argument("--json", help="write the figures here")
    args = parser.parse_args(argv)
    t0 = time.time()
    print(f"MuJoCo {__import__('mujoco').__version__}; seed {args.seed}; reset before each push")
    out = {"args": vars(args)}
    if not args.no_check:
        out["check"] = main_check(args.objects, args.pushes, args.seed, not args.no_pymunk)
        report(out["check"])
    if not args.no_sweep:
        print(f"settings sweep ({len(SWEEP_OBJECTS)} objects x 2 friction x {args.sweep_pushes}):")
        out["sweep"] = sweep(args.sweep_pushes, args.seed)
    print(f"total {time.time() - t0:.0f} s")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
    return out


def report(c):
    """Print the main check's figures."""
    print(f"rotation sense, {c['pushes_scored']} pushes off the CoM by > 2 px: agrees with "
          f"exact {c['sense_agrees_exact']:.1%}, with the Voting Theorem "
          f"{c['sense_agrees_vt']:.1%}")  # fmt: skip
    print(f"  |exact theta| (deg) where MuJoCo's sense differs: "
          f"{c['disagreements_exact_abs_theta_deg']}")  # fmt: skip
    for key in ("mj-exact", "mj-pymunk", "pymunk-exact"):
        if key in c:
            r, t = c[key]["rotation_deg"], c[key]["translation_mm"]
            print(
                f"  {key:13s} rotation median {r['median']:.2f} deg, p95 {r['p95']:.2f}; "
                f"translation median {t['median']:.2f} mm, p95 {t['p95']:.2f} (n={r['n']})"
            )
    print(f"MuJoCo: {c['pushes_per_second']:.2f} pushes/s ({c['seconds_per_push']:.2f} s each)")


if __name__ == "__main__":
    main()
