"""Speed and accuracy of the simulators.

Speed: pushes per second on one core for 3 cm pushes (``comcore.sample_pushes``)
on a mid-sized benchmark object, batched as ``push_motions`` does it and one at
a time, for each engine. Accuracy (``--accuracy``): the default settings
against a fine reference (0.25 mm steps, 256 support points, 8 projections)
on random trials of six objects.

    python benchmarks/timing/bench_sim.py                 # speed, Obj7
    python benchmarks/timing/bench_sim.py --accuracy      # accuracy vs speed table
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")  # one core: BLAS must not spread out
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import argparse
import time

import numpy as np

import comcore
import simulators
from simulators import EngineSettings, MassDistribution, PushSimulator

#: Batch sizes timed besides ``--pushes`` (throughput grows with the batch).
BATCH_SIZES = (5, 20, 60, 120)
ACCURACY_OBJECTS = ("Obj1", "Obj5", "Obj7", "Obj12", "Obj16", "Obj19")
REFERENCE = (EngineSettings(step_m=0.00025, projections=8), 256)
CANDIDATES = (
    (EngineSettings(step_m=0.002), 96),
    (EngineSettings(projections=1), 96),
    (EngineSettings(), 64),
    (EngineSettings(), 96),
    (EngineSettings(), 160),
    (EngineSettings(step_m=0.0005), 96),
    (EngineSettings(engine="pymunk"), 96),
    (EngineSettings(engine="pymunk", iterations=50, step_m=0.0005), 96),
)


def pushes_per_second(sim, actions, repeats, batched=True):
    """Median over repeats of pushes per CPU second."""
    rates = []
    for _ in range(repeats):
        t0 = time.process_time()
        if batched:
            sim.push_motions(actions)
        else:
            for a in actions:
                sim.push(a)
        rates.append(len(actions) / max(time.process_time() - t0, 1e-9))
    return float(np.median(rates))


def speed(args):
    sim = simulators.random_simulator(args.object, friction="low", rng=0)
    actions = comcore.sample_pushes(sim.mask, args.pushes, cone=0.3, rng=1)
    print(
        f"{args.object} ({sim.shape.area_m2 * 1e4:.1f} cm^2), 3 cm pushes, cone 0.3 rad, "
        f"mu_contact {sim.mu_contact:.2f}, {len(sim.mass.masses)} support points"
    )
    rows = [("quasistatic, push_motions, batch of", EngineSettings(), True, n) for n in BATCH_SIZES]
    rows += [
        ("quasistatic, push_motions, batch of", EngineSettings(), True, args.pushes),
        ("quasistatic, push() one at a time, n =", EngineSettings(), False, 20),
        ("pymunk (default settings), n =", EngineSettings(engine="pymunk"), False, 20),
    ]
    for label, settings, batched, n in rows:
        n = min(n, args.pushes)
        s = PushSimulator(sim.shape, sim.mass, mu_contact=sim.mu_contact, settings=settings)
        s.push_motions(actions[:2])  # build the engine outside the timing
        rate = pushes_per_second(s, actions[:n], args.repeats, batched)
        print(f"  {label:40s} {n:4d}: median {rate:7.1f} pushes/s/core")


def _trials(n_pushes):
    for k, name in enumerate(ACCURACY_OBJECTS):
        for friction in ("low", "high"):
            sim = simulators.random_simulator(name, friction=friction, rng=100 + k)
            yield sim, comcore.sample_pushes(sim.mask, n_pushes, cone=0.4, rng=k)


def _run(trials, settings, n_support):
    out, seconds = [], 0.0
    for sim, actions in trials:
        mass = MassDistribution.on_shape(sim.shape, com=sim.com_m, n_support=n_support)
        s = PushSimulator(sim.shape, mass, mu_contact=sim.mu_contact, settings=settings)
        t0 = time.process_time()
        out.append(s.push_motions(actions))
        seconds += time.process_time() - t0
    motions = np.vstack(out)
    return motions, seconds / len(motions)


def accuracy(args):
    trials = list(_trials(args.pushes))
    ref, ref_time = _run(trials, *REFERENCE)
    print(f"reference {REFERENCE[0]}, {REFERENCE[1]} support points: {ref_time * 1e3:.1f} ms/push")
    print(f"{len(ref)} pushes (cone 0.4 rad) on {', '.join(ACCURACY_OBJECTS)}, low and high mu")
    header = "engine        step   N proj |  ms/push | dtheta deg: med   p90   p99   max"
    print(header + " | dxy px: med   p90 | sign flips")
    for settings, n_support in CANDIDATES:
        if settings.engine == "pymunk" and not args.pymunk:
            continue
        m, t = _run(trials, settings, n_support)
        dth = np.degrees(np.abs(m[:, 0] - ref[:, 0]))
        dxy = np.hypot(m[:, 1] - ref[:, 1], m[:, 2] - ref[:, 2])
        flips = np.mean(np.sign(m[:, 0]) != np.sign(ref[:, 0]))
        q = np.percentile(dth, [50, 90, 99])
        print(
            f"{settings.engine:12s} {settings.step_m * 1e3:5.2f} {n_support:3d} "
            f"{settings.projections:4d} | {t * 1e3:8.2f} | {q[0]:14.3f} {q[1]:5.2f} {q[2]:5.2f} "
            f"{dth.max():5.2f} | {np.median(dxy):10.3f} {np.percentile(dxy, 90):5.2f} | "
            f"{flips:.3f}"
        )


def figure(path):
    """Draw pushed objects' trajectories (outline every few steps, CoM path, pusher)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6))
    cases = (("Obj19", "low", 3, 0.0), ("Obj7", "high", 8, 0.5))
    for ax, (name, friction, seed, cone) in zip(axes, cases):
        sim = simulators.random_simulator(name, friction=friction, rng=seed)
        action = comcore.sample_pushes(sim.mask, 1, cone=cone, rng=seed, travel=0.05)[0]
        res = sim.push(action, record=True)
        traj = res.trajectory
        for k in np.linspace(0, len(traj) - 1, 6).astype(int):
            outline = sim.outline_at(traj[k]) * 100
            shade = 0.25 + 0.75 * k / (len(traj) - 1)
            ax.fill(*outline.T, color=(0.2, 0.4, 0.8, 0.12), lw=0)
            ax.plot(*np.vstack([outline, outline[:1]]).T, color=(0.1, 0.2, 0.6, shade), lw=1)
        ax.plot(traj[:, 0] * 100, traj[:, 1] * 100, "r-", lw=1.5, label="CoM path")
        ax.plot(*(np.asarray(sim.com_m) * 100), "r+", ms=12, mew=2)
        ends = sim.to_world(action.reshape(2, 2)) * 100
        d = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
        r = sim.pusher_radius * 100
        for centre, alpha in ((ends[0] - r * d, 0.3), (ends[1] - r * d, 0.8)):
            ax.add_patch(plt.Circle(centre, r, color="k", alpha=alpha))
        ax.annotate("", ends[1], ends[0], arrowprops={"arrowstyle": "->", "color": "k"})
        ax.set_title(
            f"{name}, mu_contact {sim.mu_contact:.2f}: theta {np.degrees(res.motion.theta):.1f} deg"
        )
        ax.set_aspect("equal")
        ax.set_xlabel("x (cm, world)")
        ax.set_ylabel("y (cm, world, up)")
        ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--object", default="Obj7", help="benchmark object for the speed test")
    parser.add_argument("--pushes", type=int, default=200, help="pushes per batch")
    parser.add_argument("--repeats", type=int, default=5, help="timing repeats (median)")
    parser.add_argument("--accuracy", action="store_true", help="accuracy vs speed table")
    parser.add_argument("--pymunk", action="store_true", help="include pymunk in --accuracy")
    parser.add_argument("--figure", metavar="PNG", help="draw pushed objects' trajectories")
    args = parser.parse_args(argv)
    if args.figure:
        figure(args.figure)
    elif args.accuracy:
        accuracy(args)
    else:
        speed(args)


if __name__ == "__main__":
    main()
