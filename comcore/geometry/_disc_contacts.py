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

import weakref
from functools import partial

import numpy as np
from scipy import ndimage

from .._mask import Mask
from .._neighbourhood import LocalArrays, filter_halo, margin_px, padded_crop
from .._types import SkippedPush
from .._validation import check_actions, check_count, check_mask, check_positive
from ._contacts import MARCH_STEP_PX, Contacts, clip_to_box, contacts

__all__ = [
    "OutlineField",
    "disc_contacts",
    "outline_field",
    "pusher_contacts",
    "usable_pushes",
]


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


#: Gaussian sigma (pixels) smoothing the pixel outline's signed distance.
SDF_SMOOTHING_PX = 1.0
#: Padding (pixels) of the distance field around the mask image.
FIELD_PAD_PX = 24
#: Pixels from a cut edge of the neighbourhood that the smoothing and the gradient reach.
FIELD_HALO_PX = filter_halo(SDF_SMOOTHING_PX)
#: March step (pixels) and bisections of the search for the first contact.
CONTACT_MARCH_PX, CONTACT_BISECTIONS = 0.25, 8
#: Steps of a march read at a time (:meth:`OutlineField.first_touch`).
CONTACT_CHUNK = 64


class OutlineField:
    """Smoothed signed distance (px, > 0 outside) to a mask's pixel outline, and its gradient.

    What a model of a round pusher on a mask needs (:class:`comcore.LimitSurfaceModel`,
    ``predictors.EllipsoidPredictor``): the distance and outward normal anywhere
    (:meth:`sample`) and where each pusher first touches the outline
    (:meth:`pusher_paths`). Get one with :func:`outline_field` (cached per mask).

    Parameters
    ----------
    mask : Mask
    pad : int, optional
        Pixels of distance field kept around the mask's image.
    """

    def __init__(self, mask: Mask, pad: int = FIELD_PAD_PX):
        mask = check_mask(mask)
        self.pad = pad = check_count(pad, "pad")
        self.shape = mask.shape  # the image's (H, W): the march stops this side of its padding
        # On the object's neighbourhood, grown when asked elsewhere: the whole image's numbers.
        window = mask._box.grown_by(margin_px(mask.resolution) + FIELD_HALO_PX, pad)
        self._local = LocalArrays(
            window, partial(_fields, mask.data, pad), FIELD_HALO_PX, margin_px(mask.resolution),
        )

    def sample(self, x, y):
        """Distance and unit outward gradient ``(gx, gy)`` at points ``(x, y)`` (bilinear)."""
        shape = np.shape(x)
        d, gx, gy = self._local.interpolate(np.ravel(y) + self.pad, np.ravel(x) + self.pad)
        norm = np.maximum(np.hypot(gx, gy), 1e-12)
        return d.reshape(shape), (gx / norm).reshape(shape), (gy / norm).reshape(shape)

    def distance(self, x, y) -> np.ndarray:
        """The distance of :meth:`sample` alone (its gradient not interpolated)."""
        (d,) = self._local.interpolate(np.ravel(y) + self.pad, np.ravel(x) + self.pad, count=1)
        return d.reshape(np.shape(x))

    def first_touch(self, origin, unit, t, radius, rows=None, chunk: int = CONTACT_CHUNK):
        """Per path, the first step where a disc is within ``radius`` of the outline.

        The disc's centre at step ``k`` of path ``i`` is ``origin[i] + t[i, k] * unit[i]``
        (``t`` (n, m) pixels, ``radius`` (n,)). Returns ``(first, hit)``: the step's
        index (0 where none touches) and whether one does; ``rows`` (bool (n,)) leaves
        the others out (not hit). The steps are read ``chunk`` at a time and a path is
        dropped once it touches: the same answer as reading every step.
        """
        n, m = np.shape(t)
        first, hit = np.zeros(n, dtype=np.intp), np.zeros(n, dtype=bool)
        live = np.arange(n) if rows is None else np.flatnonzero(rows)
        for k in range(0, m, chunk):
            if not len(live):
                break
            tk = t[live, k : k + chunk]
            px = origin[live, :1] + tk * unit[live, :1]
            py = origin[live, 1:] + tk * unit[live, 1:]
            touching = self.distance(px, py) <= radius[live, None]
            got = touching.any(axis=1)
            first[live[got]] = k + np.argmax(touching[got], axis=1)
            hit[live[got]] = True
            live = live[~got]
        return first, hit

    def pusher_paths(self, actions, radius):
        """Where each push's disc first touches the outline, and how far it goes on.

        An action is the path of the disc's leading point; its centre runs
        ``radius`` behind. Where that disc would overlap the outline at the start
        (a notch), the largest disc that surely fits (0.45 of the leading point's
        distance to the outline) is used instead. Raises ValueError for an action
        whose leading point starts inside the object.

        Parameters
        ----------
        actions : array_like, shape (n, 4)
            Paths of the pusher's leading point, pixels.
        radius : float
            The pusher's radius in pixels (>= 0).

        Returns
        -------
        centres : numpy.ndarray, shape (n, 2)
            The disc's centre at first contact (at the path's start for a miss).
        units : numpy.ndarray, shape (n, 2)
            Unit push directions.
        travel : numpy.ndarray, shape (n,)
            Travel after first contact, pixels (0 for a miss).
        hit : numpy.ndarray of bool, shape (n,)
        radii : numpy.ndarray, shape (n,)
            The disc's radius used for each action.
        """
        actions = check_actions(actions)
        radius = check_positive(radius, "radius", allow_zero=True)
        delta = actions[:, 2:] - actions[:, :2]
        length = np.hypot(delta[:, 0], delta[:, 1])
        unit = delta / length[:, None]
        lead = self.distance(actions[:, 0], actions[:, 1])
        if (lead <= 0).any():
            bad = np.flatnonzero(lead <= 0)[:5].tolist()
            raise ValueError(
                f"actions must start outside the object; action(s) {bad} start inside it"
            )
        radii = np.full(len(actions), float(radius))
        if radius > 0:
            back = actions[:, :2] - radius * unit
            overlap = self.distance(back[:, 0], back[:, 1]) <= radius
            radii[overlap] = np.minimum(radius, 0.45 * lead[overlap])
        start = actions[:, :2] - radii[:, None] * unit
        travel, hit = _first_contact(self, start, unit, length, radii)
        return start + travel[:, None] * unit, unit, np.where(hit, length - travel, 0.0), hit, radii


