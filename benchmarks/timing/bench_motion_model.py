"""Timing of comcore.LimitSurfaceModel in one active step (the budget: under 100 ms).

One active step asks the model about ONE push for every live CoM hypothesis
and every friction value: here every pixel of a benchmark mask (all alive:
the first push, the worst case) and the active estimator's 6 friction values
(``mu`` unknown), one ``predict_hypotheses`` call per friction value, as
``comcore.estimate_active`` makes them. Timed per push on ``--pushes``
different pushes after a warm-up push on the same mask (the per-mask tables
are built once per mask; ``cold`` is that first push); median of
``--repeats`` masks' pushes. The ellipsoid model is timed the same way for
comparison.

Example::

    PYTHONPATH=. nice -n 10 python benchmarks/timing/bench_motion_model.py --repeats 3
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _masks import ellipse_mask  # this folder is on the path when run as a script

import comcore
import simulators
from predictors import EllipsoidPredictor


def largest_object(resolution):
    """The benchmark object whose mask has the most pixels, and that mask."""
    best = None
    for name in simulators.BENCHMARK_OBJECTS:
        mask = simulators.random_simulator(name, rng=0, resolution=resolution).mask
        if best is None or mask.area_px > best[1].area_px:
            best = (name, mask)
    return best


def step_times(models, mask, pushes, mus):
    """Wall and CPU seconds of one active step (all pixels x all mu x all models) per push."""
    wall, cpu = [], []
    for push in pushes:
        t0, c0 = time.perf_counter(), time.process_time()
        for mu in mus:
            for model in models:
                model.predict_hypotheses(mask, push[None], mask.pixels, float(mu))
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return np.array(wall), np.array(cpu)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--object", default=None, help="benchmark object (default: the largest)")
    parser.add_argument(
        "--pixels", type=int, default=None, help="time an ellipse of about this many pixels instead"
    )
    parser.add_argument("--resolution", type=float, default=comcore.conventions.DEFAULT_RESOLUTION,
                        help="camera resolution, metres per pixel (benchmark objects)")  # fmt: skip
    parser.add_argument("--pushes", type=int, default=5, help="timed pushes per mask")
    parser.add_argument("--repeats", type=int, default=3, help="fresh copies of the mask")
    parser.add_argument("--no-ellipsoid", action="store_true")
    args = parser.parse_args(argv)
    if args.pixels is not None:
        name, mask = "ellipse", ellipse_mask(args.pixels)
    elif args.object is None:
        name, mask = largest_object(args.resolution)
    else:
        sim = simulators.random_simulator(args.object, rng=0, resolution=args.resolution)
        name, mask = args.object, sim.mask
    mus = comcore.Likelihood().mus
    radius = simulators.DEFAULT_PUSHER_RADIUS
    models = {
        "LimitSurfaceModel": [comcore.LimitSurfaceModel(pusher_radius=radius)],
        "family (2 models)": list(comcore.LimitSurfaceModel.family(pusher_radius=radius)),
    }
    if not args.no_ellipsoid:
        models["EllipsoidPredictor"] = [EllipsoidPredictor(pusher_radius=radius)]
    print(f"{name}: {mask.area_px} pixels x {len(mus)} friction values, one push per step, "
          f"{args.pushes} pushes x {args.repeats} masks")  # fmt: skip
    for label, model in models.items():  # a list of models, weighed together
        cold, walls, cpus = [], [], []
        for r in range(args.repeats):
            fresh = comcore.Mask(mask.data.copy(), mask.resolution)  # new per-mask tables
            pushes = comcore.sample_pushes(fresh, args.pushes + 1, rng=r)
            w, _ = step_times(model, fresh, pushes[:1], mus)
            cold.append(w[0])
            w, c = step_times(model, fresh, pushes[1:], mus)
            walls.append(w)
            cpus.append(c)
        walls, cpus = np.concatenate(walls), np.concatenate(cpus)
        print(f"{label:19s} one step: median {1e3 * np.median(walls):6.1f} ms wall "
              f"(p90 {1e3 * np.percentile(walls, 90):.1f}), {1e3 * np.median(cpus):6.1f} ms CPU; "
              f"cold (first push on a mask) {1e3 * np.median(cold):.0f} ms")  # fmt: skip


if __name__ == "__main__":
    main()
