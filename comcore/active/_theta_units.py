"""Theta in degrees where every turn is small: the evidence says which unit the pushes are in.

A recording whose theta column is in degrees is refused by
:func:`comcore._validation.check_turns` only when some push turned by more than pi of its
units, 3.14 degrees. A recording whose turns are all under 3 degrees passes it, and the motion
model then reads every turn 57 times too large. The motion model tells the units apart (the Voting
Theorem alone reads only the senses, which the unit does not change): every theta multiplied by
pi/180 explains a recording in degrees far better than as given, and a recording in radians far
worse (its turns then look like none).

**Where the check lives.** In the library, so that :func:`comcore.estimate_posterior`'s users
get it too: with a motion model and ``theta_units="auto"`` (its default) it compares the two
evidences itself and refuses a recording in degrees (a ValueError saying that the model and
the data disagree, as if theta were in degrees, and naming both faults: theta in degrees, or
a model whose theta is wrong); ``"deg"`` converts, ``"rad"`` vouches for radians and
skips the check (one posterior instead of two). This module holds the margin, the units and the
words; the evidences are compared beside the posterior they rerun
(``scaled_gain`` and ``theta_degrees_nats`` in :mod:`comcore.active._posterior`), so that it
imports nothing of the estimator. ``comcore estimate`` calls ``theta_degrees_nats``
itself for every method (``--model none`` and Alg. 1, 2 included, with the default motion
model), so that ``--theta-units rad`` can still warn.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "DEGREES_NATS",
    "THETA_UNITS",
    "check_theta_units",
    "degrees_message",
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


def degrees_message(gain: float, column: str = "the column") -> str:
    """What to say of pushes that every theta times pi/180 explains ``gain`` nats better.

    The data and the motion model disagree, and either may be at fault: theta
    recorded in degrees, or a model whose theta has the wrong sign or unit. The
    message names both.

    Examples
    --------
    >>> degrees_message(42.0)
    'the motion model and the data disagree, as if theta were in degrees: if it is, multiply the column by pi/180; if not, the theta of the model is wrong: check its sign and unit against a push whose turn you know (every theta times pi/180 explains the pushes 42 nats better than as given)'
    """  # noqa: E501
    return (
        "the motion model and the data disagree, as if theta were in degrees: if it is, "
        f"multiply {column} by pi/180; if not, the theta of the model is wrong: check its "
        "sign and unit against a push whose turn you know (every theta times pi/180 explains "
        f"the pushes {gain:.0f} nats better than as given)"
    )
