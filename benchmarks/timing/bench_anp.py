"""Time AnpPredictor inference: 100 queries from 12 priors on a benchmark object, CPU.

Run: ``python benchmarks/timing/bench_anp.py [--repeats 30] [--queries 100] [--threads 1]``.
Prints the median and the 10th/90th percentile wall time of one ``predict`` call.
Needs the ``anp`` and ``sim`` extras (the priors come from the simulator).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import comcore


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=30)
    parser.add_argument("--queries", type=int, default=100)
    parser.add_argument("--priors", type=int, default=12)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--object", default="Obj7")
    args = parser.parse_args(argv)

    import simulators
    from predictors import AnpPredictor

    rng = np.random.default_rng(0)
    sim = simulators.random_simulator(args.object, friction="low", rng=rng)
    pushes = comcore.sample_pushes(sim.mask, args.priors + args.queries, cone=0.3, rng=rng)
    motions = sim.push_motions(pushes[: args.priors])
    priors = list(zip(pushes[: args.priors], motions))
    queries = pushes[args.priors :]
    anp = AnpPredictor(threads=args.threads)
    anp.predict(sim.mask, queries, priors)  # warm up (weights, allocator)
    ms = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        anp.predict(sim.mask, queries, priors)
        ms.append(1e3 * (time.perf_counter() - t0))
    p10, p50, p90 = np.percentile(ms, [10, 50, 90])
    print(
        f"AnpPredictor.predict: {len(queries)} queries from {args.priors} priors on "
        f"{args.object}, {args.threads} thread(s): median {p50:.1f} ms "
        f"(p10 {p10:.1f}, p90 {p90:.1f}, n={args.repeats})"
    )


if __name__ == "__main__":
    main()
