"""The contact of a round pusher: :func:`disc_contacts`, and the pushes an estimator can score.

An action is the path of the pusher's leading point; a round pusher touches the
object where its disc first meets the outline, which on a push at 60-80 degrees
to the normal can be where the leading point's line misses the mask altogether.
:func:`pusher_contacts` is the contact every estimator scores: the disc's for a
pusher with a radius, the leading line's (:func:`comcore.geometry.contacts`) for a point.
:func:`usable_pushes` keeps the pushes it can score and reports the others
(:class:`comcore.SkippedPush`), refusing only a batch that is mostly unusable (a
frame or unit mistake, not a few grazing pushes).
"""

from __future__ import annotations

import numpy as np

from .._mask import Mask
from .._types import SkippedPush
from .._validation import check_actions, check_mask, check_positive
from ._contacts import MARCH_STEP_PX, Contacts, clip_to_box, contacts
from ._outline_field import CONTACT_BISECTIONS, FIELD_PAD_PX, OutlineField, outline_field

__all__ = ["disc_contacts", "pusher_contacts", "usable_pushes"]


def disc_contacts(mask: Mask, actions, pusher_radius: float) -> Contacts:
    """Where a round pusher swept along each push first touches the object.

    An action is the path of the pusher's LEADING point; the disc's centre runs
    ``pusher_radius`` behind it and touches the object where it first comes
    within the radius of the outline, which can happen where the leading point's
    line misses the mask (a push at 60-80 degrees to the outline's normal meets
    the object with the disc's side). :func:`contacts` follows the leading
    point's line only; this is the contact a motion model and the Voting
    Theorem need for such pushes. Head on, both agree to within a pixel.

    The outline is the boundary of the pixel squares, its signed distance
    smoothed (the field :class:`comcore.LimitSurfaceModel` integrates pushes
    with). The disc is marched along the path in quarter-pixel steps over the
    image, then the first touch is refined by bisection. Where the disc would
    overlap the outline at the start although its leading point is outside (a
    notch narrower than the pusher), the largest disc that fits there is used.

    Parameters
    ----------
    mask : Mask
    actions : Action, sequence of Action, or array_like, shape (n, 4)
        Paths of the pusher's leading point, pixels.
    pusher_radius : float
        Radius of the round pusher, **metres** (>= 0; 0 is a point pusher
        following the smoothed outline).

    Returns
    -------
    Contacts
        ``point``: where the disc first touches the outline (pixels; the start
        for a miss or a start inside); ``normal``: the unit inward normal there
        (zeros when no hit); ``hit``; ``starts_inside`` (as :func:`contacts`
        decides it); ``travel``: pixels the pusher travels before it touches.

    Raises
    ------
    TypeError, ValueError
        If ``mask`` or ``actions`` is invalid, or ``pusher_radius`` is not a
        finite number >= 0.

    Examples
    --------
    A push along row 1.5, just above a square's top edge (row 2.5 is its
    outline), to the right: the leading point's line misses the square, the
    side of a 1.5-pixel disc touches its top-left corner.

    >>> import numpy as np
    >>> from comcore import Mask
    >>> from comcore.geometry import contacts
    >>> img = np.zeros((14, 14), bool); img[3:11, 4:12] = True
    >>> mask, push = Mask(img, resolution=0.001), [(-6.0, 1.5, 13.0, 1.5)]
    >>> c = disc_contacts(mask, push, 0.0015)
    >>> contacts(mask, push).hit.tolist(), c.hit.tolist(), bool(3.0 < c.point[0, 0] < 4.5)
    ([False], [True], True)
    >>> disc_contacts(mask, push, -1.0)
    Traceback (most recent call last):
    ...
    ValueError: pusher_radius must be a finite number >= 0, got -1.0
    """
    mask = check_mask(mask)
    acts = check_actions(actions)
    radius = check_positive(pusher_radius, "pusher_radius", allow_zero=True) / mask.resolution
    n = acts.shape[0]
    start = acts[:, :2]
    delta = acts[:, 2:] - start
    length = np.hypot(delta[:, 0], delta[:, 1])
    unit = delta / length[:, None]
    pad = int(np.ceil(radius)) + 4
    field = outline_field(mask) if pad <= FIELD_PAD_PX else OutlineField(mask, pad=pad)
    starts_inside = mask._contains(start)
    lead = field.distance(start[:, 0], start[:, 1])
    starts_inside |= lead <= 0.0
    radii = np.full(n, radius)
    if radius > 0:  # a disc overlapping the outline behind an outside leading point: shrink it
        back = start - radius * unit
        overlap = (field.distance(back[:, 0], back[:, 1]) <= radius) & ~starts_inside
        radii[overlap] = np.minimum(radius, 0.45 * lead[overlap])
    centre0 = start - radii[:, None] * unit
    # March the centre only where it can touch: over the image grown by the disc's radius.
    grow = np.ceil(radii.max(initial=0.0)) + 1.0
    h, w = mask.shape
    t_in, t_out = clip_to_box(centre0 + grow, unit, length, (h + 2 * grow, w + 2 * grow))
    k0 = np.floor(t_in / MARCH_STEP_PX)
    k1 = np.minimum(np.ceil(t_out / MARCH_STEP_PX), np.ceil(length / MARCH_STEP_PX))
    crosses = (t_in <= t_out) & ~starts_inside
    k0, k1 = np.where(crosses, k0, 0.0), np.where(crosses, k1, 0.0)
    n_steps = int((k1 - k0).max()) + 1 if n else 1
    t = np.minimum((k0[:, None] + np.arange(n_steps)[None, :]) * MARCH_STEP_PX, length[:, None])
    first, hit = field.first_touch(centre0, unit, t, radii, rows=crosses)
    rows = np.arange(n)
    lo = np.where(hit, np.maximum(t[rows, first] - MARCH_STEP_PX, 0.0), 0.0)
    hi = np.where(hit, t[rows, first], 0.0)
    for _ in range(CONTACT_BISECTIONS):
        mid = 0.5 * (lo + hi)
        d = field.distance(centre0[:, 0] + mid * unit[:, 0], centre0[:, 1] + mid * unit[:, 1])
        inside = d <= radii
        hi, lo = np.where(inside, mid, hi), np.where(inside, lo, mid)
    travel = np.where(hit, hi, 0.0)
    centre = centre0 + travel[:, None] * unit
    dist, gx, gy = field.sample(centre[:, 0], centre[:, 1])
    inward = -np.column_stack([gx, gy])
    point = np.where(hit[:, None], centre + dist[:, None] * inward, start)
    normal = np.where(hit[:, None], inward, 0.0)
    return Contacts(point=point, normal=normal, hit=hit, starts_inside=starts_inside, travel=travel)


