"""Contact geometry: where a push meets the object, the normal there, line sides."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._conventions import quarter_turn_ccw
from ._mask import Mask
from ._outline_field import CONTACT_BISECTIONS, FIELD_PAD_PX, OutlineField, outline_field
from ._validation import check_actions, check_mask, check_points, check_positive

__all__ = ["Contacts", "contacts", "disc_contacts", "signed_line_distance", "split_by_line"]

#: Step (pixels) of the march along a push path before bisection refines it.
MARCH_STEP_PX = 0.25
#: Bisection steps that refine a contact after the march (0.25 / 2**6 px).
BISECTION_STEPS = 6


@dataclass(frozen=True, eq=False)
class Contacts:
    """Where a batch of pushes first touch the object.

    Attributes
    ----------
    point : numpy.ndarray, shape (n, 2)
        Contact point ``(x, y)`` in pixels: where the pusher's path first
        enters the object's pixels. For a miss or a start inside the object it
        is the start point.
    normal : numpy.ndarray, shape (n, 2)
        Unit inward normal of the outline at the contact (zeros when no hit).
    hit : numpy.ndarray of bool, shape (n,)
        The path starts outside the object and enters it.
    starts_inside : numpy.ndarray of bool, shape (n,)
        The path starts on an object pixel (no contact can be defined).
    travel : numpy.ndarray, shape (n,)
        Distance (pixels) the pusher travels before contact (0 when no hit).
    """

    point: np.ndarray
    normal: np.ndarray
    hit: np.ndarray
    starts_inside: np.ndarray
    travel: np.ndarray

    def __post_init__(self):
        for name in ("point", "normal", "hit", "starts_inside", "travel"):
            getattr(self, name).setflags(write=False)

    @property
    def status(self) -> np.ndarray:
        """Per push: ``"hit"``, ``"miss"`` or ``"starts_inside"`` (array of str)."""
        out = np.full(self.hit.shape, "miss", dtype=object)
        out[self.hit] = "hit"
        out[self.starts_inside] = "starts_inside"
        return out

    def require_hits(self, name: str = "actions") -> None:
        """Raise ValueError naming the pushes that miss the object or start inside it."""
        if self.starts_inside.any():
            bad = np.flatnonzero(self.starts_inside)[:5].tolist()
            raise ValueError(
                f"{name} must start outside the object; action(s) {bad} start inside it"
            )
        if not self.hit.all():
            bad = np.flatnonzero(~self.hit)[:5].tolist()
            raise ValueError(f"{name} must hit the object; action(s) {bad} miss it")


def contacts(mask: Mask, actions) -> Contacts:
    """Contact point and inward normal of each push on the mask.

    The path is marched from start to end in steps of ``MARCH_STEP_PX`` and the
    first step onto an object pixel is refined by bisection. Only the steps over
    the image (plus a pixel all round) are taken, so the cost depends on the
    image's size and not on how far away a push starts or ends. The normal comes
    from the smoothed mask (:meth:`Mask.inward_normals`), not a single pixel
    step. The pusher is treated as a point moving along the action's line.

    Parameters
    ----------
    mask : Mask
    actions : Action, sequence of Action, or array_like, shape (n, 4)

    Returns
    -------
    Contacts
        Batched, even for a single action.

    Examples
    --------
    A push from the left along row 5 onto a square occupying columns 3..8:

    >>> import numpy as np
    >>> from comcore import Mask, Action
    >>> img = np.zeros((11, 12), bool); img[2:9, 3:9] = True
    >>> c = contacts(Mask(img), Action(0, 5, 10, 5))
    >>> c.hit.tolist(), np.round(c.point, 1).tolist(), np.round(c.normal, 2).tolist()
    ([True], [[2.5, 5.0]], [[1.0, 0.0]])
    >>> contacts(Mask(img), [(0, 0, 0, 1)]).status.tolist()
    ['miss']
    """
    mask = check_mask(mask)
    acts = check_actions(actions)
    n = acts.shape[0]
    start, end = acts[:, :2], acts[:, 2:]
    delta = end - start
    length = np.hypot(delta[:, 0], delta[:, 1])
    direction = delta / length[:, None]
    # March only the part of each path over the image: march indices k0..k1 of the
    # full march (t = k * MARCH_STEP_PX from the start), so the samples are the full
    # march's own and the contact is the same, at a cost set by the image, not the path.
    t_in, t_out = _clip_to_box(start, direction, length, mask.shape)
    k0 = np.floor(t_in / MARCH_STEP_PX)
    k_last = np.ceil(length / MARCH_STEP_PX)  # the full march's last step reaches the end
    k1 = np.minimum(np.ceil(t_out / MARCH_STEP_PX), k_last)
    crosses = t_in <= t_out
    k0, k1 = np.where(crosses, k0, 0.0), np.where(crosses, k1, 0.0)
    n_steps = int((k1 - k0).max()) + 1 if n else 1
    k = k0[:, None] + np.arange(n_steps)[None, :]  # (n, n_steps) indices into the full march
    t = np.minimum(k * MARCH_STEP_PX, length[:, None])
    samples = start[:, None, :] + t[..., None] * direction[:, None, :]
    inside = mask._contains(samples.reshape(-1, 2)).reshape(n, n_steps)
    inside &= crosses[:, None]
    starts_inside = mask._contains(start)
    hit = inside.any(axis=1) & ~starts_inside
    first = np.argmax(inside, axis=1)
    k_first = k[np.arange(n), first]
    lo = np.where(hit, np.minimum(np.maximum(k_first - 1, 0) * MARCH_STEP_PX, length), 0.0)
    hi = np.where(hit, t[np.arange(n), first], 0.0)
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        inn = mask._contains(start + mid[:, None] * direction)
        hi = np.where(inn, mid, hi)
        lo = np.where(inn, lo, mid)
    travel = np.where(hit, 0.5 * (lo + hi), 0.0)
    point = start + travel[:, None] * direction
    normal = np.zeros_like(point)
    if hit.any():
        nrm = mask.inward_normals(point[hit])
        # A vanishing gradient (a one-pixel sliver) falls back to facing the push.
        degenerate = ~np.any(nrm != 0, axis=1)
        nrm[degenerate] = direction[hit][degenerate]
        normal[hit] = nrm
    return Contacts(point=point, normal=normal, hit=hit, starts_inside=starts_inside, travel=travel)


def disc_contacts(mask: Mask, actions, pusher_radius: float) -> Contacts:
    """Where a round pusher swept along each push first touches the object.

    An action is the path of the pusher's LEADING point (as everywhere in
    comcore); the disc's centre runs ``pusher_radius`` behind it. The disc
    touches the object where its centre first comes within the radius of the
    outline, which can happen where the leading point's line misses the mask
    altogether: a push at 60-80 degrees to the outline's normal meets the
    object with the side of the disc. :func:`contacts` follows the leading
    point's line only; this function is the contact a motion model and the
    Voting Theorem need for such pushes. Head on, both agree to within a
    pixel.

    The outline is the boundary of the object's pixel squares, its signed
    distance smoothed to remove the pixel staircase (the field
    :class:`comcore.LimitSurfaceModel` integrates pushes with, so the contact
    here is the model's). The disc is marched along the path in quarter-pixel
    steps over the image only, then the first touch is refined by bisection.
    Where the disc would overlap the outline at the start although its
    leading point is outside (a notch narrower than the pusher), the largest
    disc that surely fits there is used, as the model does.

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
        point for a miss or a start inside); ``normal``: the outline's unit
        inward normal there (pointing from the disc's centre into the object;
        zeros when no hit); ``hit``; ``starts_inside`` (the leading point
        starts on an object pixel, as :func:`contacts` decides it);
        ``travel``: pixels the pusher travels before it touches.

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
    >>> from comcore import Mask, contacts
    >>> img = np.zeros((14, 14), bool); img[3:11, 4:12] = True
    >>> mask, push = Mask(img, resolution=0.001), [(-6.0, 1.5, 13.0, 1.5)]
    >>> contacts(mask, push).hit.tolist(), disc_contacts(mask, push, 0.0015).hit.tolist()
    ([False], [True])
    >>> c = disc_contacts(mask, push, 0.0015)
    >>> bool(3.0 < c.point[0, 0] < 4.5 and 2.0 < c.point[0, 1] < 3.0)
    True
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
    lead = field.sample(start[:, 0], start[:, 1])[0]
    starts_inside |= lead <= 0.0
    radii = np.full(n, radius)
    if radius > 0:  # a disc overlapping the outline behind an outside leading point: shrink it
        back = start - radius * unit
        overlap = (field.sample(back[:, 0], back[:, 1])[0] <= radius) & ~starts_inside
        radii[overlap] = np.minimum(radius, 0.45 * lead[overlap])
    centre0 = start - radii[:, None] * unit
    # March the centre only where it can touch: over the image grown by the disc's radius.
    grow = np.ceil(radii.max(initial=0.0)) + 1.0
    h, w = mask.shape
    t_in, t_out = _clip_to_box(centre0 + grow, unit, length, (h + 2 * grow, w + 2 * grow))
    k0 = np.floor(t_in / MARCH_STEP_PX)
    k1 = np.minimum(np.ceil(t_out / MARCH_STEP_PX), np.ceil(length / MARCH_STEP_PX))
    crosses = (t_in <= t_out) & ~starts_inside
    k0, k1 = np.where(crosses, k0, 0.0), np.where(crosses, k1, 0.0)
    n_steps = int((k1 - k0).max()) + 1 if n else 1
    t = np.minimum((k0[:, None] + np.arange(n_steps)[None, :]) * MARCH_STEP_PX, length[:, None])
    px = centre0[:, :1] + t * unit[:, :1]
    py = centre0[:, 1:] + t * unit[:, 1:]
    touching = (field.sample(px, py)[0] <= radii[:, None]) & crosses[:, None]
    hit = touching.any(axis=1)
    first = np.argmax(touching, axis=1)
    rows = np.arange(n)
    lo = np.where(hit, np.maximum(t[rows, first] - MARCH_STEP_PX, 0.0), 0.0)
    hi = np.where(hit, t[rows, first], 0.0)
    for _ in range(CONTACT_BISECTIONS):
        mid = 0.5 * (lo + hi)
        d = field.sample(centre0[:, 0] + mid * unit[:, 0], centre0[:, 1] + mid * unit[:, 1])[0]
        inside = d <= radii
        hi, lo = np.where(inside, mid, hi), np.where(inside, lo, mid)
    travel = np.where(hit, hi, 0.0)
    centre = centre0 + travel[:, None] * unit
    dist, gx, gy = field.sample(centre[:, 0], centre[:, 1])
    inward = -np.column_stack([gx, gy])
    point = np.where(hit[:, None], centre + dist[:, None] * inward, start)
    normal = np.where(hit[:, None], inward, 0.0)
    return Contacts(point=point, normal=normal, hit=hit, starts_inside=starts_inside, travel=travel)


