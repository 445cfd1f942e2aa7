"""The estimators and predictors the benchmark knows out of the box."""

from __future__ import annotations

import comcore

from ._registry import (
    PREDICTORS,
    PredictorSpec,
    TrialContext,
    missing,
    register_estimator,
    requirements,
)

__all__: list[str] = []

_SIM = missing("simulators", "PushSimulator", "pip install comcore[sim]")
_ORACLE = requirements(_SIM, missing("predictors", "OraclePredictor", "pip install comcore[sim]"))
_ELLIPSOID = missing("predictors", "EllipsoidPredictor")
_ACTIVE = missing("comcore", "estimate_active")


def _alg1(ctx: TrialContext, **options) -> comcore.Estimate:
    return comcore.estimate_heatmap(ctx.mask, ctx.candidates, ctx.motions, **options)


def _alg2(ctx: TrialContext, **options) -> comcore.Estimate:
    return comcore.estimate_progressive(ctx.mask, ctx.candidates, ctx.motions, **options)


def _alg2_rotation(ctx: TrialContext, **options) -> comcore.Estimate:
    options = {"selection": "rotation", **options}
    return comcore.estimate_progressive(ctx.mask, ctx.candidates, ctx.motions, **options)


def _centroid(ctx: TrialContext) -> comcore.Estimate:
    mask = ctx.mask
    return comcore.Estimate(com=mask.centroid, com_m=mask.centroid_m, region=mask.data)


def _hypothesis_model(ctx: TrialContext, model):
    if model is None or model == "none":
        return None
    if model == "ellipsoid":
        from predictors import EllipsoidPredictor

        return EllipsoidPredictor(pusher_radius=ctx.simulator.pusher_radius)
    raise ValueError(f"model must be 'ellipsoid' or None, got {model!r}")


def _active(ctx: TrialContext, model="ellipsoid", candidates="own", **options):
    """Run :func:`comcore.estimate_active` on the trial's object, with its own defaults.

    ``candidates``: ``"own"`` (default: the estimator draws its pushes, 200 along the
    inward normals, from the trial's estimator stream) or ``"trial"`` (the trial's random
    candidates, the set Alg. 1 and Alg. 2 choose from). Choosing its pushes is part of what
    the active estimator is for; ``"trial"`` measures it on Alg. 2's terms.
    """
    if candidates not in ("trial", "own"):
        raise ValueError(f"candidates must be 'trial' or 'own', got {candidates!r}")
    return comcore.estimate_active(  # type: ignore[attr-defined]
        ctx.mask,
        ctx.push,
        ctx.candidates if candidates == "trial" else None,
        model=_hypothesis_model(ctx, model),
        rng=ctx.rng,
        **options,
    )


def _active_vt(ctx: TrialContext, **options):
    return _active(ctx, **{"model": None, **options})


register_estimator("alg1", _alg1, description="Alg. 1: calmest region of the rotation heat map")
register_estimator(
    "alg2", _alg2, description="Alg. 2: progressive Voting-Theorem cuts, equality-score order"
)
register_estimator(
    "alg2-rotation",
    _alg2_rotation,
    description="Alg. 2 taking pushes in ascending |theta| (the paper's Fig. 7 ablation)",
)
register_estimator(
    "centroid",
    _centroid,
    description="baseline: the mask's area centroid (no push)",
    uses_motions=False,
)
register_estimator(
    "active",
    _active,
    description="comcore.estimate_active pushing the object, ellipsoid motion model",
    uses_motions=False,
    requires=requirements(_ACTIVE, _ELLIPSOID),
)
register_estimator(
    "active-vt",
    _active_vt,
    description="comcore.estimate_active pushing the object, Voting Theorem only",
    uses_motions=False,
    requires=_ACTIVE,
)


def _oracle(ctx: TrialContext):
    from predictors import OraclePredictor

    return OraclePredictor(ctx.simulator)


def _ellipsoid(ctx: TrialContext):
    from predictors import EllipsoidPredictor

    return EllipsoidPredictor(pusher_radius=ctx.simulator.pusher_radius)


def _anp(ctx: TrialContext):
    from predictors import AnpPredictor

    return AnpPredictor()


PREDICTORS["oracle"] = PredictorSpec("oracle", _oracle, 0, _ORACLE, pushes_object=True)
PREDICTORS["ellipsoid"] = PredictorSpec("ellipsoid", _ellipsoid, 12, _ELLIPSOID)
PREDICTORS["anp"] = PredictorSpec(
    "anp", _anp, 12, missing("predictors", "AnpPredictor", "pip install comcore[anp]")
)
