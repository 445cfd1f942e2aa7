"""How Alg. 1's error depends on the candidate count, length scale and threshold.

Each trial simulates max(--counts) oracle pushes once (cached in --cache), then
runs Alg. 1 (and Alg. 2 and the centroid for reference) on the first n of them
for every n and parameter setting. Two heat maps: the paper's sum
``S = sum_a exp(-d/l) |theta_a|`` (``alg1``) and, for comparison only, its
line-density-normalised mean ``S / sum_a exp(-d/l)`` (``alg1-mean``; not in
comcore). Prints mean / median error in cm and writes them as JSON.

    PYTHONPATH=. nice -n 10 python benchmarks/accuracy/alg1_study.py --trials 4 \\
        --out alg1_study.json
"""

from __future__ import annotations

import argparse
import itertools
import json
import time
from collections import defaultdict

import numpy as np

import comcore
from comcore.bench import TrialSpec
from comcore.geometry._regions import estimate_from_region  # no public equivalent

OBJECTS = ("Obj1", "Obj4", "Obj7", "Obj12", "Obj16", "Obj19")


def trials(args, n_max: int):
    """(mask, true CoM px, candidates, motions) per trial, simulated once and cached."""
    key = f"{args.objects}|{args.trials}|{args.seed}|{args.cone}|{n_max}"
    try:
        data = np.load(args.cache, allow_pickle=False)
        if str(data["key"]) == key:
            n = int(data["n"])
            res = [float(r) for r in data["resolution"]]
            return [
                (comcore.Mask(data[f"mask{i}"], res[i]), tuple(data["com"][i]),
                 data["cands"][i], data["motions"][i])
                for i in range(n)
            ]  # fmt: skip
    except (OSError, KeyError):
        pass
    out = []
    start = time.perf_counter()
    for obj, friction, trial in itertools.product(
        args.objects.split(","), ("low", "high"), range(args.trials)
    ):
        spec = TrialSpec(obj, friction, trial, seed=args.seed, cone=args.cone)
        sim = spec.simulator()
        mask = sim.mask
        cands = comcore.sample_pushes(mask, n_max, cone=args.cone, rng=spec.rng("cand"))
        out.append((mask, sim.com_px, cands, sim.push_motions(cands)))
        print(f"{obj} {friction} {trial} simulated at {time.perf_counter() - start:.0f} s")
    arrays = {f"mask{i}": t[0].data for i, t in enumerate(out)}
    np.savez_compressed(
        args.cache, key=key, n=len(out), resolution=[t[0].resolution for t in out],
        com=[t[1] for t in out], cands=[t[2] for t in out], motions=[t[3] for t in out],
        **arrays,
    )  # fmt: skip
    return out


def mean_heatmap_estimate(mask, actions, motions, threshold, length_scale):
    """Alg. 1 with the heat map divided by the local line density (not the paper's)."""
    distance = comcore.geometry.signed_line_distance(mask.pixels, actions)
    weight = np.exp(-np.abs(distance) / length_scale)
    score = weight @ np.abs(motions[:, 0]) / (weight.sum(axis=1) + 1e-3)
    lo, hi = score.min(), score.max()
    heat = np.zeros(mask.shape)
    heat[mask.data] = (score - lo) / (hi - lo) if hi > lo else 0.0
    region = comcore.geometry.largest_component(mask.data & (heat < threshold))
    return estimate_from_region(mask, region)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", default=",".join(OBJECTS))
    parser.add_argument("--trials", type=int, default=5)
    parser.add_argument("--counts", default="20,60,150,400")
    parser.add_argument("--length-scales", default="1,3,10")
    parser.add_argument("--thresholds", default="0.05,0.1,0.2,0.3")
    parser.add_argument("--cone", type=float, default=0.3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", default="alg1_study.json")
    parser.add_argument("--cache", default="alg1_study_cache.npz", help="simulated trials")
    args = parser.parse_args()
    counts = [int(v) for v in args.counts.split(",")]
    scales = [float(v) for v in args.length_scales.split(",")]
    thresholds = [float(v) for v in args.thresholds.split(",")]
    errors: dict[tuple, list[float]] = defaultdict(list)
    for mask, com, cands, motions in trials(args, max(counts)):
        cm = 100 * mask.resolution
        for n in counts:
            acts, mots = cands[:n], motions[:n]
            est = comcore.estimate_progressive(mask, acts, mots)
            errors[("alg2", n, 0.0, 0.0)].append(est.error_px(com) * cm)
            errors[("centroid", n, 0.0, 0.0)].append(
                float(np.hypot(*np.subtract(mask.centroid, com))) * cm
            )
            for scale, threshold in itertools.product(scales, thresholds):
                est = comcore.estimate_heatmap(
                    mask, acts, mots, threshold=threshold, length_scale=scale
                )
                errors[("alg1", n, scale, threshold)].append(est.error_px(com) * cm)
                est = mean_heatmap_estimate(mask, acts, mots, threshold, scale)
                errors[("alg1-mean", n, scale, threshold)].append(est.error_px(com) * cm)
    table = [
        {
            "estimator": k[0], "candidates": k[1], "length_scale": k[2], "threshold": k[3],
            "n": len(v), "mean_cm": float(np.mean(v)), "median_cm": float(np.median(v)),
        }
        for k, v in sorted(errors.items())
    ]  # fmt: skip
    with open(args.out, "w", encoding="utf-8") as f:
        json.dump({"args": vars(args), "rows": table}, f, indent=1)
    print("estimator candidates length_scale threshold n mean_cm median_cm")
    for r in table:
        print(
            f"{r['estimator']:8s} {r['candidates']:4d} {r['length_scale']:5.1f} "
            f"{r['threshold']:5.2f} {r['n']:4d} {r['mean_cm']:6.2f} {r['median_cm']:6.2f}"
        )


if __name__ == "__main__":
    main()
