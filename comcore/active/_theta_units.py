"""Theta in degrees where every turn is small: the evidence says which unit the pushes are in.

A recording whose theta column is in degrees is refused by :func:`comcore._validation.check_turns`
only when one push turned by more than pi "radians" (180 degrees would be needed: 3.2 degrees
typed as 3.2). A recording whose turns are all under 3 degrees passes it, and the motion model
then reads every turn 57 times too large. The motion model tells the units apart (the Voting
Theorem alone reads only the senses, which the unit does not change): every theta multiplied by
pi/180 explains a recording in degrees far better than as given, and a recording in radians far
worse (its turns then look like none).

**Where the check lives.** Here, in the library, so that :func:`comcore.estimate_posterior`'s
users get it too: with a motion model and ``theta_units="auto"`` (its default) it compares the
two evidences itself and refuses a recording in degrees (a ValueError saying *theta looks like
degrees: multiply the column by pi/180*); ``"deg"`` converts, ``"rad"`` vouches for radians and
skips the check (one posterior instead of two). ``comcore estimate`` calls
:func:`theta_degrees_nats` itself for every method (``--model none`` and Alg. 1, 2 included,
with the default motion model), so that ``--theta-units rad`` can still warn.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._types import Motion
from ._options import DEFAULT_MODEL, DEFAULT_PUSHER_RADIUS

__all__ = [
    "DEGREES_NATS",
    "THETA_UNITS",
    "check_theta_units",
    "degrees_message",
    "scaled_gain",
    "theta_degrees_nats",
    "theta_in_radians",
]

#: The units ``theta_units`` takes: ``auto`` (radians, checked against degrees), ``rad``
#: (radians, not checked), ``deg`` (degrees, converted).
THETA_UNITS = ("auto", "rad", "deg")
#: A recording whose log evidence under the motion model rises by more than this (nats) with
#: every theta multiplied by pi/180 is in degrees (calibrated by
#: benchmarks/calibration/theta_units.py on seed 1; its false alarms and detections on seed 0
#: are in docs/how-to/recordings.md).
DEGREES_NATS = 10.0


def check_theta_units(theta_units) -> str:
    """``theta_units`` if it is one of :data:`THETA_UNITS`, else a ValueError.

    Examples
    --------
    >>> check_theta_units("deg")
    'deg'
    >>> check_theta_units("degrees")
    Traceback (most recent call last):
    ...
    ValueError: theta_units must be one of ('auto', 'rad', 'deg'), got 'degrees'
    """
    if not isinstance(theta_units, str) or theta_units not in THETA_UNITS:
        raise ValueError(f"theta_units must be one of {THETA_UNITS}, got {theta_units!r}")
    return theta_units


def theta_in_radians(motions, theta_units: str) -> np.ndarray:
    """``motions`` (n, 3) with theta in radians: multiplied by pi/180 for ``"deg"``.

    Examples
    --------
    >>> theta_in_radians([[90.0, 1.0, 2.0]], "deg").round(4).tolist()
    [[1.5708, 1.0, 2.0]]
    """
    motions = np.array(motions, dtype=float)
    if check_theta_units(theta_units) == "deg" and motions.ndim == 2 and motions.shape[1:] == (3,):
        motions[:, 0] *= math.pi / 180
    return motions


def theta_degrees_nats(
    mask, actions, motions, *, model=DEFAULT_MODEL, pusher_radius: float = DEFAULT_PUSHER_RADIUS
) -> float:
    """How much better (nats) every theta multiplied by pi/180 explains the pushes.

    The log evidence of :func:`comcore.estimate_posterior`'s posterior under
    ``model`` (default: the limit-surface model with ``pusher_radius``
    metres) over the pushes with every theta times pi/180, minus that over
    the pushes as given (:func:`scaled_gain`). Above :data:`DEGREES_NATS`
    the theta column is in degrees. Two posteriors without bagging: about
    2 s each for 40 pushes.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
    >>> motions = [(1.344, 12.931, -12.832), (-1.344, -12.832, 12.931),
    ...            (-1.08, 7.821, 9.148), (1.08, 9.148, 7.821)]  # radians
    >>> theta_degrees_nats(mask, actions, motions) < 0
    True
    """
    from ._posterior import estimate_posterior  # it calls this module: imported when used

    options = {"model": model, "pusher_radius": pusher_radius}
    given = estimate_posterior(mask, actions, motions, bootstrap=0, theta_units="rad", **options)
    return scaled_gain(mask, given, options)


def scaled_gain(mask, given, options: dict) -> float:
    """Log evidence with every theta of ``given``'s pushes times pi/180, minus ``given``'s.

    ``given`` is :func:`comcore.estimate_posterior`'s estimate of the pushes as
    given; its records are scored again (``pushes=``, with ``options``: the
    same model, prior and likelihood) with theta converted. Each push keeps
    its outcome: one that carried evidence as given still does, so that
    both evidences score the same pushes (a push whose converted turn is below
    the noise would otherwise drop out and count as explained).
    """
    from ._posterior import estimate_posterior  # as above

    scaled = [
        dataclasses.replace(r, motion=Motion(r.motion[0] * math.pi / 180, *r.motion[1:]))
        for r in given.pushes
    ]
    other = estimate_posterior(mask, pushes=scaled, bootstrap=0, theta_units="rad", **options)
    return float(other.posterior.log_evidence - given.posterior.log_evidence)


def degrees_message(gain: float, column: str = "the column") -> str:
    """What to say of a recording whose theta looks like degrees (``gain`` nats).

    Examples
    --------
    >>> degrees_message(42.0)
    'theta looks like degrees: multiply the column by pi/180 (every theta times pi/180 explains the pushes 42 nats better than as given)'
    """  # noqa: E501
    return (
        f"theta looks like degrees: multiply {column} by pi/180 (every theta times pi/180 "
        f"explains the pushes {gain:.0f} nats better than as given)"
    )
