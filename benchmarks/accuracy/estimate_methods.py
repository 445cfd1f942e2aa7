"""How ``comcore estimate``'s methods fare on recorded pushes, with senses observed wrong.

Each case: a benchmark object drawn by ``simulators.random_simulator`` (low friction), N
random pushes (``comcore.sample_pushes``, cone 0.3 rad) run in the simulator from the initial
pose, as a recording would hold them; then ``k`` of the pushes that turned the object have
their rotation's sign flipped (a tracking error). Every method of ``comcore estimate`` runs
on the same recording (as ``comcore.cli.estimate.estimate`` calls it); the table gives the
CoM error (cm) and, for the posterior, how often the true CoM lies in its 90 % credible
region. ``--model`` is the posterior's motion model (``comcore estimate --model``): the
default ``limit-surface``, or ``none`` (the Voting Theorem alone: ``comcore estimate``'s
default before its posterior took the active session's motion model).

    python benchmarks/accuracy/estimate_methods.py               # 20 objects x seeds 0, 1, 2
    python benchmarks/accuracy/estimate_methods.py --model none  # the posterior without the model
    python benchmarks/accuracy/estimate_methods.py --objects Obj3 --seeds 0 --flips 0  # quick look
    python benchmarks/accuracy/estimate_methods.py --flips 0,all --model none  # every sign flipped

``--flips all`` flips the sign of every push's rotation (theta with the y axis up, the
mistake docs/explanation/conventions.md warns about); the last lines count the recordings whose sign
``comcore estimate`` calls flipped (:func:`comcore.cli.estimate.sign_flip_nats`) and the
statuses: ``ok`` and ``wide`` (consistent, the region within ``target_radius`` or wider;
the two together are what ``ok`` alone said before ``wide`` existed).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy import ndimage

import comcore
from comcore.cli.estimate import (
    BOOTSTRAP,
    MODELS,
    SIGN_FLIP_NATS,
    SYSTEMATIC_ERROR,
    estimate,
    methods,
    sign_flip_nats,
)


def cases(objects, seeds, n_pushes):
    import simulators

    for name in objects:
        for seed in seeds:
            rng = np.random.default_rng([seed, int(name[3:])])
            sim = simulators.random_simulator(name, friction="low", rng=rng)
            actions = comcore.sample_pushes(sim.mask, n_pushes, cone=0.3, rng=rng)
            yield name, seed, sim, actions, np.asarray(sim.push_motions(actions), float), rng


def main(argv=None) -> None:
    import simulators

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", default=",".join(simulators.BENCHMARK_OBJECTS))
    parser.add_argument(
        "--seeds", default="0,1,2", help="seeds per object, e.g. 0 or 1,2"
    )
    parser.add_argument(
        "--systematic-error", type=float, default=SYSTEMATIC_ERROR,
        help="the posterior's (metres; comcore estimate --systematic-error)",
    )  # fmt: skip
    parser.add_argument(
        "--bootstrap", type=int, default=BOOTSTRAP,
        help="the posterior's resamplings for its region (comcore estimate --bootstrap)",
    )  # fmt: skip
    parser.add_argument("--pushes", type=int, default=40)
    parser.add_argument(
        "--flips", default="0,1,3", help="wrong senses per recording ('all': every sign flipped)"
    )
    parser.add_argument("--model", choices=MODELS, default=MODELS[0], help="the posterior's")
    args = parser.parse_args(argv)
    seeds = [int(v) for v in args.seeds.split(",") if v.strip()]
    objects = [o.strip() for o in args.objects.split(",") if o.strip()]
    flips = [k.strip() if k.strip() == "all" else int(k) for k in args.flips.split(",")]
    names = [m for m in methods() if m != "alg2-rotation"]
    errors = {(m, k): [] for m in names for k in flips}
    covered = {k: [] for k in flips}
    near = {k: [] for k in flips}  # the truth's pixel within a pixel of the region
    statuses = {(m, k): [] for m in names for k in flips}
    flagged = {k: 0 for k in flips}  # comcore estimate's check of theta's sign
    seconds = {m: [] for m in names}
    start = time.perf_counter()
    for _, _, sim, actions, motions, rng in cases(objects, seeds, args.pushes):
        turned = np.flatnonzero(np.abs(motions[:, 0]) > 0.01)
        cm = 100 * sim.mask.resolution
        for k in flips:
            observed = motions.copy()
            if k == "all":
                observed[:, 0] *= -1
            else:
                wrong = rng.choice(turned, size=min(k, len(turned)), replace=False)
                observed[wrong, 0] *= -1
            flagged[k] += sign_flip_nats(sim.mask, actions, observed) > SIGN_FLIP_NATS
            for m in names:
                t0 = time.perf_counter()
                est = estimate(sim.mask, actions, observed, m, model=args.model,
                               systematic_error=args.systematic_error,
                               bootstrap=args.bootstrap)  # fmt: skip
                seconds[m].append(time.perf_counter() - t0)
                errors[m, k].append(est.error_px(sim.com_px) * cm)
                statuses[m, k].append(est.status)
                if m == "posterior":
                    x, y = np.round(sim.com_px).astype(int)
                    covered[k].append(bool(est.region[y, x]))
                    near[k].append(bool(ndimage.binary_dilation(est.region)[y, x]))
    n = len(errors[names[0], flips[0]])
    print(f"{n} recordings ({len(objects)} objects x seeds {seeds}), "
          f"{args.pushes} pushes each, posterior --model {args.model} "
          f"--systematic-error {args.systematic_error:g} --bootstrap {args.bootstrap}; "
          f"{time.perf_counter() - start:.0f} s")
    print("| method | wrong senses | mean error (cm) | median (cm) | p90 (cm) "
          "| truth in 90 % region | within a pixel of it |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for m in names:
        for k in flips:
            e = np.asarray(errors[m, k])
            share = f"{100 * np.mean(covered[k]):.0f} %" if m == "posterior" else ""
            close = f"{100 * np.mean(near[k]):.0f} %" if m == "posterior" else ""
            print(f"| {m} | {k} | {e.mean():.2f} | {np.median(e):.2f} | "
                  f"{np.quantile(e, 0.9):.2f} | {share} | {close} |")
    print("time per estimate (median): " + ", ".join(
        f"{m} {1000 * np.median(seconds[m]):.0f} ms" for m in names))
    print("comcore estimate's sign check: " + ", ".join(
        f"{k} wrong: flagged {flagged[k]} of {n}" for k in flips))
    for m in ("posterior", "alg2"):
        print(f"{m} status: " + ", ".join(
            f"{k} wrong: {statuses[m, k].count('ok')} ok, {statuses[m, k].count('wide')} wide "
            f"of {len(statuses[m, k])}" for k in flips))


if __name__ == "__main__":
    main()
