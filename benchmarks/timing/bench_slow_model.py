"""How long a slow motion model (0.2 s a call) costs through ``comcore.estimate_posterior``.

A simple correct model (comcore's limit-surface model, without its own friction
batching) made to sleep ``--sleep`` seconds per call, run through ``estimate_posterior``
on 8 pushes of a simulated object with the default ``theta_units="auto"`` (its
units check included); with and without the ``predict_frictions`` hook (every
friction value in one call). Prints the calls and the median seconds of
``--repeats`` runs.

Example::

    PYTHONPATH=. nice -n 10 python benchmarks/timing/bench_slow_model.py --repeats 3
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import comcore
import simulators


class SlowModel:
    """A correct model that sleeps ``sleep`` seconds a call (no friction hook)."""

    def __init__(self, pusher_radius: float, sleep: float):
        self.inner = comcore.LimitSurfaceModel(pusher_radius=pusher_radius)
        self.sleep = sleep
        self.calls = 0

    def predict_hypotheses(self, mask, actions, coms, mu):
        self.calls += 1
        time.sleep(self.sleep)
        return self.inner.predict_hypotheses(mask, actions, coms, mu)


class SlowBatchedModel(SlowModel):
    """The same model with ``predict_frictions``: every friction value in one call."""

    def predict_frictions(self, mask, actions, coms, mus):
        self.calls += 1
        time.sleep(self.sleep)
        return np.stack([self.inner.predict_hypotheses(mask, actions, coms, m) for m in mus])


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sleep", type=float, default=0.2, help="seconds a call (0.2)")
    parser.add_argument("--pushes", type=int, default=8, help="pushes (8)")
    parser.add_argument("--repeats", type=int, default=3, help="runs; the median is shown (3)")
    args = parser.parse_args(argv)
    sim = simulators.random_simulator("Obj3", friction="low", rng=0)
    actions = comcore.sample_pushes(sim.mask, args.pushes, cone=0.4, rng=0)
    motions = np.array([sim.push(a).motion for a in actions])
    print(f"Obj3, {args.pushes} pushes, {sim.mask.area_px} px, {args.sleep} s a call")
    for make in (SlowModel, SlowBatchedModel):
        seconds, calls = [], []
        for _ in range(args.repeats):
            model = make(sim.pusher_radius, args.sleep)
            start = time.perf_counter()
            comcore.estimate_posterior(sim.mask, actions, motions, model=model)
            seconds.append(time.perf_counter() - start)
            calls.append(model.calls)
        hook = "with predict_frictions" if make is SlowBatchedModel else "without hook"
        print(f"{hook:24s} calls {calls[0]:3d}  median {statistics.median(seconds):6.2f} s")


if __name__ == "__main__":
    main()
