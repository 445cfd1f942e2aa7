"""Contact geometry: where a push meets the object, the normal there, line sides."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._mask import Mask
from .._validation import check_actions, check_mask, check_points, check_positive
from ..conventions import quarter_turn_ccw

__all__ = ["Contacts", "clip_to_box", "contacts", "signed_line_distance", "split_by_line"]

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
    t_in, t_out = clip_to_box(start, direction, length, mask.shape)
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


def clip_to_box(start, direction, length, shape) -> tuple[np.ndarray, np.ndarray]:
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
