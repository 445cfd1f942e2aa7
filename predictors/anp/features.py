"""The ANP's inputs in a normalised object frame (numpy only, no torch).

The network never sees pixels. Every object is described in its own frame:

* origin at the mask's area centroid ``c`` (pixels), axes those of the pixel
  frame (x right, y down: :mod:`comcore.conventions`), unit length ``L``
  pixels, where ``L`` is :data:`CROP_MARGIN` times the largest distance from
  the centroid to an object pixel. A point ``p`` (pixels) has coordinates
  ``u = (p - c) / L``; the whole object lies in the unit disc.
* the mask is resampled into a ``size x size`` image covering the square
  ``[-1, 1]^2`` (pixel ``j`` has its centre at ``u = (2 j + 1) / size - 1``,
  the ``align_corners=False`` convention of ``torch.nn.functional.grid_sample``).
* a motion ``(theta, tx, ty)`` becomes ``(theta / THETA_SCALE, tx / (L T_SCALE),
  ty / (L T_SCALE))``: theta keeps its sign convention (CCW on screen), the
  centroid's displacement is measured in object lengths.

Because the crop is centred on the centroid, the eight symmetries of the
square map the frame onto itself exactly; :func:`dihedral` applies one to an
episode (used as data augmentation, exact up to floating point).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from comcore import Mask
from comcore.checks import check_actions, check_mask, check_motions
from comcore.geometry import contacts, signed_line_distance

__all__ = [
    "CROP_MARGIN",
    "N_PUSH_FEATURES",
    "THETA_SCALE",
    "T_SCALE",
    "ObjectFrame",
    "dihedral",
    "motions_from_targets",
    "object_frame",
    "push_features",
    "targets_from_motions",
]

#: The crop's half-width is this times the largest centroid-to-pixel distance.
CROP_MARGIN = 1.15
#: Radians of rotation that map to 1 in the network's targets.
THETA_SCALE = 0.2
#: Object lengths of displacement that map to 1 in the network's targets.
T_SCALE = 0.3
#: Reference length (metres) of the size feature ``log(L_m / SIZE_REF_M)``.
SIZE_REF_M = 0.05
#: Columns of :func:`push_features`.
N_PUSH_FEATURES = 14


@dataclass(frozen=True)
class ObjectFrame:
    """A mask in its normalised frame.

    Attributes
    ----------
    image : numpy.ndarray of float32, shape (size, size)
        Occupancy in ``[0, 1]`` resampled over ``[-1, 1]^2``.
    center : tuple of float
        The mask's area centroid ``(x, y)``, pixels: the frame's origin.
    length_px : float
        ``L``, the frame's unit length in pixels.
    resolution : float
        Metres per pixel of the mask.
    """

    image: np.ndarray
    center: tuple[float, float]
    length_px: float
    resolution: float

    @property
    def size_feature(self) -> float:
        """``log(L_m / SIZE_REF_M)``: tells the network the object's real size."""
        return float(np.log(self.length_px * self.resolution / SIZE_REF_M))

    def to_frame(self, points_px) -> np.ndarray:
        """Pixels ``(..., 2)`` to frame coordinates ``u``."""
        return (np.asarray(points_px, float) - np.asarray(self.center)) / self.length_px


def object_frame(mask: Mask, size: int = 64) -> ObjectFrame:
    """Resample ``mask`` into its normalised frame.

    Parameters
    ----------
    mask : Mask
    size : int, optional
        Side of the output image in pixels (default 64).

    Returns
    -------
    ObjectFrame

    Examples
    --------
    >>> import numpy as np
    >>> from comcore import Mask
    >>> f = object_frame(Mask(np.pad(np.ones((10, 20), bool), 5)), size=32)
    >>> f.image.shape, f.center, round(f.length_px, 2)
    ((32, 32), (14.5, 9.5), 12.66)
    >>> float(f.image[16, 16]), float(f.image[0, 0])
    (1.0, 0.0)
    """
    mask = check_mask(mask)
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or size < 4:
        raise ValueError(f"size must be an integer >= 4, got {size!r}")
    center = np.asarray(mask.centroid)
    radius = float(np.hypot(*(mask.pixels - center).T).max()) + 0.5
    length = CROP_MARGIN * radius
    u = (2 * np.arange(size) + 1) / size - 1
    xs = center[0] + length * u
    ys = center[1] + length * u
    rows, cols = np.meshgrid(ys, xs, indexing="ij")
    image = ndimage.map_coordinates(
        mask.data.astype(np.float32), [rows, cols], order=1, mode="constant", cval=0.0
    )
    return ObjectFrame(
        image=image.astype(np.float32),
        center=(float(center[0]), float(center[1])),
        length_px=length,
        resolution=mask.resolution,
    )


