"""Accuracy of comcore.estimate_active on the benchmark objects, with the simulator as the robot.

Each trial draws a random mass distribution and contact friction in the friction
class (``simulators.random_simulator``), lets the estimator push the simulated
object (``push = lambda a: sim.push(a).motion``: every push from the initial pose)
and compares the estimate with the simulator's true CoM. The estimator never sees
the simulator or the true CoM. With ``--flip p`` each observed rotation has its
sign flipped with probability ``p`` (the translation is left as it was).

Prints a Markdown table (per friction class: mean/median/max error in cm, mean
pushes, stop statuses) and, with ``--per-object``, one row per object.

Example::

    PYTHONPATH=. nice -n 10 python benchmarks/accuracy/eval_active.py --objects Obj1 Obj7 --trials 1
"""

from __future__ import annotations

import argparse
import json
import time
from collections import Counter

import numpy as np

import comcore
import comcore.bench


def _model(name: str, limit_surfaces):
    if name == "none":
        return None
    if name == "ellipsoid":
        import simulators
        from predictors import EllipsoidPredictor

        # The robot knows its pusher's radius; the rest is the model's defaults, or a
        # mixture of limit-surface variants (weighed by the estimator like the friction).
        radius = simulators.DEFAULT_PUSHER_RADIUS
        if not limit_surfaces:
            return EllipsoidPredictor(pusher_radius=radius)
        return [EllipsoidPredictor(pusher_radius=radius, limit_surface=s) for s in limit_surfaces]
    raise ValueError(f"--model must be 'ellipsoid' or 'none', got {name!r}")


def make_simulator(name, friction, seed, resolution=None):
    """The trial's random simulator (a draw the simulator refuses is redrawn: said so)."""
    import simulators

    extra = {} if resolution is None else {"resolution": resolution}

    def said(attempt, e):
        print(f"  {name} {friction} seed {seed}: random_simulator failed ({e}); redrawing")

    return simulators.accepted_random_simulator(
        name, friction, rng=lambda attempt: [seed, attempt], on_refusal=said, **extra
    )


def run_trial(name, friction, seed, args, model):
    """One estimation on a fresh random simulator; returns a dict of results."""

    sim = make_simulator(name, friction, seed, args.resolution)
    flip_rng = np.random.default_rng([seed, 1])
    flips = []

    def push(action):
        if args.answer is not None:  # a broken robot (or tracker): the same answer every time
            return comcore.Motion(args.answer, 0.0, 0.0)
        motion = sim.push(action).motion
        flip = bool(flip_rng.random() < args.flip)
        flips.append(flip)
        return comcore.Motion(-motion.theta, motion.tx, motion.ty) if flip else motion

    kwargs = {"selection": args.selection, "model_weight": args.model_weight}
    if args.flip_prob is not None:
        kwargs["flip_prob"] = args.flip_prob
    for key in ("theta_noise", "translation_error", "motion_noise"):
        if getattr(args, key) is not None:
            kwargs[key] = tuple(getattr(args, key))
    if args.pusher_error is not None:
        kwargs["pusher_error"] = args.pusher_error
    if args.target_radius is not None:
        kwargs["target_radius"] = args.target_radius
    if args.max_pushes is not None:
        kwargs["max_pushes"] = args.max_pushes
    start = time.perf_counter()
    est = comcore.estimate_active(
        sim.mask,
        push,
        model=model,
        rng=np.random.default_rng([seed, 2]),
        **comcore.bench.option_groups(**kwargs, cone=args.cone),
    )
    cm = 100 * sim.mask.resolution
    return {
        "object": name,
        "friction": friction,
        "seed": int(seed),
        "mu": float(sim.mu_contact),
        "error_cm": est.error_px(sim.com_px) * cm,
        "prior_error_cm": float(np.hypot(*np.subtract(sim.mask.centroid, sim.com_px))) * cm,
        "pushes": len(est.used),
        "flips": int(sum(flips)),
        "status": est.status,
        "radius_cm": est.posterior.credible_radius_px * cm,
        "in_region": bool(est.region[round(sim.com_px[1]), round(sim.com_px[0])]),
        "seconds": time.perf_counter() - start,
        "history_error_cm": [
            float(np.hypot(*np.subtract(h.com, sim.com_px))) * cm for h in est.posterior.history
        ],
        "history_radius_cm": [h.credible_radius_px * cm for h in est.posterior.history],
    }


