"""Check a weights file on the benchmark objects: ``python -m predictors.anp.evaluate``.

For each benchmark object and friction class: one random mass distribution
(``simulators.random_simulator``), 12 simulated prior pushes and ``--queries``
query pushes (cone 0.3 rad), predicted by :class:`AnpPredictor` and compared
with the simulator. Prints one line per trial and a summary: sense accuracy on
queries turning more than 5 degrees, mean absolute error of theta (degrees)
and of the centroid's displacement (mm), and the latent CoM's error (mm).
The full comparison with other predictors lives under ``benchmarks/``.
"""

from __future__ import annotations

import argparse

import numpy as np

import comcore

from .predictor import AnpPredictor

__all__ = ["evaluate_on_benchmark", "main"]


def evaluate_on_benchmark(anp: AnpPredictor, objects=None, n_priors: int = 12,
                          n_queries: int = 50, seed: int = 1000) -> list[dict]:
    """One dict of metrics per (object, friction class) trial."""
    import simulators

    names = list(simulators.BENCHMARK_OBJECTS if objects is None else objects)
    rows = []
    for name in names:
        for j, friction in enumerate(("low", "high")):
            trial_seed = seed + 2 * simulators.BENCHMARK_OBJECTS.index(name) + j
            sim = simulators.random_simulator(name, friction=friction, rng=trial_seed)
            rng = np.random.default_rng(trial_seed)
            found = simulators.sample_accepted_pushes(  # as the training data: one by one
                sim, n_priors + n_queries, cone=0.3, rng=rng, batched=False, draws=50
            )
            pushes, true = found.pushes, found.motions
            priors = [(comcore.Action(*a), comcore.Motion(*m))
                      for a, m in zip(pushes[:n_priors], true[:n_priors])]
            pred = anp.predict(sim.mask, pushes[n_priors:], priors)
            truth = true[n_priors:]
            big = np.abs(truth[:, 0]) > np.deg2rad(5)
            mm = 1000 * sim.mask.resolution
            com = anp.estimate_com(sim.mask, priors)
            rows.append({
                "object": name, "friction": friction, "n_sense": int(big.sum()),
                "sense_acc": float((np.sign(pred[big, 0]) == np.sign(truth[big, 0])).mean()),
                "theta_mae_deg": float(np.rad2deg(np.abs(pred[:, 0] - truth[:, 0]).mean())),
                "t_mae_mm": float(mm * np.hypot(*(pred[:, 1:] - truth[:, 1:]).T).mean()),
                "com_err_mm": float(mm * np.hypot(*np.subtract(com, sim.com_px))),
            })
    return rows


def main(argv=None) -> dict:
    """Command-line entry point; returns the summary."""
    p = argparse.ArgumentParser(prog="python -m predictors.anp.evaluate", description=__doc__)
    p.add_argument("--weights", default=None, help="weights file (default: the shipped one)")
    p.add_argument("--objects", nargs="+", default=None, help="benchmark objects (default all)")
    p.add_argument("--queries", type=int, default=50)
    p.add_argument("--seed", type=int, default=1000)
    args = p.parse_args(argv)
    rows = evaluate_on_benchmark(AnpPredictor(args.weights), args.objects,
                                 n_queries=args.queries, seed=args.seed)
    for r in rows:
        print(" ".join(f"{v:.3f}" if isinstance(v, float) else str(v) for v in r.values()))
    n = sum(r["n_sense"] for r in rows)
    summary = {
        "trials": len(rows),
        "n_sense": n,
        "sense_acc": sum(r["sense_acc"] * r["n_sense"] for r in rows if r["n_sense"]) / max(n, 1),
        **{
            k: float(np.mean([r[k] for r in rows]))
            for k in ("theta_mae_deg", "t_mae_mm", "com_err_mm")
        },
    }
    print(
        f"sense accuracy (|theta| > 5 deg) {summary['sense_acc']:.3f} over {n} queries; "
        f"theta MAE {summary['theta_mae_deg']:.2f} deg; displacement MAE "
        f"{summary['t_mae_mm']:.2f} mm; latent CoM error {summary['com_err_mm']:.1f} mm"
    )
    return summary


if __name__ == "__main__":  # pragma: no cover
    main()
