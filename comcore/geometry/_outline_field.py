"""The outline of a mask as a smoothed signed distance, and where a round pusher meets it.

The outline is the boundary of the object's pixel squares (as in
:func:`comcore.geometry.contacts`); its signed distance is smoothed with a Gaussian of
``SDF_SMOOTHING_PX`` to remove the staircase of a pixel outline, so that its
gradient is a usable normal: on straight edges it equals
:meth:`comcore.Mask.inward_normals`, at corners it points from the corner to
the disc's centre, as for a real round pusher.
"""

from __future__ import annotations

import weakref
from functools import partial

import numpy as np
from scipy import ndimage

from .._mask import Mask
from .._neighbourhood import LocalArrays, filter_halo, margin_px, padded_crop
from .._validation import check_actions, check_count, check_mask, check_positive
from ._contacts import clip_to_box

__all__ = ["OutlineField", "outline_field"]

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
        )  # fmt: skip

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
