"""Push count against error for every stop radius, per realism condition, offline.

Records runs that never stop early with ``tune_active.py --keep-pushes`` (the
label ``active(target_radius=1e-6,min_information=0.0)``: the defaults, all 5
pushes), scores every prefix of each run's pushes again with
:func:`comcore.estimate_posterior` (the defaults' model and likelihood: for a
run that reset the object that is the session's own posterior after k pushes)
and evaluates each rule "stop at the first k whose 90 % region's radius is at
most r, else after the budget" on the same pushes: the choice of pushes does
not depend on the stop rule. Prints per rule and condition the mean error
(cm), mean pushes, the share of runs whose region held the CoM where the rule
stopped, and the share that stopped ``ok`` (before the budget) over 1 cm off.

Usage::

    PYTHONPATH=. python benchmarks/calibration/tune_active.py --seed 1 --trials 2 \\
        --conditions exact,pymunk,pusher-error \\
        --estimators "active(target_radius=1e-6,min_information=0.0)" --keep-pushes full.pkl
    PYTHONPATH=. python benchmarks/calibration/stop_frontier.py full.pkl --radii 5,6,7,8,9,10
    PYTHONPATH=. python benchmarks/calibration/stop_frontier.py full.pkl \\
        --options '{"model_weight": 1.0}'

``--options`` scores the same pushes under other likelihood options (those of
:func:`comcore.estimate_posterior`), e.g. the model untempered.
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


def _prefixes(job):
    """(condition, errors cm, holds, history) of a run: after each k = 0..n pushes, and its states.

    The history of the posterior over all n pushes holds every prefix's state (radius,
    counts, consistency): the stop rule reads it; the prefixes' own posteriors give the
    error and whether the region held the truth where the rule stops.
    """
    cond, kept, flat = job
    options = posterior_options(flat)
    n = len(executed(kept))
    full = replay(kept, options)
    errors, holds = [np.nan], [False]  # the prior (k = 0): the rules here never stop there
    for k in range(1, n + 1):
        est = full if k == n else replay(kept, options, k)
        errors.append(100 * est.error_px(kept["true_px"]) * kept["resolution"])
        holds.append(est.region_holds(kept["true_px"]))
    return cond, np.array(errors), np.array(holds), full.posterior.history, kept["resolution"]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("runs", help="pickle written by tune_active.py --keep-pushes")
    p.add_argument("--radii", default="5,6,7,8,9,10", help="stop radii (mm)")
    p.add_argument("--budget", type=int, default=5)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument(
        "--options", default="{}",
        help='JSON of estimate_posterior options to score the pushes with (default: the defaults; '
        '\'{"model": null}\': the Voting Theorem alone)',
    )  # fmt: skip
    args = p.parse_args(argv)
    with open(args.runs, "rb") as f:
        rows = [r for r in pickle.load(f) if r.get("pushes_kept") is not None]
    rows = [r for r in rows if has_evidence(r["pushes_kept"])]
    start = time.time()
    with ProcessPoolExecutor(args.workers) as pool:
        options = json.loads(args.options)
        jobs = [(r["condition"], r["pushes_kept"], options) for r in rows]
        runs = list(pool.map(_prefixes, jobs))
    conds = list(dict.fromkeys(c for c, *_ in runs))
    print(f"{len(runs)} runs, {time.time() - start:.0f} s")
    print("error cm / pushes / 90 % region holds the CoM / ok stops over 1 cm, per condition")
    print("(comcore.StopRule with these radii and --budget, its other fields the defaults)")
    print("| stop radius (mm) | " + " | ".join(conds) + " |")
    print("|---" * (len(conds) + 1) + "|")
    for radius in (float(v) for v in args.radii.split(",")):
        rule = comcore.StopRule(max_pushes=max(args.budget, 1), target_radius=radius / 1000)
        cells = []
        for cond in conds:
            mine = [(e, h, hist, res) for c, e, h, hist, res in runs if c == cond]
            ks = [rule.stop_index(hist, res) for _, _, hist, res in mine]
            err = np.mean([e[k] for (e, *_), k in zip(mine, ks)])
            held = np.mean([h[k] for (_, h, *_), k in zip(mine, ks)])
            bad = np.mean(
                [e[k] > 1.0 and rule.reason(hist[k], res) == "ok"
                 for (e, _, hist, res), k in zip(mine, ks)]
            )  # fmt: skip
            cells.append(f"{err:.3f} / {np.mean(ks):.2f} / {100 * held:.0f} % / {100 * bad:.1f} %")
        print(f"| {radius:g} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
