"""Evaluate motion predictors against the simulator: docs/results/motion.md's figures.

For every benchmark object and friction class, ``--trials`` random trials
(``simulators.random_simulator``: random mass distribution and CoM, contact
friction uniform in the class). Each trial draws ``--priors + --queries``
pushes with ``comcore.sample_pushes`` (3 cm after contact, directions within
``--cone`` of the inward normal); the oracle (``OraclePredictor``, the
simulator of the true object) gives their motions. Every predictor sees the
first ``--priors`` pushes with their true motions and predicts the rest.

Predictors:

* ``ellipsoid (fitted)``: ``EllipsoidPredictor`` fitting the CoM and mu to the priors;
* ``anp``: ``AnpPredictor`` with its shipped weights (skipped when torch or
  the weights are missing);
* ``trivial (centroid)``: the ellipsoid with the CoM at the mask's centroid
  (mu fitted to the priors);
* ``ellipsoid (true CoM, mu)``: the ellipsoid told the truth: the model's own error
  (with ``--variants``, also for each pressure and limit-surface option).

Metrics per friction class: sense-of-rotation accuracy on queries whose true
``|theta| > 5 deg``, mean absolute error of theta (deg) and of the translation
(mm), and the median ratio of predicted to true ``|theta|`` on those queries
(1: no bias in magnitude). Prints a Markdown table and saves a predicted-vs-true theta plot.

Usage::

    python benchmarks/accuracy/eval_predictors.py --trials 1 --seed 0 --out docs/img/pred_theta.png
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import comcore
import simulators
from predictors import EllipsoidPredictor

ROOT = Path(__file__).resolve().parents[2]
BIG_ROTATION_DEG = 5.0


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--trials", type=int, default=1, help="trials per object and friction class")
    p.add_argument("--objects", default="all", help="'all', a count (first N) or names: Obj1,Obj7")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", default=str(ROOT / "docs" / "img" / "pred_theta.png"),
                   help="path of the scatter plot ('none': no plot)")  # fmt: skip
    p.add_argument("--priors", type=int, default=12)
    p.add_argument("--queries", type=int, default=50)
    p.add_argument("--cone", type=float, default=0.5, help="push directions within this (rad)")
    p.add_argument("--anp-weights", default=None, help="ANP weights file (default: shipped)")
    p.add_argument(
        "--variants",
        action="store_true",
        help="also compare the ellipsoid's pressure / limit-surface variants, told the truth",
    )
    p.add_argument("--fit-figure", default=str(ROOT / "docs" / "img" / "pred_fit.png"),
                   help="picture of the first trial's CoM fit ('none': no picture)")  # fmt: skip
    args = p.parse_args(argv)
    if args.objects == "all":
        args.objects = list(simulators.BENCHMARK_OBJECTS)
    elif args.objects.isdigit():
        args.objects = list(simulators.BENCHMARK_OBJECTS[: int(args.objects)])
    else:
        args.objects = [o.strip() for o in args.objects.split(",") if o.strip()]
    for name in ("trials", "priors", "queries"):
        if getattr(args, name) < 1:
            p.error(f"--{name} must be >= 1")
    return args


def load_anp(weights):
    """The ANP predictor, or None and the reason it is unavailable."""
    try:
        from predictors import AnpPredictor

        return AnpPredictor(weights) if weights else AnpPredictor(), ""
    except (ImportError, FileNotFoundError, ValueError) as e:
        return None, f"{type(e).__name__}: {e}"


def simulated_pushes(sim, n, cone, rng):
    """``n`` pushes from ``comcore.sample_pushes`` and their true motions (the oracle's).

    A push the simulator rejects (its disc pusher would overlap the object at the
    start: the sampler's clearance is measured to pixel centres, the disc to the
    true outline) is replaced by a fresh draw. Each push is simulated alone.
    """
    found = simulators.sample_accepted_pushes(sim, n, cone=cone, rng=rng, batched=False)
    return found.pushes, found.motions


VARIANTS = [
    (p, ls) for p in ("uniform", "tilted") for ls in ("rotation", "translation", "directional")
]


def run_trial(sim, args, rng, anp):
    """Predictions of every predictor on one trial: {name: (pred, true)}, and extras."""
    mask = sim.mask
    pushes, motions = simulated_pushes(sim, args.priors + args.queries, args.cone, rng)
    priors = [(comcore.Action(*a), comcore.Motion(*m)) for a, m in zip(pushes, motions)]
    priors = priors[: args.priors]
    queries, true = pushes[args.priors :], motions[args.priors :]
    radius = sim.pusher_radius
    out, extras = {}, {}
    t0 = time.perf_counter()
    fit = EllipsoidPredictor(pusher_radius=radius).fit(mask, priors)
    extras["fit_s"] = time.perf_counter() - t0
    for key, com in (("com_error_mm", fit.com), ("com_mean_error_mm", fit.com_mean)):
        extras[key] = 1000 * mask.resolution * float(np.hypot(*np.subtract(com, sim.com_px)))
    cov = fit.com_cov
    err = np.subtract(fit.com, sim.com_px)
    extras["mahalanobis"] = float(np.sqrt(err @ np.linalg.solve(cov, err)))
    fitted = EllipsoidPredictor(com=fit.com, mu_contact=fit.mu_contact, pusher_radius=radius)
    out["ellipsoid (fitted)"] = fitted.predict(mask, queries)
    if anp is not None:
        out["anp"] = comcore.motion.predict_motions(anp, mask, queries, priors)
    trivial = EllipsoidPredictor(com=mask.centroid, pusher_radius=radius)
    out["trivial (centroid)"] = trivial.predict(mask, queries, priors)
    told = EllipsoidPredictor(com=sim.com_px, mu_contact=sim.mu_contact, pusher_radius=radius)
    out["ellipsoid (true CoM, mu)"] = told.predict(mask, queries)
    for pressure, surface in VARIANTS if args.variants else ():
        model = EllipsoidPredictor(sim.com_px, sim.mu_contact, pressure, surface, radius)
        out[f"model {pressure}/{surface} (true CoM, mu)"] = model.predict(mask, queries)
    extras["fit"], extras["priors"] = fit, priors
    return {k: (v, true) for k, v in out.items()}, extras


def metrics(pred, true, resolution):
    big = np.abs(true[:, 0]) > np.radians(BIG_ROTATION_DEG)
    sense = float(np.mean(np.sign(pred[big, 0]) == np.sign(true[big, 0]))) if big.any() else np.nan
    mae_theta = float(np.degrees(np.abs(pred[:, 0] - true[:, 0])).mean())
    # Bias of the magnitude: median of predicted over true |theta| on the big rotations.
    ratio = float(np.median(np.abs(pred[big, 0]) / np.abs(true[big, 0]))) if big.any() else np.nan
    move = np.hypot(pred[:, 1] - true[:, 1], pred[:, 2] - true[:, 2])
    mae_move = float(move.mean() * resolution * 1000)
    return sense, mae_theta, ratio, mae_move, int(big.sum()), len(true)


def table(results, resolution):
    lines = [
        f"| predictor | friction | sense acc. (true abs(theta) > {BIG_ROTATION_DEG:g} deg) "
        "| MAE theta (deg) | median abs(theta) ratio | MAE translation (mm) | queries (big) |",
        "|---|---|---|---|---|---|---|",
    ]
    names = list(dict.fromkeys(name for fr in results for name in results[fr]))
    for name in names:
        for fr in [*results, "all"]:
            parts = results.values() if fr == "all" else [results[fr]]
            pairs = [p for part in parts for p in part.get(name, [])]
            if not pairs:
                continue
            pred = np.vstack([p for p, _ in pairs])
            true = np.vstack([t for _, t in pairs])
            s, mt, ratio, mm, nb, n = metrics(pred, true, resolution)
            lines.append(
                f"| {name} | {fr} | {s:.3f} | {mt:.2f} | {ratio:.2f} | {mm:.2f} | {n} ({nb}) |"
            )
    return "\n".join(lines)


def plot(results, path):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib missing (pip install comcore[plot]): no plot", file=sys.stderr)
        return
    names = [n for n in dict.fromkeys(n for fr in results for n in results[fr]) if "model" not in n]
    fig, axes = plt.subplots(1, len(names), figsize=(3.3 * len(names), 3.4), squeeze=False)
    for ax, name in zip(axes[0], names):
        for fr, colour in (("low", "tab:blue"), ("high", "tab:orange")):
            pairs = results.get(fr, {}).get(name, [])
            if pairs:
                pred = np.degrees(np.vstack([p for p, _ in pairs])[:, 0])
                true = np.degrees(np.vstack([t for _, t in pairs])[:, 0])
                ax.scatter(true, pred, s=3, alpha=0.4, color=colour, label=f"{fr} friction")
        lim = ax.get_xlim()
        ax.plot(lim, lim, "k-", lw=0.8)
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("true theta (deg)")
        ax.set_ylabel("predicted theta (deg)")
        ax.legend(fontsize=7, markerscale=3)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"saved {path}", file=sys.stderr)


def fit_figure(sim, fit, priors, path):
    """The posterior over the CoM of one trial, with its priors and the truth."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(4.6, 4.0))
    ax.imshow(sim.mask.data, cmap="Greys", alpha=0.35)
    logw = np.log10(np.maximum(fit.weights, 1e-4))
    sc = ax.scatter(*fit.candidates.T, c=logw, s=7, cmap="viridis", marker="s", vmin=-4)
    fig.colorbar(sc, ax=ax, label="log10 posterior weight (refined pixels)")
    for (sx, sy, ex, ey), (theta, _, _) in priors:
        colour = "tab:red" if theta > 0 else "tab:blue"
        ax.annotate("", (ex, ey), (sx, sy), arrowprops={"arrowstyle": "->", "color": colour})
    vals, vecs = np.linalg.eigh(fit.com_cov)
    t = np.linspace(0, 2 * np.pi, 100)
    ellipse = (vecs @ (2 * np.sqrt(vals)[:, None] * np.array([np.cos(t), np.sin(t)]))).T
    ax.plot(*(ellipse + fit.com).T, "w-", lw=1, label="2 sigma")
    ax.plot(*sim.com_px, "kx", ms=9, mew=2, label="true CoM")
    ax.plot(*fit.com, "r+", ms=11, mew=2, label="fitted CoM")
    ax.set_title(f"{sim.shape.name}: 12 priors (red CCW, blue CW)", fontsize=9)
    ax.legend(fontsize=7, loc="best", framealpha=0.6)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"saved {path}", file=sys.stderr)