def push_features(mask: Mask, frame: ObjectFrame, actions) -> np.ndarray:
    """Per-push features in the object frame, shape (n, N_PUSH_FEATURES).

    Columns: start ``u`` (2), end ``u`` (2), unit direction (2), contact point
    ``u`` (2), inward normal at the contact (2), hit flag (1), travel after
    contact in object lengths (1), ``cos`` of the angle between the push and
    the normal (1), signed distance (object lengths) from the centroid to the
    push line, positive on its counter-clockwise side (1). Pushes that miss
    get the start point as contact, a zero normal and zero travel.
    """
    acts = check_actions(actions)
    con = contacts(mask, acts)
    start, end = acts[:, :2], acts[:, 2:]
    delta = end - start
    length = np.hypot(delta[:, 0], delta[:, 1])
    direction = delta / length[:, None]
    after = np.where(con.hit, length - con.travel, 0.0) / frame.length_px
    cosine = np.einsum("ij,ij->i", direction, con.normal)
    lever = signed_line_distance([frame.center], acts)[0] / frame.length_px
    return np.column_stack(
        [
            frame.to_frame(start),
            frame.to_frame(end),
            direction,
            frame.to_frame(con.point),
            con.normal,
            con.hit.astype(float),
            after,
            cosine,
            lever,
        ]
    ).astype(np.float32)


def targets_from_motions(motions, length_px: float) -> np.ndarray:
    """Motions ``(theta, tx, ty)`` in pixels to normalised targets, shape (n, 3)."""
    m = check_motions(motions)
    out = np.empty_like(m)
    out[:, 0] = m[:, 0] / THETA_SCALE
    out[:, 1:] = m[:, 1:] / (length_px * T_SCALE)
    return out.astype(np.float32)


def motions_from_targets(targets, length_px: float) -> np.ndarray:
    """Inverse of :func:`targets_from_motions` (works for means, shape (..., 3))."""
    t = np.asarray(targets, dtype=float)
    out = np.empty_like(t)
    out[..., 0] = t[..., 0] * THETA_SCALE
    out[..., 1:] = t[..., 1:] * (length_px * T_SCALE)
    return out


#: Point-feature columns (pairs) that transform as positions or vectors.
_VECTOR_PAIRS = ((0, 1), (2, 3), (4, 5), (6, 7), (8, 9))
#: Columns that change sign under a mirror and are unchanged by rotations.
_PSEUDO_SCALARS = [13]


def dihedral(image, features, targets, k: int, flip: bool, points=None):
    """Apply a symmetry of the square to an episode in the object frame.

    The symmetry is ``k`` quarter turns counter-clockwise on screen
    (:func:`comcore.conventions.rotation_matrix`), preceded by a left-right mirror when
    ``flip``. A mirror reverses the sense of rotation.

    Parameters
    ----------
    image : numpy.ndarray, shape (..., S, S)
    features : numpy.ndarray, shape (..., n, N_PUSH_FEATURES)
    targets : numpy.ndarray, shape (..., n, 3)
    k : int
    flip : bool
    points : numpy.ndarray, shape (..., 2), optional
        Positions in the frame (e.g. the true CoM) to transform too.

    Returns
    -------
    image, features, targets[, points]
        New arrays; the inputs are not modified. ``points`` only when given.

    Examples
    --------
    Four quarter turns are the identity:

    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> img, f, t = rng.random((8, 8)), rng.random((3, 14)), rng.random((3, 3))
    >>> out = dihedral(img, f, t, k=4, flip=False)
    >>> all(np.allclose(a, b) for a, b in zip(out, (img, f, t)))
    True
    """
    image = np.array(image, copy=True)
    features = np.array(features, copy=True)
    targets = np.array(targets, copy=True)
    pts = None if points is None else np.array(points, copy=True)
    if flip:
        if pts is not None:
            pts[..., 0] = -pts[..., 0]
        image = image[..., ::-1].copy()
        for x, _ in _VECTOR_PAIRS:
            features[..., x] = -features[..., x]
        features[..., _PSEUDO_SCALARS] = -features[..., _PSEUDO_SCALARS]
        targets[..., 0] = -targets[..., 0]
        targets[..., 1] = -targets[..., 1]
    for _ in range(int(k) % 4):
        # rotation_matrix(pi / 2): (x, y) -> (y, -x); np.rot90 is the same map on images.
        image = np.rot90(image, axes=(-2, -1)).copy()
        for x, y in _VECTOR_PAIRS:
            features[..., x], features[..., y] = features[..., y].copy(), -features[..., x]
        targets[..., 1], targets[..., 2] = targets[..., 2].copy(), -targets[..., 1]
        if pts is not None:
            pts[..., 0], pts[..., 1] = pts[..., 1].copy(), -pts[..., 0]
    return (image, features, targets) if pts is None else (image, features, targets, pts)
