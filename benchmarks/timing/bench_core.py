"""Time the paper's two estimators on a 200 x 200 mask with 100 actions.

Run: ``python benchmarks/timing/bench_core.py [--repeats 50] [--actions 100] [--size 200]``.
Prints the median and the 10th/90th percentile wall time of each estimator.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import comcore


def make_case(size: int, n_actions: int, seed: int = 0):
    """A filled ellipse covering most of a size x size image, random pushes, toy motions."""
    yy, xx = np.mgrid[0:size, 0:size]
    c = (size - 1) / 2
    img = ((xx - c) / (0.45 * size)) ** 2 + ((yy - c) / (0.35 * size)) ** 2 <= 1
    mask = comcore.Mask(img, resolution=0.0025)
    rng = np.random.default_rng(seed)
    actions = comcore.sample_pushes(mask, n_actions, cone=0.5, travel=0.03, rng=rng)
    com = np.array([c + 9.0, c - 5.0])
    lever = comcore.geometry.signed_line_distance([com], actions)[0]
    motions = np.column_stack([0.004 * lever, np.zeros(n_actions), np.zeros(n_actions)])
    return mask, actions, motions


def time_it(fn, repeats: int) -> np.ndarray:
    fn()  # warm caches (mask pixels, outline normals)
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return np.array(out) * 1e3


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=50)
    parser.add_argument("--actions", type=int, default=100)
    parser.add_argument("--size", type=int, default=200)
    args = parser.parse_args(argv)
    mask, actions, motions = make_case(args.size, args.actions)
    print(f"mask {mask.shape} with {mask.area_px} object pixels, {args.actions} actions")
    for name, fn in [
        ("estimate_heatmap (Alg. 1)", lambda: comcore.estimate_heatmap(mask, actions, motions)),
        (
            "estimate_progressive (Alg. 2)",
            lambda: comcore.estimate_progressive(mask, actions, motions),
        ),
    ]:
        ms = time_it(fn, args.repeats)
        p10, p50, p90 = np.percentile(ms, [10, 50, 90])
        print(f"{name:32s} median {p50:6.2f} ms   (p10 {p10:.2f}, p90 {p90:.2f}, n={args.repeats})")


if __name__ == "__main__":
    main()