def draw_simulator(obj, friction, rng, attempts=5):
    """``random_simulator``, drawn again (from the same stream) when the draw is refused."""

    def said(attempt, e):
        print(f"{obj} {friction}: redrawn ({e})", file=sys.stderr)

    return simulators.accepted_random_simulator(
        obj, friction, rng=rng, attempts=attempts, on_refusal=said
    )


def main(argv=None):
    args = parse_args(argv)
    anp, why = load_anp(args.anp_weights)
    if anp is None:
        print(f"AnpPredictor skipped ({why})", file=sys.stderr)
    rng = np.random.default_rng(args.seed)
    results: dict = {"low": {}, "high": {}}
    fit_s, com_err, mean_err, maha = [], [], [], []
    t0 = time.perf_counter()
    for obj in args.objects:
        for friction in ("low", "high"):
            for _ in range(args.trials):
                sim = draw_simulator(obj, friction, rng)
                out, extras = run_trial(sim, args, rng, anp)
                for name, pair in out.items():
                    results[friction].setdefault(name, []).append(pair)
                if not fit_s and args.fit_figure.lower() != "none":
                    fit_figure(sim, extras["fit"], extras["priors"], args.fit_figure)
                fit_s.append(extras["fit_s"])
                com_err.append(extras["com_error_mm"])
                mean_err.append(extras["com_mean_error_mm"])
                maha.append(extras["mahalanobis"])
        print(f"{obj} done ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    resolution = comcore.conventions.DEFAULT_RESOLUTION
    print(table(results, resolution))
    print(
        f"\nEllipsoid fit ({len(fit_s)} trials): CoM error {np.mean(com_err):.1f} mm mean, "
        f"{np.median(com_err):.1f} mm median (posterior mean: {np.mean(mean_err):.1f} / "
        f"{np.median(mean_err):.1f} mm); truth within 2 sigma of the fitted covariance in "
        f"{np.mean(np.array(maha) < 2.0):.0%} of trials; fit time {np.median(fit_s):.2f} s "
        f"median, {np.max(fit_s):.2f} s max; {time.perf_counter() - t0:.0f} s in all"
    )
    if args.out.lower() != "none":
        plot(results, args.out)


if __name__ == "__main__":
    main()