def _clip_to_box(start, direction, length, shape) -> tuple[np.ndarray, np.ndarray]:
    """Where each path ``start + t * direction``, ``0 <= t <= length``, is over the image.

    The box is the image's pixels plus one pixel all round, so every point that
    :meth:`Mask.contains` can find inside lies strictly within it. Returns
    ``(t_in, t_out)`` per path (Liang-Barsky); ``t_in > t_out`` where the path
    never crosses the box.
    """
    h, w = shape
    box_lo = np.array([-1.5, -1.5])
    box_hi = np.array([w + 0.5, h + 0.5])
    t_in = np.zeros(len(start))
    t_out = np.asarray(length, dtype=float).copy()
    for axis in range(2):
        p, d = start[:, axis], direction[:, axis]
        flat = d == 0.0
        safe = np.where(flat, 1.0, d)
        ta, tb = (box_lo[axis] - p) / safe, (box_hi[axis] - p) / safe
        near, far = np.minimum(ta, tb), np.maximum(ta, tb)
        outside = flat & ((p < box_lo[axis]) | (p > box_hi[axis]))
        t_in = np.where(flat, t_in, np.maximum(t_in, near))
        t_out = np.where(flat, t_out, np.minimum(t_out, far))
        t_out = np.where(outside, -1.0, t_out)
    return t_in, t_out


