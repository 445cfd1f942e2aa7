"""The cost of estimate_posterior's bagged region: the same recording with and without it.

Run: ``python benchmarks/timing/bench_bagging.py [--objects Obj1,Obj7] [--pushes 10,40]
[--resolution 0.0025] [--repeats 3] [--model limit-surface|none]``.

Per object (``simulators.random_simulator``, low friction, seed 0) and number of pushes,
a recording of random pushes (``comcore.sample_pushes``, cone 0.3 rad) run in the
simulator; ``comcore.estimate_posterior`` is timed on it (wall, ``time.perf_counter``,
and CPU, ``time.process_time``) with ``bootstrap=0`` (the posterior's own region) and
with the default (``comcore.active.RECORDED_BOOTSTRAP`` resamplings), ``--repeats`` times each,
alternating; the medians are printed, with what the bag adds.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import comcore


def recording(name: str, n: int, resolution: float):
    import simulators

    rng = np.random.default_rng([0, int(name[3:])])
    sim = simulators.random_simulator(name, friction="low", rng=rng, resolution=resolution)
    actions = comcore.sample_pushes(sim.mask, n, cone=0.3, rng=rng)
    return sim.mask, actions, np.asarray(sim.push_motions(actions), float)


def timed(*args, **kwargs) -> tuple[float, float]:
    """Wall and CPU seconds of ``comcore.estimate_posterior(*args, **kwargs)``."""
    wall, cpu = time.perf_counter(), time.process_time()
    comcore.estimate_posterior(*args, theta_units="rad", **kwargs)  # bagging, no units check
    return time.perf_counter() - wall, time.process_time() - cpu


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--objects", default="Obj1,Obj7")
    p.add_argument("--pushes", default="10,40")
    p.add_argument("--resolution", type=float, default=0.0025)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--model", choices=("limit-surface", "none"), default="limit-surface")
    args = p.parse_args(argv)
    model = comcore.active._options.DEFAULT_MODEL if args.model == "limit-surface" else None
    print("| object | pushes | pixels | bootstrap=0 wall / CPU (s) | default wall / CPU (s) "
          "| the bag adds (CPU) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name in args.objects.split(","):
        for n in (int(v) for v in args.pushes.split(",")):
            mask, actions, motions = recording(name, n, args.resolution)
            times = {0: [], comcore.active.RECORDED_BOOTSTRAP: []}
            for _ in range(args.repeats):
                for b in times:
                    times[b].append(timed(mask, actions, motions, model=model, bootstrap=b))
            med = {b: np.median(np.asarray(t), axis=0) for b, t in times.items()}
            plain, bagged = med[0], med[comcore.active.RECORDED_BOOTSTRAP]
            print(f"| {name} | {n} | {mask.area_px} | {plain[0]:.2f} / {plain[1]:.2f} | "
                  f"{bagged[0]:.2f} / {bagged[1]:.2f} | {bagged[1] - plain[1]:+.2f} s |")


if __name__ == "__main__":
    main()
