"""What a user sets from their robot: the believable range of each value, and the unit guess.

Part of the conventions (:mod:`comcore.conventions` re-exports every name here): a value
in metres or radians outside its :data:`PLAUSIBLE` range is refused by
:func:`check_plausible` with a guess at the unit it was typed in (millimetres for metres,
degrees for radians, pixels per metre for metres per pixel).
"""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = ["DEFAULT_RESOLUTION", "MAX_IMAGE_PIXELS", "PLAUSIBLE", "Plausible", "check_plausible"]

#: Default camera resolution in metres per pixel (2.5 mm, as in the simulator).
DEFAULT_RESOLUTION = 0.0025
#: The most pixels an image (a mask, a camera frame) may have: 8192 x 8192, twice an 8K
#: camera's. Beyond it comcore refuses the image by its shape instead of asking numpy for
#: gigabytes (a broadcast view, a mask drawn in millimetres read as metres).
MAX_IMAGE_PIXELS = 8192 * 8192


class Plausible(NamedTuple):
    """The believable range of a value a user sets from their robot (see :data:`PLAUSIBLE`)."""

    low: float
    """Smallest believable value (0: any positive value, or zero where zero is allowed)."""
    high: float
    """Largest believable value."""
    typical: float
    """A usual value: among the units a wrong value may have been typed in, the guess is the
    one that brings it nearest this (on a log scale)."""
    unit: str
    """The unit the value must be given in, as messages write it."""


#: Believable values of what a user sets from their robot, in metres or radians: the one
#: place these ranges live (docs/explanation/conventions.md lists them). A value outside its range
#: is refused by :func:`check_plausible` with a guess at the unit it was typed in.
PLAUSIBLE = {
    # a camera over a table: 10 micrometres to 5 cm a pixel
    "resolution": Plausible(1e-5, 0.05, DEFAULT_RESOLUTION, "m per pixel"),
    # a round pusher: a point (0) to a disc 10 cm across
    "pusher_radius": Plausible(0.0, 0.05, 0.004, "m"),
    # a push's travel: no push goes further than half a metre
    "push_length": Plausible(0.0, 0.5, 0.03, "m"),
    # the credible region's radius a session stops at
    "target_radius": Plausible(0.0, 0.5, 0.006, "m"),
    # a standard deviation or error scale of a position (pusher, tracker, model)
    "length_noise": Plausible(0.0, 0.05, 0.001, "m"),
    # a standard deviation of a measured rotation: under about 29 degrees
    "angle_noise": Plausible(0.0, 0.5, 0.01, "rad"),
}

#: Units a length may have been typed in, with their size in metres.
_LENGTH_UNITS = (("millimetres", 1e-3), ("centimetres", 1e-2), ("micrometres", 1e-6))


def check_plausible(value: float, name: str, kind: str) -> float:
    """``value`` if it is believable as a :data:`PLAUSIBLE` ``kind``, else a ValueError.

    The message gives the range and, where converting the value from another
    unit brings it into the range, the likeliest such unit (the one nearest
    the typical value): millimetres or centimetres typed for metres, degrees
    for radians, pixels per metre for metres per pixel.

    Parameters
    ----------
    value : float
        A finite number, already checked for its sign.
    name : str
        The argument's name in the message.
    kind : str
        A key of :data:`PLAUSIBLE`.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If ``value`` lies outside the range.

    Examples
    --------
    >>> check_plausible(0.0025, "resolution", "resolution")
    0.0025
    >>> check_plausible(2.5, "resolution", "resolution")
    Traceback (most recent call last):
    ...
    ValueError: resolution 2.5 m per pixel is implausible (expected 1e-05 to 0.05 m per pixel): did you mean millimetres, 0.0025?
    >>> check_plausible(0.5, "motion_noise's rotation", "angle_noise")
    0.5
    >>> check_plausible(5.0, "pusher_radius", "pusher_radius")
    Traceback (most recent call last):
    ...
    ValueError: pusher_radius 5 m is implausible (expected at most 0.05 m): did you mean millimetres, 0.005?
    """  # noqa: E501
    if kind not in PLAUSIBLE:
        raise ValueError(f"kind must be one of {', '.join(sorted(PLAUSIBLE))}, got {kind!r}")
    rule = PLAUSIBLE[kind]
    v = float(value)
    if rule.low <= v <= rule.high:
        return v
    expected = (
        f"{rule.low:g} to {rule.high:g} {rule.unit}"
        if rule.low > 0
        else f"at most {rule.high:g} {rule.unit}"
    )
    message = f"{name} {v:g} {rule.unit} is implausible (expected {expected})"
    guess = _unit_guess(v, rule)
    raise ValueError(message + (f": did you mean {guess[0]}, {guess[1]:.3g}?" if guess else ""))


def _unit_guess(value: float, rule: Plausible) -> tuple[str, float] | None:
    """The likeliest unit ``value`` was typed in, and the value in ``rule``'s unit, or None."""
    if rule.unit == "rad":
        options = [("degrees", math.radians(value))]
    else:
        options = [(unit, value * size) for unit, size in _LENGTH_UNITS]
        if rule.unit == "m per pixel" and value > 0:
            options.append((f"{value:g} pixels per metre", 1.0 / value))
    fits = [(u, v) for u, v in options if max(rule.low, 1e-300) <= v <= rule.high]
    if not fits or rule.typical <= 0:
        return None
    return min(fits, key=lambda uv: abs(math.log(uv[1] / rule.typical)))