def signed_line_distance(points, actions) -> np.ndarray:
    """Signed distance (pixels) from points to each action's line.

    Positive on the counter-clockwise side of the push direction as seen on
    screen (the pusher's left when the screen is viewed normally).

    Parameters
    ----------
    points : array_like, shape (m, 2)
    actions : Action, sequence of Action, or array_like, shape (n, 4)

    Returns
    -------
    numpy.ndarray, shape (m, n)

    Examples
    --------
    A push to the right (+x): the row above it (smaller y) is on its CCW side.

    >>> signed_line_distance([[5.0, 3.0], [5.0, 7.0]], [(0, 5, 10, 5)]).ravel().tolist()
    [2.0, -2.0]
    """
    return line_distances(check_points(points), check_actions(actions))


def _line_params(actions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(left, offset)`` of each action's line: signed distance ``p . left - offset``.

    ``left`` is the unit push direction turned a quarter turn counter-clockwise
    on screen, so the distance is positive on the counter-clockwise side.
    """
    start = actions[:, :2]
    delta = actions[:, 2:] - start
    direction = delta / np.hypot(delta[:, 0], delta[:, 1])[:, None]
    left = quarter_turn_ccw(direction)  # (n, 2)
    return left, np.einsum("ij,ij->i", left, start)


def line_distances(points: np.ndarray, actions: np.ndarray, dtype=np.float64) -> np.ndarray:
    """Unvalidated core of :func:`signed_line_distance`: one (m, 2) x (2, n) product.

    The signed distance is ``(p - start) . left`` with ``left`` the push
    direction turned a quarter turn counter-clockwise on screen.
    """
    left, offset = _line_params(actions)
    out = points.astype(dtype, copy=False) @ left.T.astype(dtype)
    out -= offset.astype(dtype)
    return out


def side_counts(region: np.ndarray, actions: np.ndarray, band: float):
    """Pixels of a boolean image more than ``band`` px on each side of many lines.

    Unvalidated; ``actions`` is (n, 4). Counts row by row from prefix sums:
    along a pixel row the signed distance is linear in x, so the pixels beyond
    a line form one run whose length a cumulative count gives. The cost is
    (rows x lines), not (pixels x lines). A pixel exactly ``band`` from a line
    (a tie) may fall either way by rounding, as with any distance threshold.

    Returns
    -------
    ccw, cw : numpy.ndarray of int, shape (n,)
        Counts on the counter-clockwise side (distance > ``band``) and the
        clockwise side (distance < ``-band``).
    """
    n = actions.shape[0]
    occupied = np.flatnonzero(region.any(axis=1))
    if n == 0 or occupied.size == 0:
        return np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64)
    r0, r1 = occupied[0], occupied[-1] + 1
    width = region.shape[1]
    cum = np.zeros((r1 - r0, width + 1), dtype=np.int64)  # cum[y, c]: pixels left of column c
    np.cumsum(region[r0:r1], axis=1, out=cum[:, 1:])
    left, offset = _line_params(actions)
    slope = left[:, :1]  # d = slope * x + intercept along a row
    intercept = left[:, 1:] * np.arange(r0, r1) - offset[:, None]  # (n, rows)
    row = np.arange(r1 - r0)
    total = cum[:, width]

    def beyond(slope, intercept):  # pixels with slope * x + intercept > band
        safe = np.where(slope == 0.0, 1.0, slope)
        edge = (band - intercept) / safe  # the run starts (slope > 0) or ends (< 0) here
        first = np.clip(np.floor(edge) + 1.0, 0, width).astype(np.intp)
        stop = np.clip(np.ceil(edge), 0, width).astype(np.intp)
        count = np.where(slope > 0, total - cum[row, first], cum[row, stop])
        count = np.where(slope == 0.0, np.where(intercept > band, total, 0), count)
        return count.sum(axis=1)

    return beyond(slope, intercept), beyond(-slope, -intercept)


def split_by_line(mask: Mask, action, band: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Split the mask's pixels by an action's line, leaving out a band around it.

    Parameters
    ----------
    mask : Mask
    action : Action or array_like, shape (4,)
    band : float, optional
        Pixels whose centre lies within ``band`` pixels of the line belong to
        neither side (the paper's ``d_t``, default 0.5 px).

    Returns
    -------
    ccw_side, cw_side : numpy.ndarray of bool, shape (H, W)
        Object pixels on the counter-clockwise (left on screen) and clockwise
        side of the push direction.

    Examples
    --------
    >>> import numpy as np
    >>> from comcore import Mask
    >>> left, right = split_by_line(Mask(np.ones((5, 5), bool)), (0, 2, 4, 2))
    >>> int(left.sum()), int(right.sum())
    (10, 10)
    """
    mask = check_mask(mask)
    acts = check_actions(action)
    if acts.shape[0] != 1:
        raise ValueError(f"action must be a single action, got {acts.shape[0]}")
    band = check_positive(band, "band", allow_zero=True)
    d = signed_line_distance(mask.pixels, acts)[:, 0]
    ccw = np.zeros(mask.shape, bool)
    cw = np.zeros(mask.shape, bool)
    rows, cols = mask.pixels[:, 1].astype(int), mask.pixels[:, 0].astype(int)
    ccw[rows, cols] = d > band
    cw[rows, cols] = d < -band
    return ccw, cw
