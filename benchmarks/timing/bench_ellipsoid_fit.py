"""Time EllipsoidPredictor.fit: the CoM and mu_contact fitted to prior pushes, CPU.

Run: ``python benchmarks/timing/bench_ellipsoid_fit.py [--object Obj19] [--priors 12]
[--repeats 10]``.

The priors are simulated pushes on a benchmark object (Obj19: about 2,000
mask pixels). Prints the median and the 10th/90th percentile wall time of one
``fit`` call, twice: ``cold``, each call on a fresh copy of the mask (what a
new object costs: the mask's support points, distance field and
characteristic lengths are computed and cached per mask object), and
``warm``, repeated calls on the same mask. Needs the ``sim`` extra (the
priors come from the simulator).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import comcore


def _percentiles(seconds) -> str:
    p10, p50, p90 = np.percentile(seconds, [10, 50, 90])
    return f"median {p50:.3f} s (p10 {p10:.3f}, p90 {p90:.3f})"


def main(argv=None) -> None:
    """Parse the options, time the fits and print one line per kind."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--object", default="Obj19", help="benchmark object (default Obj19)")
    parser.add_argument("--priors", type=int, default=12, help="prior pushes to fit to")
    parser.add_argument("--repeats", type=int, default=10, help="fits timed per kind")
    parser.add_argument("--friction", choices=("low", "high"), default="low")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    for name in ("priors", "repeats"):
        if getattr(args, name) < 1:
            parser.error(f"--{name} must be at least 1, got {getattr(args, name)}")

    import simulators
    from predictors import EllipsoidPredictor

    sim = simulators.random_simulator(args.object, friction=args.friction, rng=args.seed)
    pushes = comcore.sample_pushes(sim.mask, args.priors, cone=0.5, rng=args.seed)
    priors = list(zip(pushes, sim.push_motions(pushes)))
    predictor = EllipsoidPredictor(pusher_radius=sim.pusher_radius)

    def fresh_mask() -> comcore.Mask:  # a new object: no per-mask cache applies
        return comcore.Mask(sim.mask.data.copy(), resolution=sim.mask.resolution)

    predictor.fit(fresh_mask(), priors)  # warm up imports and numpy
    cold, warm = [], []
    for _ in range(args.repeats):
        mask = fresh_mask()
        t0 = time.perf_counter()
        predictor.fit(mask, priors)
        cold.append(time.perf_counter() - t0)
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        fit = predictor.fit(sim.mask, priors)
        warm.append(time.perf_counter() - t0)
    error_mm = 1e3 * sim.mask.resolution * float(np.hypot(*(np.subtract(fit.com, sim.com_px))))
    head = (f"EllipsoidPredictor.fit: {args.priors} priors on {args.object} "
            f"({sim.mask.area_px} px, {args.friction} friction), n={args.repeats}")  # fmt: skip
    print(head)
    print(f"  cold (fresh mask): {_percentiles(cold)}")
    print(f"  warm (same mask):  {_percentiles(warm)}")
    print(f"  fitted CoM {error_mm:.1f} mm from the true one")


if __name__ == "__main__":
    main()
