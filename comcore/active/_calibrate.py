"""Choosing the model's power from calibration objects: :func:`comcore.calibrate_model_weight`.

The default power on the motion model's likelihood is learned per session
(``model_weight=(0.25, 0.4, 0.6, 1.0)``), but four or five pushes of one object
cannot tell a model that is right from one that errs the same way on every push,
so the default region is wider than it must be where the model is right, and
that costs pushes. The motions hardly tell the two apart: the power learned
from them comes out about the same on our own engine, where the model is
nearly right, as on pymunk, where it errs (docs/explanation/calibration.md). What does
tell them apart is the truth: a few objects whose CoM the user measured (a
balance, or hanging the object from two points). This module
scores their pushes again under each power and reports how often each power's
region held the measured CoM.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .._types import Estimate
from .._validation import check_mask, check_point, check_powers
from ._likelihood import Likelihood, check_models
from ._options import (
    DEFAULT_CREDIBLE,
    DEFAULT_MODEL,
    DEFAULT_PUSHER_RADIUS,
    SESSION_SYSTEMATIC_ERROR,
    group_or_default,
)
from ._posterior import estimate_posterior

__all__ = ["PowerCalibration", "calibrate_model_weight"]

#: Powers scored by default.
CALIBRATION_POWERS = (0.25, 0.4, 0.6, 0.8, 1.0)
#: Confidence of :attr:`PowerCalibration.coverage_low`, the one-sided lower bound.
COVERAGE_CONFIDENCE = 0.9


@dataclass(frozen=True)
class PowerCalibration:
    """What :func:`comcore.calibrate_model_weight` measured, per power.

    Attributes
    ----------
    powers : tuple of float
        The powers scored, increasing.
    coverage : numpy.ndarray, shape (n_powers,)
        Share of the calibration objects whose credible region held the measured CoM.
    coverage_low : numpy.ndarray, shape (n_powers,)
        A one-sided 90 % lower confidence bound on each coverage (Clopper-Pearson):
        how low the coverage of objects to come may be, given only these. Ten
        objects all held give 0.79: they cannot certify a 90 % region.
    radius_m : numpy.ndarray, shape (n_powers,)
        Mean equivalent-circle radius of the regions (metres).
    error_m : numpy.ndarray, shape (n_powers,)
        Mean distance of the posterior mean from the measured CoM (metres).
    n_objects : int
    level : float
        The credible level of the regions (and the coverage asked for).
    recommended : float
        The largest power whose regions held the CoM at least ``level`` of the
        time (the smallest power if none did): pass it as ``model_weight``.
    """

    powers: tuple
    coverage: np.ndarray
    coverage_low: np.ndarray
    radius_m: np.ndarray
    error_m: np.ndarray
    n_objects: int
    level: float
    recommended: float


def calibrate_model_weight(
    records,
    *,
    model=DEFAULT_MODEL,
    pusher_radius: float = DEFAULT_PUSHER_RADIUS,
    powers=CALIBRATION_POWERS,
    credible: float = DEFAULT_CREDIBLE,
    likelihood=None,
) -> PowerCalibration:
    """Score pushes of objects with a measured CoM under fixed powers of the model's likelihood.

    For each record and power, :func:`comcore.estimate_posterior` with
    ``likelihood`` whose ``model_weight`` is that power; the result says how often each power's
    ``credible`` region held the measured CoM, and recommends the largest power
    that held it at least ``credible`` of the time. With ``n`` objects the
    coverage is a share of ``n`` (its standard error about
    ``sqrt(0.09 / n)``: 10 objects tell 90 % from 70 %, not from 85 %).

    Parameters
    ----------
    records : iterable of (Mask, Estimate, true_com) or (Mask, actions, motions, true_com)
        One per calibration object: the first mask of its session, the
        session's :class:`Estimate` (from :meth:`ActiveSession.estimate` or
        :func:`comcore.estimate_active`: its pushes and motions in that
        mask's frame, and which rotations the camera could not tell and how
        well each registration fitted, are replayed as the session scored
        them; the object need not have been reset between pushes) or the
        pushes and motions themselves (each rotation observed, no
        registration residual), and the measured CoM ``(x, y)`` in that
        mask's pixels. Misses are dropped as the estimator drops them.
    model, pusher_radius
        The motion model, as for :func:`comcore.estimate_active` (default
        ``LimitSurfaceModel(pusher_radius=pusher_radius)``).
    powers : sequence of float, optional
        Powers in (0, 1] to score.
    credible : float, optional
        Level of the regions, and the coverage the recommendation asks for.
    likelihood : Likelihood, optional
        The likelihood you run the sessions with (``pusher_error``,
        ``motion_noise``, ``mu``, ...); its ``model_weight`` is replaced by
        each power, and a ``systematic_error`` left None is the sessions' (0),
        not ``estimate_posterior``'s own for recordings.

    Returns
    -------
    PowerCalibration

    Raises
    ------
    TypeError, ValueError
        On invalid records or options (each named).

    Examples
    --------
    >>> import numpy as np, comcore
    >>> from comcore.vt import predicted_sense
    >>> mask = comcore.Mask(np.pad(np.ones((24, 24), bool), 6))
    >>> def plate(seed, com):  # four pushes and the senses they turned the plate
    ...     actions = comcore.sample_pushes(mask, 4, cone=0.0, rng=seed)
    ...     c = comcore.geometry.contacts(mask, actions)
    ...     senses = [predicted_sense(com, p, n, comcore.Action(*a).direction, 0.3)
    ...               for p, n, a in zip(c.point, c.normal, actions)]
    ...     return mask, actions, [(0.1 * s, 0.0, 0.0) for s in senses], com
    >>> cal = comcore.calibrate_model_weight(
    ...     [plate(0, (15.0, 20.0)), plate(1, (20.0, 14.0))], model=None, powers=(0.5, 1.0))
    >>> cal.n_objects, cal.coverage.tolist(), cal.recommended
    (2, [1.0, 1.0], 1.0)
    """
    models = check_models(model, pusher_radius)
    likelihood = group_or_default(likelihood, Likelihood, "likelihood")
    if likelihood.systematic_error is None:  # scored as the sessions score them
        likelihood = dataclasses.replace(likelihood, systematic_error=SESSION_SYSTEMATIC_ERROR)
    if isinstance(powers, str) or np.ndim(powers) != 1:
        raise TypeError(f"powers must be a sequence of numbers in (0, 1], got {powers!r}")
    grid = tuple(sorted(check_powers(tuple(powers), "powers")))
    try:
        items = list(records)
    except TypeError as e:
        raise TypeError(
            "records must be an iterable of (mask, estimate, true_com) or "
            "(mask, actions, motions, true_com) tuples, one per calibration object"
        ) from e
    if not items:
        raise ValueError("records must hold at least one calibration object")
    hits = np.zeros((len(items), len(grid)), dtype=bool)
    radius = np.zeros_like(hits, dtype=float)
    error = np.zeros_like(hits, dtype=float)
    for i, record in enumerate(items):
        mask, pushes, truth = _record(record, i)
        mask = check_mask(mask, f"records[{i}] mask")
        truth = check_point(truth, f"records[{i}] true_com")
        for j, power in enumerate(grid):
            try:
                est = estimate_posterior(
                    mask,
                    **pushes,
                    model=list(models) if models else None,
                    credible=credible,
                    likelihood=dataclasses.replace(likelihood, model_weight=power),
                    bootstrap=0,  # the sessions' region: the posterior's own, not bagged
                    theta_units="rad" if j else "auto",  # theta's unit checked once a record
                )
            except (TypeError, ValueError) as e:  # the record's pushes: say which record
                if j:
                    raise
                raise type(e)(f"records[{i}]: {e}") from e
            hits[i, j] = est.region_holds(truth)
            radius[i, j] = est.posterior.credible_radius_px * mask.resolution
            error[i, j] = est.error_px(truth) * mask.resolution
    coverage = hits.mean(axis=0)
    good = [p for p, c in zip(grid, coverage) if c >= credible - 1e-12]
    from scipy import stats  # here: scipy.stats costs import time that comcore need not pay

    held, n = hits.sum(axis=0), len(items)
    low = np.where(held > 0, stats.beta.ppf(1 - COVERAGE_CONFIDENCE, held, n - held + 1), 0.0)
    return PowerCalibration(
        powers=grid,
        coverage=coverage,
        coverage_low=low,
        radius_m=radius.mean(axis=0),
        error_m=error.mean(axis=0),
        n_objects=len(items),
        level=float(credible),
        recommended=max(good) if good else grid[0],
    )


def _record(record, i: int):
    """``(mask, pushes as estimate_posterior's keywords, true_com)`` of one calibration record."""
    what = (
        f"records[{i}] must be a (mask, estimate, true_com) or "
        "(mask, actions, motions, true_com) tuple"
    )
    try:
        items = tuple(record)
    except TypeError as e:
        raise TypeError(what) from e
    if len(items) == 3 and isinstance(items[1], Estimate):
        mask, est, truth = items
        if not any(p.outcome != "failed" for p in est.pushes):
            raise ValueError(
                f"records[{i}]'s estimate holds no executed push (Estimate.pushes): "
                "pass an ActiveSession's or estimate_active's Estimate"
            )
        return mask, {"pushes": est.pushes}, truth
    if len(items) != 4:
        raise TypeError(what)
    mask, actions, motions, truth = items
    return mask, {"actions": actions, "motions": motions}, truth
