"""Score recorded pushes again under other likelihood options (the active likelihood's calibration).

``benchmarks/calibration/tune_active.py --keep-pushes runs.pkl`` records every run's mask
and evidence pushes; this script scores them again with
:func:`comcore.estimate_posterior` under each variant of ``--variants`` and
reports per condition and variant: the mean error (cm), the share of runs
whose 90 % credible region holds the true CoM, the quantiles of the truth's
HPD rank (the posterior mass more probable than the truth's pixel: uniform
on [0, 1] for an honest posterior) and the mean radius (mm) of the 90 %
region, which sets when the estimator stops. ``--prefixes`` also scores the
first k pushes of every run (calibration as the pushes accumulate).

The pushes were chosen by the recording's own likelihood; a variant changes
only how they are scored, so this measures calibration, not push counts.
Tune on seed 1 (or others); the figures in docs/ are measured on seed 0.

Usage::

    PYTHONPATH=. nice -n 10 python benchmarks/calibration/tune_active.py --seed 1 --trials 2 \\
        --conditions exact,pusher-error --keep-pushes runs.pkl
    PYTHONPATH=. python benchmarks/calibration/rescore_pushes.py runs.pkl \\
        --variants '{"default": {}, "w1": {"model_weight": 1.0}}'
"""

from __future__ import annotations

import argparse
import json
import pickle
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np
from replay import executed, has_evidence, posterior_options, replay  # this folder is on the path

import comcore


def _score(job) -> list[tuple]:
    """(variant, k, error cm, credible level of the truth, radius mm, scale, power) per variant."""
    kept, variants, prefixes = job
    resolution = kept["resolution"]
    n = len(executed(kept))
    ks = range(1, n + 1) if prefixes else [n]
    out = []
    for name, flat in variants.items():
        options = posterior_options(flat)
        likelihood = options.get("likelihood", comcore.Likelihood())
        factors = np.asarray(likelihood.model_scales, dtype=float)
        powers = np.asarray(likelihood.model_weight, dtype=float)
        for k in ks:
            est = replay(kept, options, k)
            err = float(np.hypot(*(np.asarray(est.com) - kept["true_px"]))) * resolution
            radius_mm = est.posterior.credible_radius_px * resolution * 1000
            scale = float(np.exp(est.posterior.scale_posterior @ np.log(factors)))
            weights = est.posterior.model_weight_posterior
            power = float(weights @ powers) if options["model"] else float("nan")
            level = comcore.credible_level(est, kept["true_px"])
            out.append((name, k, 100 * err, level, radius_mm, scale, power))
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("runs", help="pickle written by tune_active.py --keep-pushes")
    p.add_argument("--variants", default='{"default": {}}', help="JSON: name -> options")
    p.add_argument("--conditions", default=None, help="only these (comma-separated)")
    p.add_argument("--prefixes", action="store_true", help="also score the first k pushes")
    p.add_argument("--workers", type=int, default=2)
    args = p.parse_args(argv)
    variants = json.loads(args.variants)
    with open(args.runs, "rb") as f:
        rows = [r for r in pickle.load(f) if r.get("pushes_kept") is not None]
    if args.conditions:
        wanted = set(args.conditions.split(","))
        rows = [r for r in rows if r["condition"] in wanted]
    rows = [r for r in rows if has_evidence(r["pushes_kept"])]
    start = time.time()
    jobs = [(r["pushes_kept"], variants, args.prefixes) for r in rows]
    with ProcessPoolExecutor(args.workers) as pool:
        scored = list(pool.map(_score, jobs, chunksize=2))
    for cond in dict.fromkeys(r["condition"] for r in rows):
        idx = [i for i, r in enumerate(rows) if r["condition"] == cond]
        for name in variants:
            got = [s for i in idx for s in scored[i] if s[0] == name]
            ks = sorted({s[1] for s in got}) if args.prefixes else [None]
            for k in ks:
                if k is None:
                    sel = [max((s for s in scored[i] if s[0] == name), key=lambda s: s[1])
                           for i in idx]
                else:
                    sel = [s for s in got if s[1] == k]
                arr = np.array([s[2:] for s in sel])
                q = np.quantile(arr[:, 1], [0.25, 0.5, 0.75])
                tag = "final" if k is None else f"k={k}"
                print(
                    f"{cond:15s} {name:22s} {tag:6s} n={len(arr):3d} err {arr[:, 0].mean():.3f}"
                    f" cov90 {100 * np.mean(arr[:, 1] <= 0.9):3.0f}% cov50"
                    f" {100 * np.mean(arr[:, 1] <= 0.5):3.0f}% hpd q25/50/75 {q[0]:.2f}/"
                    f"{q[1]:.2f}/{q[2]:.2f} radius {arr[:, 2].mean():.2f} mm"
                    f" scale {np.exp(np.log(arr[:, 3]).mean()):.2f} power {np.mean(arr[:, 4]):.2f}"
                )
    print(f"{len(rows)} runs, {time.time() - start:.0f} s")


if __name__ == "__main__":
    main()
