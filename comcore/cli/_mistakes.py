"""What ``comcore estimate`` checks a recording for: the mistakes a user makes on day one.

theta in degrees, x and y swapped, most pushes missing the mask (refused, with the likely
mistake), a mask whose scale disagrees with the pushes' (:func:`scale_mistake`: refused), and
theta's sign flipped (the y-up convention: reported as ``inconsistent``
whatever the method, :func:`sign_flip_nats`). Theta in degrees is seen by a turn over pi and,
where every turn is small, by the motion model's evidence (:func:`units_mistake`, with
:func:`comcore.active._posterior.theta_degrees_nats`: the library's check, which
``comcore.estimate_posterior`` makes too). The object's size in metres
(:func:`object_size_m`) shows a resolution ten times off.
"""

from __future__ import annotations

import numpy as np

import comcore
from comcore.active._posterior import DEGREES_NATS, degrees_message, theta_degrees_nats

from ._inputs import InputError, line_list

__all__ = [
    "MOST_DROPPED",
    "SIGN_FLIP_NATS",
    "object_size_m",
    "recording_mistakes",
    "scale_mistake",
    "sign_flip_nats",
    "sign_mistake",
    "units_mistake",
]

#: A recording whose Voting-Theorem evidence rises by more than this (nats) with every
#: theta's sign flipped has its sign flipped (a Bayes factor of 20): it flags recordings with
#: every sign flipped, not those with a few senses flipped at random (calibrated by
#: ``benchmarks/accuracy/estimate_methods.py --flips 0,1,3,all``; docs/how-to/benchmark.md).
SIGN_FLIP_NATS = 3.0
#: More than this share of the pushes dropped (missing the object or starting inside it)
#: means the pushes are not in the mask's pixel frame: refused.
MOST_DROPPED = 0.5
#: At least this share of the pushes dropped sends the recording to :func:`scale_mistake`.
SCALE_DROPPED = 0.25
#: The scales :func:`scale_mistake` tries: the pushes about an anchor point, times these.
SCALES = np.round(np.arange(0.5, 2.0001, 0.01), 2)
#: Closest a scale that fits may be to 1 and still count as a disagreement.
SCALE_TOLERANCE = 0.05


def sign_flip_nats(mask: comcore.Mask, actions, motions) -> float:
    """How much better (nats) every theta with its sign flipped explains the pushes.

    The log evidence of the Voting Theorem's posterior
    (``comcore.estimate_posterior(..., model=None)``) over the pushes with
    every theta negated, minus that over the pushes as given: above
    :data:`SIGN_FLIP_NATS` the recording's theta is counter-clockwise with
    the y axis up (the table's frame) instead of on screen. Model-free and
    quick (two posteriors of the senses alone), so it is checked for every
    method.

    Examples
    --------
    >>> import numpy as np
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
    >>> motions = np.array([(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)])
    >>> sign_flip_nats(mask, actions, motions) < 0 < sign_flip_nats(mask, actions, -motions)
    True
    """
    motions = np.asarray(motions, dtype=float)
    flipped = motions * np.array([-1.0, 1.0, 1.0])
    evidence = [
        comcore.estimate_posterior(mask, actions, m, model=None).posterior.log_evidence
        for m in (motions, flipped)
    ]
    return float(evidence[1] - evidence[0])


def sign_mistake(mask, pushes) -> str | None:
    """The message for a recording whose theta looks sign-flipped, or None."""
    gain = sign_flip_nats(mask, pushes.actions, pushes.motions)
    if gain <= SIGN_FLIP_NATS:
        return None
    return (
        f"the pushes are explained far better with every theta's sign flipped ({gain:.0f} nats "
        "more evidence): theta looks counter-clockwise with the y axis up (a table's frame); "
        "comcore's theta is counter-clockwise on screen, y pointing down the image: negate the "
        "theta column"
    )


def units_mistake(mask, pushes, theta_units: str, pusher_radius: float) -> str | None:
    """The message for a recording whose theta looks like degrees, or None.

    Every theta times pi/180 against as given, under the default motion model
    (whatever the method: the Voting Theorem alone cannot tell the units apart).
    ``theta_units`` is ``--theta-units``: ``"auto"`` refuses such a recording
    (InputError), ``"rad"`` returns the message (reported as ``inconsistent``),
    ``"deg"`` (converted already) checks nothing.
    """
    if theta_units == "deg":
        return None
    gain = theta_degrees_nats(mask, pushes.actions, pushes.motions, pusher_radius=pusher_radius)
    if gain <= DEGREES_NATS:
        return None
    if theta_units == "auto":
        raise InputError(
            f"--pushes: column theta: {degrees_message(gain)}; --theta-units deg converts it "
            "(--theta-units rad estimates anyway, with status inconsistent)"
        )
    return degrees_message(gain)


