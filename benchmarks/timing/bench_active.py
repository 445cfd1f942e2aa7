"""Timing of comcore.estimate_active: choosing a push, a run without a model, a default step.

The budget: choosing from 200 candidates on a 5,000-pixel mask takes
under 50 ms (median). The choice is the expected information gain of every
candidate over the whole (pixel x friction) posterior; it is timed on the
uniform prior (every pixel alive: the worst case) and after a few pushes.

Example::

    PYTHONPATH=. nice -n 10 python benchmarks/timing/bench_active.py --repeats 30
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _masks import ellipse_mask  # this folder is on the path when run as a script

import comcore

# Timing comcore's internal push scoring directly: no public API exposes it alone.
from comcore.active._choice import sense_information
from comcore.active._grid import GridPosterior
from comcore.vt._voting import force_lines


def median_ms(fn, repeats: int) -> float:
    """Median wall time of ``fn()`` in milliseconds."""
    fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return 1e3 * float(np.median(times))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pixels", type=int, default=5000)
    parser.add_argument("--candidates", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=30)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--objects",
        default="Obj1,Obj7,Obj10,Obj19,Obj20",
        help="benchmark objects to time the default model's steps on ('' for none)",
    )
    parser.add_argument(
        "--sessions", type=int, default=1, help="sessions (seeds) per object for the step times"
    )
    args = parser.parse_args(argv)

    mask = ellipse_mask(args.pixels)
    cands = comcore.sample_pushes(mask, args.candidates, cone=0.3, rng=args.seed)
    con = comcore.geometry.contacts(mask, cands)
    direction = cands[:, 2:] - cands[:, :2]
    direction /= np.hypot(direction[:, 0], direction[:, 1])[:, None]
    mus = comcore.Likelihood().mus
    lines = force_lines(con.point, con.normal, direction, np.arctan(mus))
    post = GridPosterior(mask.pixels, np.full(mask.area_px, 1 / mask.area_px), mus)

    def choose():
        return sense_information(post.pixels, post.sense_weights, lines, 0.05)

    print(
        f"mask {mask.area_px} px, {len(cands)} candidates, {len(mus)} friction values "
        f"(mu unknown), {args.repeats} repeats"
    )
    print(f"choose a push, uniform prior:   {median_ms(choose, args.repeats):6.1f} ms (median)")

    com = np.add(mask.centroid, (7.0, -4.0))

    def push(action):
        c = comcore.geometry.contacts(mask, action)
        sense = comcore.vt.predicted_sense(com, c.point[0], c.normal[0], action.direction, 0.4)
        return comcore.Motion(0.1 * sense, 0.0, 0.0)

    est = comcore.estimate_active(mask, push, cands, stop=comcore.StopRule(max_pushes=3))
    post.update(np.log(est.posterior.image[mask.data] + 1e-300)[:, None, None])
    print(f"choose a push, after 3 pushes:  {median_ms(choose, args.repeats):6.1f} ms (median)")

    def run():
        stop = comcore.StopRule(max_pushes=4, target_radius=1e-6)
        return comcore.estimate_active(mask, push, cands, model=None, stop=stop)

    per_push = median_ms(run, max(3, args.repeats // 5)) / 4
    print(f"whole run without a model:      {per_push:6.1f} ms per push (median of runs / 4)")
    if args.objects:
        default_model_steps(args.objects.split(","), args.seed, args.sessions)


def default_model_steps(objects, seed: int, sessions: int = 1) -> None:
    """Time the active steps of the defaults (the motion model included) on benchmark masks.

    A step is ``observe`` (the posterior update, the model asked about every
    live hypothesis at the pusher-offset nodes) plus ``next_push`` (the
    choice), on the object pushed by the benchmark's simulator (reset before
    each push), for ``sessions`` sessions per object (seeds ``seed``,
    ``seed + 1``, ...). CPU time, so that a machine shared with other jobs does
    not inflate it. Reports the median step, the median first step (every
    hypothesis alive, nothing remembered) and the slowest.
    """
    import simulators

    for name in objects:
        steps, firsts = [], []
        for s in range(seed, seed + sessions):
            sim = simulators.random_simulator(name, "low", rng=s)
            session = comcore.ActiveSession(sim.mask, pusher_radius=sim.pusher_radius, rng=s)
            first = True
            while not session.done:
                start = time.process_time()
                action = session.next_push()
                step = time.process_time() - start
                motion = sim.push(action).motion
                start = time.process_time()
                session.observe(motion=motion, reset=True)  # and plans the next push
                step += time.process_time() - start
                (firsts if first else steps).append(step)
                first = False
        ms, first_ms = 1e3 * np.array(steps + firsts), 1e3 * np.array(firsts)
        print(
            f"default model, {name:6s} ({sim.mask.area_px:5d} px): {len(ms)} steps, "
            f"median {np.median(ms):6.1f} ms, first push median {np.median(first_ms):6.1f} ms, "
            f"max {ms.max():6.1f} ms (CPU)"
        )


if __name__ == "__main__":
    main()