def pusher_contacts(mask: Mask, actions, pusher_radius: float) -> Contacts:
    """The contact every estimator scores: the disc's (``pusher_radius`` > 0, metres) or the line's.

    ``pusher_radius=0`` is a point pusher: :func:`comcore.geometry.contacts`, the leading
    point's line on the pixel mask (the paper's estimators' default).
    """
    if pusher_radius == 0:
        return contacts(mask, actions)
    return disc_contacts(mask, actions, pusher_radius)


def usable_pushes(con: Contacts, name: str = "actions", *, most: bool = True):
    """The pushes that can be scored (a bool array) and a :class:`SkippedPush` for each other.

    A push is usable when its pusher starts outside the object and touches it.
    Raises ValueError naming the first unusable pushes when none is usable, or
    (``most=True``, for recorded pushes) when more than half are not: a batch
    that mostly misses the object is a mistake of frame or units (x and y
    swapped, another resolution), not a few grazing pushes.
    """
    usable = con.hit & ~con.starts_inside
    bad = np.flatnonzero(~usable)
    n = len(usable)
    if len(bad) and (not usable.any() or (most and 2 * len(bad) > n)):
        inside = np.flatnonzero(con.starts_inside)[:5].tolist()
        misses = np.flatnonzero(~con.hit & ~con.starts_inside)[:5].tolist()
        raise ValueError(
            f"{name} must start outside the object and touch it: {len(bad)} of {n} do not "
            f"(starting inside: {inside}, missing: {misses}, the first of each); pushes in "
            "another frame (x and y swapped?) or at another resolution than the mask's?"
        )
    skipped = []
    for i in bad:
        inside = bool(con.starts_inside[i])
        what = "starts inside the object" if inside else "never touches the object"
        reason = "starts_inside" if inside else "misses"
        skipped.append(SkippedPush(int(i), "", reason, f"{name}[{int(i)}] {what}"))
    return usable, tuple(skipped)