def recording_mistakes(mask, recorded, dropped: dict, degrees: bool = False) -> None:
    """Refuse a recording whose theta is in degrees, or most of whose pushes miss the mask.

    For the latter, say whether x and y look swapped. ``degrees``: theta was
    given in degrees (``--theta-units deg``) and converted.
    """
    turned = np.flatnonzero(np.abs(recorded.motions[:, 0]) > np.pi)
    if len(turned):
        line, theta = int(recorded.lines[turned[0]]), float(recorded.motions[turned[0], 0])
        if degrees:
            raise InputError(
                f"--pushes: line {line}, column theta: {np.degrees(theta):g} degrees is more "
                "than 180 (a push turns an object by less than half a turn)"
            )
        raise InputError(
            f"--pushes: line {line}, column theta: {theta:g} rad is more than pi (a push turns an "
            f"object by less than half a turn): theta must be in radians (degrees? "
            f"{np.radians(theta):.3g} rad)"
        )
    n = len(recorded.lines)
    scaled = scale_mistake(mask, recorded.actions, len(dropped))
    if scaled and len(dropped) <= MOST_DROPPED * n:
        raise InputError(
            f"--mask and --pushes: {len(dropped)} of {n} pushes miss the object or start inside "
            f"it (CSV line(s) {line_list(list(dropped))}) and {scaled}: the mask's scale "
            "disagrees with the pushes' (a camera zoomed otherwise, or a mask made at another "
            "resolution); take the mask with the camera and zoom the pushes were measured in"
        )
    if len(dropped) <= MOST_DROPPED * n:
        return
    message = (
        f"--pushes: {len(dropped)} of {n} pushes miss the object or start inside it (CSV "
        f"line(s) {line_list(list(dropped))}): the pushes do not look like pushes on this mask"
    )
    swapped = recorded.actions[:, [1, 0, 3, 2]]
    found = comcore.geometry.contacts(mask, swapped)
    hits = int(np.sum(found.hit & ~found.starts_inside))
    if hits > n - len(dropped):
        message += (
            f"; with the x and y columns swapped {hits} of {n} would hit it: x is the column and "
            "y the row (pointing down), so sx, ex, tx go along the image's width"
        )
    elif scaled:
        message += f"; {scaled}: the mask's scale disagrees with the pushes'"
    else:
        message += "; are the mask and the pushes in the same pixel frame and resolution?"
    raise InputError(message)


def _fitting(mask: comcore.Mask, actions: np.ndarray) -> int:
    """How many pushes start off the object and enter it (the leading point's path)."""
    found = comcore.geometry.contacts(mask, actions)
    return int(np.sum(found.hit & ~found.starts_inside))


def scale_mistake(mask: comcore.Mask, actions, dropped: int) -> str | None:
    """Say whether the pushes fit the mask at another scale; ``None`` if not, or not asked.

    The pushes are in the recording's pixels; a mask taken at another zoom (or
    drawn at another resolution) puts the object where the pushes start inside
    it or miss it. The rule: when at least :data:`SCALE_DROPPED` of the pushes
    are dropped (``dropped`` of them), the pushes' end points are scaled about
    the mask's area centroid, the image's centre and its top-left pixel by each
    of :data:`SCALES`; if one scale at least :data:`SCALE_TOLERANCE` from 1
    lets all but a tenth of the pushes (and more than as given) start off the
    object and enter it, the mask's scale disagrees with the pushes'. The scale
    named is the one the mask would need (the inverse of the pushes'): of those
    that fit the most pushes, the closest to 1 (long pushes fit a range).

    Examples
    --------
    A square and four pushes that reach it only once it is drawn about 1.3 times larger:

    >>> import numpy as np
    >>> mask = comcore.Mask(np.pad(np.ones((26, 26), bool), 17))
    >>> pushes = [(30, 1, 30, 14), (30, 59, 30, 46), (1, 30, 14, 30), (59, 30, 46, 30)]
    >>> scale_mistake(mask, pushes, 4)
    'the pushes fit the mask scaled by 1.28 about its centroid (4 of 4 pushes), but 0 of 4 as given'
    """
    actions = np.asarray(actions, dtype=float).reshape(-1, 4)
    n = len(actions)
    if n == 0 or dropped < SCALE_DROPPED * n:
        return None
    given = _fitting(mask, actions)
    height, width = mask.data.shape
    anchors = {
        "its centroid": np.array(mask.centroid, dtype=float),
        "the image's centre": np.array([(width - 1) / 2, (height - 1) / 2]),
        "the image's top-left pixel": np.zeros(2),
    }
    best = (given, 0.0, "", 1.0)  # (pushes that fit, -|scale - 1|, anchor, scale)
    for scale in SCALES[np.abs(SCALES - 1.0) >= SCALE_TOLERANCE]:
        for where, anchor in anchors.items():
            ends = anchor + scale * (actions.reshape(-1, 2) - anchor)
            found = (_fitting(mask, ends.reshape(-1, 4)), -abs(scale - 1.0), where, scale)
            best = max(best, found, key=lambda f: f[:2])
    fits, _, where, scale = best
    if fits > given and n - fits <= n // 10:
        return (
            f"the pushes fit the mask scaled by {1 / scale:.2f} about {where} ({fits} of {n} "
            f"pushes), but {given} of {n} as given"
        )
    return None


def object_size_m(mask: comcore.Mask) -> list[float]:
    """Width and height (metres) of the object's bounding box in the image.

    A resolution ten times off is still plausible and cannot be told from the
    pushes (they are in pixels); the object's size in metres shows it.

    Examples
    --------
    >>> import numpy as np
    >>> object_size_m(comcore.Mask(np.pad(np.ones((20, 30), bool), 4), resolution=0.0025))
    [0.075, 0.05]
    """
    rows, cols = np.nonzero(mask.data)
    return [
        float((cols.max() - cols.min() + 1) * mask.resolution),
        float((rows.max() - rows.min() + 1) * mask.resolution),
    ]
