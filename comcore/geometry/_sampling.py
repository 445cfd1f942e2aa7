"""Seeded samplers shared by tests, benchmarks and users."""

from __future__ import annotations

import numpy as np

from .._mask import Mask
from .._neighbourhood import true_pixels
from .._validation import check_mask, check_physical, check_positive, check_rng
from ..conventions import DEFAULT_TRAVEL_M, rotate_vectors
from ._contacts import MARCH_STEP_PX, contacts

__all__ = ["sample_pushes"]

#: Default distance from the start of a push to the object, metres.
DEFAULT_SAMPLED_STANDOFF_M = 0.012
#: Default free space around a push's start, metres: a 4 mm disc pusher trailing
#: its leading point sweeps points up to 8 mm from the start; plus 1 mm slack.
DEFAULT_CLEARANCE_M = 0.009
#: A pixel's outline can lie this far (pixels) from its centre: half the diagonal.
HALF_PIXEL_DIAGONAL = 0.5 * np.sqrt(2.0)
#: Most pushes one :func:`sample_pushes` call draws: about 4 s on a 30 x 30 pixel object
#: (the time grows with the push's length in pixels); more is a mistake (a count typed
#: for a seed) that would run for minutes. Sessions offer at most
#: ``comcore.active._options.MAX_CANDIDATES`` candidates.
MAX_SAMPLED_PUSHES = 100_000
#: Shortest travel after contact, in pixels of the mask: the step of the contact search
#: (``MARCH_STEP_PX``); a push ending closer to its contact may miss it (5e-324 m did).
#: Sessions refuse pushes under a pixel long on their own, saying so.
MIN_TRAVEL_PX = MARCH_STEP_PX


def sample_pushes(
    mask: Mask,
    n: int,
    *,
    cone: float = 0.0,
    travel: float = DEFAULT_TRAVEL_M,
    standoff: float = DEFAULT_SAMPLED_STANDOFF_M,
    clearance: float = DEFAULT_CLEARANCE_M,
    rng=None,
) -> np.ndarray:
    """Random candidate pushes onto the object's outline.

    Each push aims at a uniformly drawn outline pixel, along the inward normal
    turned by an angle drawn uniformly in ``[-cone, cone]``; it starts
    ``standoff`` metres before the contact (outside the object) and ends
    ``travel`` metres after it. Pushes whose path does not reach the object
    first at the aimed contact's side, or whose start lies within
    ``clearance`` metres of the object (a round pusher must fit there; this
    matters on concave outlines) are redrawn.

    Parameters
    ----------
    mask : Mask
    n : int
        Number of pushes, 0 to ``MAX_SAMPLED_PUSHES`` (100 000).
    cone : float, optional
        Half-angle in radians of the directions about the inward normal,
        in ``[0, pi/2)``; 0 gives pushes exactly along the normal.
    travel : float, optional
        Pusher travel after contact, metres (default 0.03): at least
        ``MIN_TRAVEL_PX`` (a quarter) pixel of the mask, at most half a metre.
    standoff : float, optional
        Distance from start to contact, metres (default 0.012).
    clearance : float, optional
        Minimum distance from the start to the object's outline, metres
        (default 0.009), measured conservatively (to the nearest object pixel
        centre, minus half a pixel diagonal); 0 disables the check.
    rng : None, int or numpy.random.Generator, optional
        Seed or generator; ``None`` draws a fresh generator.

    Returns
    -------
    numpy.ndarray, shape (n, 4)
        ``(sx, sy, ex, ey)`` rows in pixels.

    Raises
    ------
    ValueError
        If ``n`` is negative or over ``MAX_SAMPLED_PUSHES``, ``travel`` shorter
        than a quarter pixel of the mask, ``travel``, ``standoff`` or ``clearance``
        longer than half a metre (millimetres typed for metres), or the outline
        admits no valid push.

    Examples
    --------
    >>> import numpy as np
    >>> from comcore import Mask
    >>> from comcore.geometry import contacts
    >>> m = Mask(np.pad(np.ones((30, 30), bool), 10), resolution=0.0025)
    >>> pushes = sample_pushes(m, 5, cone=0.3, rng=0)
    >>> pushes.shape, bool(contacts(m, pushes).hit.all())
    ((5, 4), True)
    >>> np.array_equal(pushes, sample_pushes(m, 5, cone=0.3, rng=0))
    True
    >>> sample_pushes(m, 5, travel=1e-4)
    Traceback (most recent call last):
    ...
    ValueError: travel must carry the pusher at least 0.25 pixel past the contact, 0.000625 m at this mask's resolution, got 0.0001 m (travel is in metres)
    """  # noqa: E501
    mask = check_mask(mask)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise ValueError(f"n must be a non-negative integer, got {n!r}")
    if n > MAX_SAMPLED_PUSHES:
        raise ValueError(
            f"n must be at most {MAX_SAMPLED_PUSHES} pushes (MAX_SAMPLED_PUSHES, a few seconds), "
            f"got {n}: draw them in batches if you need more"
        )
    cone = check_positive(cone, "cone", allow_zero=True) + 0.0  # -0.0 is 0 (uniform(0, -0.0) fails)
    if cone >= np.pi / 2:
        raise ValueError(f"cone must be in [0, pi/2), got {cone}")
    travel_px = check_physical(travel, "travel", "push_length") / mask.resolution
    if travel_px < MIN_TRAVEL_PX:
        raise ValueError(
            f"travel must carry the pusher at least {MIN_TRAVEL_PX:g} pixel past the contact, "
            f"{MIN_TRAVEL_PX * mask.resolution:g} m at this mask's resolution, got "
            f"{float(travel):g} m (travel is in metres)"
        )
    standoff_px = check_physical(standoff, "standoff", "push_length") / mask.resolution
    clearance_px = (
        check_physical(clearance, "clearance", "push_length", allow_zero=True) / mask.resolution
    )
    rng = check_rng(rng)
    outline = true_pixels(mask.boundary, mask._box)  # the object's box: not the whole frame
    out = np.empty((0, 4))
    for _ in range(50):
        if len(out) >= n:
            break
        k = 2 * (n - len(out)) + 8
        target = outline[rng.integers(len(outline), size=k)]
        normal = mask.inward_normals(target)
        valid = np.any(normal != 0, axis=1)
        target, normal = target[valid], normal[valid]
        direction = rotate_vectors(normal, rng.uniform(-cone, cone, size=len(normal)))
        start = target - (standoff_px + 0.5) * direction
        candidate = np.hstack([start, target + travel_px * direction])
        con = contacts(mask, candidate)
        free = mask.distance_to_object(start) - HALF_PIXEL_DIAGONAL
        good = con.hit & ((free >= clearance_px) | (clearance_px == 0))
        candidate = candidate[good]
        # Exactly `travel` of pusher motion after the (refined) contact.
        end = con.point[good] + travel_px * direction[good]
        candidate[:, 2:] = end
        out = np.vstack([out, candidate])
    if len(out) < n:
        raise ValueError(
            "could not sample pushes: the mask's outline admits no valid push with "
            f"clearance={float(clearance):g} m and standoff={float(standoff):g} m (each start "
            "must lie at least clearance from the object): lower clearance (0 disables it)"
        )
    return out[:n]
