"""The margin of the theta-in-degrees check: evidence gains on honest and on degrees recordings.

``comcore estimate`` and ``comcore.estimate_posterior`` refuse a recording when every theta
multiplied by pi/180 raises its log evidence under the motion model by more than
``comcore.active._posterior.DEGREES_NATS`` (:func:`theta_degrees_nats`). This script
measures that gain on simulated recordings (``simulators.random_simulator``, the benchmark
objects, low and high friction, ``comcore.sample_pushes`` with cone 0.3 rad, run from the
initial pose as a recording holds them, with tracking noise added) of three kinds:

* ``radians, 3 cm``: honest, pushes of 3 cm (``comcore.sample_pushes``' default travel);
* ``radians, small``: honest, pushes of ``--small-travel`` (3 mm), those that turned the
  object by 3 degrees or more left out: every turn under 3 degrees;
* ``degrees, small``: the same recording with theta written in degrees (each under pi, so
  the check that theta is at most pi does not see it).

It prints the gains' spread per kind and, for each margin of ``--margins``, the false alarms
(honest recordings over it) and the detections (degrees recordings over it). Choose the margin
on one set of seeds and report the rates on another:

    python benchmarks/calibration/theta_units.py --seeds 1            # tune
    python benchmarks/calibration/theta_units.py --seeds 0            # report
    python benchmarks/calibration/theta_units.py --objects Obj3 --seeds 0 --frictions low  # short
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import comcore
from comcore.active._posterior import DEGREES_NATS, theta_degrees_nats

KINDS = ("radians, 3 cm", "radians, small", "degrees, small")
#: Largest turn of a small-turn recording (radians): 3 degrees.
SMALL_TURN = math.radians(3.0)


def recordings(sim, n_pushes, small_travel, noise, rng):
    """``{kind: (actions, motions)}`` of one simulated object (noise: radians, metres std)."""
    px = noise[1] / sim.mask.resolution

    def observed(actions):
        motions = np.asarray(sim.push_motions(actions), float)
        return motions + rng.normal(0.0, 1.0, motions.shape) * [noise[0], px, px]

    out = {}
    actions = comcore.sample_pushes(sim.mask, n_pushes, cone=0.3, rng=rng)
    out[KINDS[0]] = actions, observed(actions)
    actions = comcore.sample_pushes(sim.mask, n_pushes, cone=0.3, travel=small_travel, rng=rng)
    motions = observed(actions)
    keep = np.abs(motions[:, 0]) < SMALL_TURN
    if keep.sum() >= 2:
        out[KINDS[1]] = actions[keep], motions[keep]
        out[KINDS[2]] = actions[keep], motions[keep] * [180 / math.pi, 1, 1]
    return out


def rates(gains: dict, margin: float) -> str:
    honest = np.concatenate([gains[k] for k in KINDS[:2]])
    degrees = np.asarray(gains[KINDS[2]])
    return (f"margin {margin:g} nats: false alarms {int(np.sum(honest > margin))} of "
            f"{len(honest)} honest recordings, detections {int(np.sum(degrees > margin))} of "
            f"{len(degrees)} in degrees")  # fmt: skip


def main(argv=None) -> None:
    import simulators

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", default=",".join(simulators.BENCHMARK_OBJECTS))
    parser.add_argument("--seeds", default="1", help="seeds, e.g. 1 (tune) or 0 (report)")
    parser.add_argument("--frictions", default="low,high")
    parser.add_argument("--pushes", type=int, default=20, help="pushes drawn per recording")
    parser.add_argument("--small-travel", type=float, default=0.003, help="metres")
    parser.add_argument(
        "--noise", default="0.00873,0.0005",
        help="tracking noise added to every motion: theta (radians), translation (metres) std",
    )  # fmt: skip
    parser.add_argument("--margins", default=f"0,3,5,{DEGREES_NATS:g},20,50")
    args = parser.parse_args(argv)
    objects = [o.strip() for o in args.objects.split(",") if o.strip()]
    seeds = [int(v) for v in args.seeds.split(",") if v.strip()]
    frictions = [f.strip() for f in args.frictions.split(",") if f.strip()]
    noise = tuple(float(v) for v in args.noise.split(","))
    gains = {k: [] for k in KINDS}
    start = time.perf_counter()
    for name in objects:
        for seed in seeds:
            for f, friction in enumerate(frictions):
                rng = np.random.default_rng([seed, int(name[3:]), f])
                sim = simulators.random_simulator(name, friction=friction, rng=rng)
                for kind, (actions, motions) in recordings(
                    sim, args.pushes, args.small_travel, noise, rng
                ).items():
                    gains[kind].append(theta_degrees_nats(sim.mask, actions, motions))
    print(f"{len(objects)} objects x seeds {seeds} x frictions {frictions}, {args.pushes} pushes "
          f"drawn, noise {noise[0]:g} rad / {noise[1]:g} m; "
          f"{time.perf_counter() - start:.0f} s")  # fmt: skip
    print("| recordings | n | min gain (nats) | median | max |")
    print("| --- | --- | --- | --- | --- |")
    for kind in KINDS:
        g = np.asarray(gains[kind])
        print(f"| {kind} | {len(g)} | {g.min():.1f} | {np.median(g):.1f} | {g.max():.1f} |")
    for margin in (float(v) for v in args.margins.split(",")):
        print(rates(gains, margin))


if __name__ == "__main__":
    main()
