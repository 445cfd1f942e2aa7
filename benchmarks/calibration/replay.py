"""Keep a benchmark run's pushes and score them again: shared by the tuning scripts.

``tune_active.py --keep-pushes`` keeps, per run, the first mask the pushes live on
(the robot's camera mask for a run that never reset the object), the Estimate's
push records and the true CoM (:func:`kept_pushes`); ``rescore_pushes.py``,
``stop_frontier.py`` and ``calibrate_power.py`` score them again with
:func:`comcore.estimate_posterior` under other likelihood options
(:func:`posterior_options`). Nothing here re-implements the library: the
posterior, the stop rule (``comcore.StopRule.stop_index``) and the truth's
credible level (``comcore.credible_level``) are comcore's.
"""

from __future__ import annotations

import comcore
import comcore.bench

#: The benchmark's pusher (simulators' default), for the default model.
PUSHER_RADIUS = 0.004


def kept_pushes(est: comcore.Estimate, mask: comcore.Mask, true_px) -> dict:
    """What a replay needs of one run: its first mask, its push records and the true CoM."""
    first = est.extras.get("first_mask", mask)
    return {
        "mask": first.data.copy(),
        "resolution": first.resolution,
        "pushes": tuple(est.pushes),
        "true_px": tuple(float(v) for v in true_px),
    }


def executed(kept: dict) -> list:
    """The kept run's executed pushes (evidence or miss), in order."""
    return [p for p in kept["pushes"] if p.outcome != "failed"]


def has_evidence(kept: dict) -> bool:
    return any(p.outcome == "evidence" for p in kept["pushes"])


def posterior_options(options: dict) -> dict:
    """``estimate_posterior`` keywords from a flat JSON variant.

    ``{"model": null}`` (or ``{"vt": true}``): the Voting Theorem alone; otherwise
    ``comcore.LimitSurfaceModel(pusher_radius=...)`` (``"pusher_radius"``, default the
    benchmark's 4 mm); the other keys are :class:`comcore.Likelihood`'s fields
    (``systematic_error`` defaults to the sessions', 0).
    """
    options = {k: tuple(v) if isinstance(v, list) else v for k, v in options.items()}
    vt = options.pop("vt", False) or ("model" in options and options.pop("model") is None)
    if "model" in options:
        raise ValueError("a variant's 'model' may only be null (the Voting Theorem alone)")
    radius = options.pop("pusher_radius", PUSHER_RADIUS)
    # a replay scores a session's pushes as the session did: with the sessions' floor for
    # the systematic error (0), not estimate_posterior's own for recordings (2 mm)
    options.setdefault("systematic_error", comcore.active.SESSION_SYSTEMATIC_ERROR)
    out = {"model": None if vt else comcore.LimitSurfaceModel(pusher_radius=radius)}
    out.update(comcore.bench.option_groups(**options))
    if set(out) - {"model", "likelihood"}:
        raise ValueError(f"a variant may set only the likelihood's options, got {options}")
    out["bootstrap"] = 0  # and the session's region: the posterior's own, not the bagged one
    return out


def replay(kept: dict, options: dict, k: int | None = None) -> comcore.Estimate:
    """The posterior over the kept run's first ``k`` executed pushes (all by default)."""
    mask = comcore.Mask(kept["mask"], resolution=kept["resolution"])
    pushes = executed(kept)
    return comcore.estimate_posterior(mask, pushes=pushes[:k], **options)
