"""``comcore demo``: push a simulated object, run both estimators, print the CoM and its error."""

from __future__ import annotations

import numpy as np

import comcore

HELP = (
    "push a simulated benchmark object and compare the paper's two estimators (needs comcore[sim])"
)


def add_arguments(parser) -> None:
    """Options of ``comcore demo``."""
    parser.add_argument("--object", default="Obj7", help="benchmark object name (Obj1..Obj20)")
    parser.add_argument("--friction", choices=("low", "high"), default="low")
    parser.add_argument("--pushes", type=int, default=60, help="number of candidate pushes")
    parser.add_argument(
        "--cone", type=float, default=0.3, help="push directions: radians about the normal"
    )
    parser.add_argument("--seed", type=int, default=0)


def run(args) -> int:
    """Run the demo; returns the exit status."""
    try:
        import simulators
        from predictors import OraclePredictor
    except ImportError as e:
        print(f"comcore demo needs the simulator: pip install comcore[sim] ({e})")
        return 2
    rng = np.random.default_rng(args.seed)
    sim = simulators.random_simulator(args.object, friction=args.friction, rng=rng)
    mask = sim.mask
    actions = comcore.sample_pushes(mask, args.pushes, cone=args.cone, rng=rng)
    motions = comcore.predict_motions(OraclePredictor(sim), mask, actions)
    cm_per_px = 100 * mask.resolution
    print(
        f"{args.object}: {mask.area_m2 * 1e4:.1f} cm^2, mu_contact {sim.mu_contact:.2f}, "
        f"true CoM ({sim.com_px[0]:.1f}, {sim.com_px[1]:.1f}) px; {args.pushes} simulated pushes"
    )
    results = {
        "centroid (baseline)": comcore.Estimate(
            com=mask.centroid, com_m=mask.centroid_m, region=mask.data
        ),
        "Alg. 1 heat map": comcore.estimate_heatmap(mask, actions, motions),
        "Alg. 2 progressive": comcore.estimate_progressive(mask, actions, motions),
    }
    for name, est in results.items():
        print(
            f"  {name:22s} CoM ({est.com[0]:6.1f}, {est.com[1]:6.1f}) px  "
            f"error {est.error_px(sim.com_px) * cm_per_px:5.2f} cm  "
            f"pushes used {len(est.used):3d}  status {est.status}"
        )
    return 0