def plot_posterior(name, friction, seed, args, model, path):
    """Plot the posterior after each push of one trial (re-run with growing budgets)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sim = make_simulator(name, friction, seed)
    cands = comcore.sample_pushes(
        sim.mask, 200, cone=args.cone, rng=np.random.default_rng([seed, 2])
    )
    choice = comcore.PushChoice(selection=args.selection)
    kwargs = {"model": model, "choice": choice}
    if args.max_pushes is not None:
        kwargs["stop"] = comcore.StopRule(max_pushes=args.max_pushes)
    final = comcore.estimate_active(sim.mask, lambda a: sim.push(a).motion, cands, **kwargs)
    steps = len(final.used)
    fig, axes = plt.subplots(1, steps + 1, figsize=(2.6 * (steps + 1), 2.9))
    ys, xs = np.nonzero(sim.mask.data)
    box = (xs.min() - 3, xs.max() + 3, ys.max() + 3, ys.min() - 3)
    for k, ax in enumerate(np.atleast_1d(axes)):
        kwargs["stop"] = comcore.StopRule(max_pushes=k)
        est = comcore.estimate_active(sim.mask, lambda a: sim.push(a).motion, cands, **kwargs)
        post = np.ma.masked_where(~sim.mask.data, est.posterior.image)
        ax.imshow(sim.mask.data, cmap="Greys", alpha=0.25)
        ax.imshow(post, cmap="viridis")
        ax.contour(est.region, levels=[0.5], colors="w", linewidths=0.8)
        for a in (p.action for p in est.pushes):
            ax.annotate("", a[2:], a[:2], arrowprops={"arrowstyle": "->", "color": "tab:red"})
        ax.plot(*sim.com_px, "r+", ms=10, mew=1.5)
        ax.plot(*est.com, "wx", ms=7, mew=1.5)
        err = est.error_px(sim.com_px) * sim.mask.resolution * 100
        radius = est.posterior.credible_radius_px * sim.mask.resolution * 100
        ax.set_title(f"{k} pushes\nerr {err:.2f} cm, r90 {radius:.2f} cm", fontsize=8)
        ax.set_xlim(box[0], box[1])
        ax.set_ylim(box[2], box[3])
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle(
        f"{name}, {friction} friction (mu={sim.mu_contact:.2f}): posterior push by push "
        "(+ true CoM, x estimate, white: 90% region)",
        fontsize=9,
    )
    fig.tight_layout(rect=(0, 0, 1, 0.86))
    fig.savefig(path, dpi=110)
    print(f"saved {path}")


def summarise(rows, key):
    """Markdown table of the rows grouped by ``key``."""
    lines = [
        f"| {key} | trials | mean err (cm) | median | max | prior err (cm) | mean pushes "
        "| in 90% region | statuses |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for group in dict.fromkeys(r[key] for r in rows):
        sel = [r for r in rows if r[key] == group]
        err = np.array([r["error_cm"] for r in sel])
        status = Counter(r["status"] for r in sel)
        lines.append(
            f"| {group} | {len(sel)} | {err.mean():.3f} | {np.median(err):.3f} | {err.max():.3f}"
            f" | {np.mean([r['prior_error_cm'] for r in sel]):.3f}"
            f" | {np.mean([r['pushes'] for r in sel]):.2f}"
            f" | {np.mean([r['in_region'] for r in sel]):.0%}"
            f" | {', '.join(f'{k} {v}' for k, v in sorted(status.items()))} |"
        )
    return "\n".join(lines)


def main(argv=None):
    import simulators

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", nargs="+", default=list(simulators.BENCHMARK_OBJECTS))
    parser.add_argument("--friction", nargs="+", default=["low", "high"])
    parser.add_argument("--trials", type=int, default=1, help="trials per object and class")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--model", default="ellipsoid", help="'ellipsoid' or 'none'")
    parser.add_argument(
        "--limit-surfaces", nargs="*", default=None, help="ellipsoid variants to weigh"
    )
    parser.add_argument("--theta-noise", type=float, nargs=2, default=None)
    parser.add_argument(
        "--translation-error", type=float, nargs=2, default=None, help="metres, relative"
    )
    parser.add_argument("--pusher-error", type=float, default=None, help="estimator's, metres")
    parser.add_argument(
        "--motion-noise", type=float, nargs=2, default=None, help="estimator's: rad, metres"
    )
    parser.add_argument("--resolution", type=float, default=None, help="camera m/px")
    parser.add_argument(
        "--answer", type=float, default=None, help="the robot always answers (THETA, 0, 0)"
    )
    parser.add_argument(
        "--max-pushes", type=int, default=None, help="budget (default: the estimator's)"
    )
    parser.add_argument("--target-radius", type=float, default=None, help="metres")
    parser.add_argument("--flip", type=float, default=0.0, help="probability to flip a sense")
    parser.add_argument("--flip-prob", type=float, default=None, help="estimator's flip_prob")
    parser.add_argument("--cone", type=float, default=0.0)
    parser.add_argument("--selection", default="sense", help="sense or model")
    parser.add_argument("--model-weight", type=float, default=1.0, help="likelihood power")
    parser.add_argument("--per-object", action="store_true")
    parser.add_argument("--out", default=None, help="write the rows as JSON here")
    parser.add_argument("--plot", default=None, help="plot the first trial's posterior here")
    args = parser.parse_args(argv)
    model = _model(args.model, args.limit_surfaces)
    if args.plot:
        seed = int(np.random.SeedSequence([args.seed, 0]).generate_state(1)[0])
        plot_posterior(args.objects[0], args.friction[0], seed, args, model, args.plot)
        return
    rows = []
    for k, (name, friction, _) in enumerate(
        (n, f, t) for f in args.friction for n in args.objects for t in range(args.trials)
    ):
        seed = int(np.random.SeedSequence([args.seed, k]).generate_state(1)[0])
        rows.append(run_trial(name, friction, seed, args, model))
        r = rows[-1]
        print(
            f"{name:6s} {friction:4s} mu={r['mu']:.2f} err={r['error_cm']:.3f} cm "
            f"(prior {r['prior_error_cm']:.2f}) pushes={r['pushes']} flips={r['flips']} "
            f"{r['status']} r90={r['radius_cm']:.2f} cm {r['seconds']:.1f}s",
            flush=True,
        )
    print()
    print(f"model={args.model} flip={args.flip} seed={args.seed} trials={args.trials}")
    print(summarise(rows, "friction"))
    if args.per_object:
        print()
        print(summarise(rows, "object"))
    if args.out:
        with open(args.out, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