def _fields(data: np.ndarray, pad: int, window) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The smoothed signed distance and its gradient ``(sdf, gx, gy)`` on a padded window."""
    img = padded_crop(data, pad, window)
    outside = ndimage.distance_transform_edt(~img)
    inside = ndimage.distance_transform_edt(img)
    sdf = ndimage.gaussian_filter(
        np.where(img, 0.5 - inside, outside - 0.5), SDF_SMOOTHING_PX, mode="nearest"
    )
    gy, gx = np.gradient(sdf)
    return sdf, gx, gy


_FIELDS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def outline_field(mask: Mask) -> OutlineField:
    """The :class:`OutlineField` of a mask, computed once per mask (masks are immutable).

    Examples
    --------
    >>> import numpy as np, comcore
    >>> field = comcore.geometry.outline_field(comcore.Mask(np.pad(np.ones((20, 20), bool), 10)))
    >>> x, y = np.array([4.0]), np.array([19.5])  # left of the square, whose outline is at x = 9.5
    >>> distance, gx, gy = field.sample(x, y)
    >>> round(float(distance[0]), 1), round(float(gx[0]), 3), round(float(gy[0]), 3)
    (5.5, -1.0, 0.0)
    """
    field = _FIELDS.get(check_mask(mask))
    if field is None:
        field = _FIELDS[mask] = OutlineField(mask)
    return field


def _first_contact(field, start, unit, length, radius):
    """Travel to first contact of a disc of ``radius`` along each path, and a hit flag.

    Each path is marched at ``t = k * CONTACT_MARCH_PX`` only where it passes over the image
    grown by the field's padding and the largest radius (steps ``k0..k1`` of the full march,
    so the samples and the contact are the full march's): farther out the distance exceeds
    every radius. The cost is set by the image, never by the path's length.
    """
    grow = float(radius.max(initial=0.0)) + field.pad + 2.0
    h, w = field.shape
    t_in, t_out = clip_to_box(start + grow, unit, length, (h + 2 * grow, w + 2 * grow))
    crosses = t_in <= t_out
    k_last = np.ceil(length / CONTACT_MARCH_PX)  # the full march's last step reaches the end
    k0 = np.where(crosses, np.floor(t_in / CONTACT_MARCH_PX), 0.0)
    k1 = np.where(crosses, np.minimum(np.ceil(t_out / CONTACT_MARCH_PX), k_last), 0.0)
    n = int((k1 - k0).max(initial=0.0)) + 1
    k = k0[:, None] + np.arange(n)[None, :]  # indices into the full march
    t = np.minimum(k * CONTACT_MARCH_PX, length[:, None])
    first, touches = field.first_touch(start, unit, t, radius)
    hit = touches & ~((first == 0) & (k0 == 0))  # touching at the start: not a hit
    rows = np.arange(len(start))
    k_first = k[rows, first]
    lo = np.where(hit, np.minimum(np.maximum(k_first - 1, 0) * CONTACT_MARCH_PX, length), 0.0)
    hi = np.where(hit, np.minimum(k_first * CONTACT_MARCH_PX, length), 0.0)
    for _ in range(CONTACT_BISECTIONS):
        mid = 0.5 * (lo + hi)
        inside = field.distance(start[:, 0] + mid * unit[:, 0], start[:, 1] + mid * unit[:, 1])
        inside = inside <= radius
        hi, lo = np.where(inside, mid, hi), np.where(inside, lo, mid)
    return np.where(hit, hi, 0.0), hit
