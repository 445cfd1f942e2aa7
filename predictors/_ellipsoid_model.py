"""The quasi-static pusher-slider with an ellipsoidal limit surface, vectorised.

Physics (Lynch, Maekawa and Tanie 1992; Howe and Cutkosky 1996), in the
object's body frame with the CoM as origin and everything in pixels:

* The limit surface is the ellipsoid ``fx^2 + fy^2 + (m / c)^2 = (mu_f N)^2``,
  with ``c`` the support's characteristic length (see
  :func:`predictors._ellipsoid_support.characteristic_length_sq`). By maximum
  dissipation a wrench ``(f, m)`` makes the object move with the twist
  ``(v, omega) ~ (f, m / c^2)``.
* A point contact at ``r`` (from the CoM) with inward normal ``n`` moves with
  ``v + omega * w``, ``w = (r_y, -r_x)`` (pixel frame, ``omega`` CCW on
  screen), so a contact force ``f`` moves the contact with ``A f``,
  ``A = I + w w^T / c^2``. The motion cone is ``A`` applied to the friction
  cone.
* **Sticking** (the pusher's velocity ``u`` inside the motion cone, i.e. the
  force ``g = A^-1 u`` inside the friction cone) has the closed form
  ``omega = (w . u) / (c^2 + |r|^2)``, ``v = u - omega w``.
* **Sliding** (outside): the force lies on the friction-cone edge on ``g``'s
  side, scaled so that the contact's normal velocity equals the pusher's.

The push is integrated over its path in ``n_steps`` equal steps after first
contact. At each step the pusher's end-of-step position is taken into the body
frame; the outline's signed distance there gives the contact point, its normal
and the penetration (or gap) that this step must remove, so the contact point
slides along the outline as the object turns and contact may break and resume.
The normal is the gradient of the smoothed signed distance: on straight edges
it equals :meth:`comcore.Mask.inward_normals` (to round-off), at corners it
points from the corner to the disc's centre, as for a real round pusher.
"""

from __future__ import annotations

import weakref

import numpy as np
from scipy import ndimage

from comcore import Mask

__all__ = [
    "DistanceField",
    "body_twist",
    "distance_field",
    "first_contact",
    "pusher_paths",
    "simulate",
]

#: Gaussian sigma (pixels) that smooths the pixel outline's signed distance.
SDF_SMOOTHING_PX = 1.0
#: Padding (pixels) of the distance field around the mask image.
FIELD_PAD_PX = 24
#: March step (pixels) of the search for the first contact.
CONTACT_MARCH_PX = 0.25
#: Bisection steps refining the first contact.
CONTACT_BISECTIONS = 8


class DistanceField:
    """Signed distance (pixels, > 0 outside) to a mask's outline and its gradient.

    The outline is the boundary of the object's pixel squares (as in
    :func:`comcore.contacts`); the distance is smoothed with a Gaussian of
    ``SDF_SMOOTHING_PX`` to remove the staircase of a pixel outline.
    """

    def __init__(self, mask: Mask, pad: int = FIELD_PAD_PX):
        img = np.pad(mask.data, pad)
        outside = ndimage.distance_transform_edt(~img)
        inside = ndimage.distance_transform_edt(img)
        sdf = np.where(img, 0.5 - inside, outside - 0.5)
        sdf = ndimage.gaussian_filter(sdf, SDF_SMOOTHING_PX, mode="nearest")
        gy, gx = np.gradient(sdf)
        self.pad = pad
        self._fields = (sdf, gx, gy)

    def sample_xy(self, x, y) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Distance and unit outward gradient ``(gx, gy)`` at points ``(x, y)`` (same shapes).

        Bilinear interpolation; points off the padded grid take the nearest border value.
        """
        shape = np.shape(x)
        coords = np.vstack([np.ravel(y) + self.pad, np.ravel(x) + self.pad])
        sdf, gx, gy = (
            ndimage.map_coordinates(f, coords, order=1, mode="nearest") for f in self._fields
        )
        norm = np.maximum(np.sqrt(gx * gx + gy * gy), 1e-12)
        return sdf.reshape(shape), (gx / norm).reshape(shape), (gy / norm).reshape(shape)

    def sample(self, points) -> tuple[np.ndarray, np.ndarray]:
        """Distance, shape (...), and unit outward gradient, shape (..., 2), at points."""
        p = np.asarray(points, dtype=float)
        sdf, gx, gy = self.sample_xy(p[..., 0], p[..., 1])
        return sdf, np.stack([gx, gy], axis=-1)


_FIELDS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def distance_field(mask: Mask) -> DistanceField:
    """The (cached) :class:`DistanceField` of an immutable mask."""
    field = _FIELDS.get(mask)
    if field is None:
        field = _FIELDS[mask] = DistanceField(mask)
    return field


def pusher_paths(field: DistanceField, actions: np.ndarray, radius: float):
    """Paths of the disc's centre and the disc's radius, per action.

    An action is the path of the disc's leading point; its centre runs
    ``radius`` behind. Where a disc that large would overlap the outline at
    the start (in a concave corner, or through the smoothing of the outline),
    the largest disc that surely fits is used instead (``0.45`` times the
    leading point's distance to the outline).

    Returns
    -------
    centres : numpy.ndarray, shape (n, 4)
    radii : numpy.ndarray, shape (n,)

    Raises
    ------
    ValueError
        If an action's leading point starts inside the object.
    """
    delta = actions[:, 2:] - actions[:, :2]
    unit = delta / np.hypot(delta[:, 0], delta[:, 1])[:, None]
    lead = field.sample(actions[:, :2])[0]
    if (lead <= 0).any():
        bad = np.flatnonzero(lead <= 0)[:5].tolist()
        raise ValueError(f"actions must start outside the object; action(s) {bad} start inside it")
    radii = np.full(len(actions), float(radius))
    if radius > 0:
        overlap = field.sample(actions[:, :2] - radius * unit)[0] <= radius
        radii[overlap] = np.minimum(radius, 0.45 * lead[overlap])
    return actions - np.tile(radii[:, None] * unit, 2), radii


def first_contact(field: DistanceField, actions: np.ndarray, radius):
    """Pusher travel to first contact, and hit / starts-inside flags, per action.

    The pusher is a disc of ``radius`` pixels (a number or one per action)
    whose centre follows the action.

    Returns
    -------
    travel : numpy.ndarray, shape (n,)
    hit : numpy.ndarray of bool, shape (n,)
    starts_inside : numpy.ndarray of bool, shape (n,)
    """
    start = actions[:, :2]
    delta = actions[:, 2:] - start
    length = np.hypot(delta[:, 0], delta[:, 1])
    unit = delta / length[:, None]
    n_samples = int(np.ceil(length.max(initial=0.0) / CONTACT_MARCH_PX)) + 1
    t = np.minimum(np.arange(n_samples)[None, :] * CONTACT_MARCH_PX, length[:, None])
    radius = np.broadcast_to(np.asarray(radius, dtype=float), length.shape)
    gap = field.sample(start[:, None, :] + t[..., None] * unit[:, None, :])[0] - radius[:, None]
    touching = gap <= 0
    starts_inside = touching[:, 0]
    hit = touching.any(axis=1) & ~starts_inside
    first = np.argmax(touching, axis=1)
    rows = np.arange(len(actions))
    lo = np.where(hit, t[rows, np.maximum(first - 1, 0)], 0.0)
    hi = np.where(hit, t[rows, first], 0.0)
    for _ in range(CONTACT_BISECTIONS):
        mid = 0.5 * (lo + hi)
        inside = field.sample(start + mid[:, None] * unit)[0] - radius <= 0
        hi = np.where(inside, mid, hi)
        lo = np.where(inside, lo, mid)
    return np.where(hit, hi, 0.0), hit, starts_inside


def _twist(rx, ry, nx, ny, ux, uy, c2, mu, cos_a, sin_a):
    """Component form of :func:`body_twist` (the hot loop of :func:`simulate`).

    ``cos_a, sin_a`` are the cosine and sine of the friction cone's half-angle ``atan(mu)``.
    """
    # w = (r_y, -r_x): the contact's velocity per unit CCW-on-screen rotation about the CoM.
    wx, wy = ry, -rx
    wu = wx * ux + wy * uy
    omega_stick = wu / (c2 + rx * rx + ry * ry)
    fx = ux - omega_stick * wx  # A^-1 u: the force that makes the contact stick
    fy = uy - omega_stick * wy
    f_normal = fx * nx + fy * ny
    f_tangent = ny * fx - nx * fy  # comcore.ccw_cross(n, f)
    sticking = (f_normal > 0) & (np.abs(f_tangent) <= mu * f_normal)
    # The friction-cone edge on the force's side: n turned by +/- atan(mu) (CCW on screen).
    sin_a = np.where(f_tangent >= 0, sin_a, -sin_a)
    ex = cos_a * nx + sin_a * ny
    ey = -sin_a * nx + cos_a * ny
    w_edge = wx * ex + wy * ey
    normal_rate = ex * nx + ey * ny + w_edge * (wx * nx + wy * ny) / c2  # (A edge) . n
    sticking = sticking | (normal_rate <= 1e-9)
    scale = (ux * nx + uy * ny) / np.where(sticking, 1.0, normal_rate)
    vx = np.where(sticking, fx, scale * ex)
    vy = np.where(sticking, fy, scale * ey)
    omega = np.where(sticking, omega_stick, scale * w_edge / c2)
    return vx, vy, omega, sticking


def body_twist(r, normal, u, c2, mu):
    """Body-frame displacement ``(v, omega)`` of the object for a contact displacement ``u``.

    All arguments broadcast: ``r`` (contact minus CoM), ``normal`` (inward unit
    normal) and ``u`` (the displacement the pusher imposes on the contact, with
    ``u . normal > 0``) of shape (..., 2); ``c2`` and ``mu`` of shape (...).

    Returns
    -------
    v : numpy.ndarray, shape (..., 2)
    omega : numpy.ndarray, shape (...)
        Radians, counter-clockwise on screen.
    sticking : numpy.ndarray of bool, shape (...)
    """
    r, normal, u = (np.asarray(a, dtype=float) for a in (r, normal, u))
    mu = np.asarray(mu, dtype=float)
    alpha = np.arctan(mu)
    vx, vy, omega, sticking = _twist(
        r[..., 0], r[..., 1], normal[..., 0], normal[..., 1], u[..., 0], u[..., 1], c2, mu,
        np.cos(alpha), np.sin(alpha),
    )  # fmt: skip
    return np.stack([vx, vy], axis=-1), omega, sticking


def simulate(mask, field, actions, coms, c2, mu, radius=0.0, n_steps=24) -> np.ndarray:
    """Integrate each push for each CoM hypothesis.

    Parameters
    ----------
    mask : Mask
    field : DistanceField
        ``distance_field(mask)``.
    actions : numpy.ndarray, shape (n_actions, 4)
    coms : numpy.ndarray, shape (n_hyp, 2)
    c2 : numpy.ndarray, shape (n_hyp,) or (n_hyp, 3)
        Squared characteristic length of each hypothesis, or the support's
        second-moment tensor (``limit_surface="directional"`` of
        :func:`predictors._ellipsoid_support.characteristic_length_sq`),
        contracted at every step with the direction of the pusher's motion
        relative to the object.
    mu : numpy.ndarray, shape (n_hyp,)
        Contact friction of each hypothesis (``inf`` allowed).
    radius : float
        Pusher radius in pixels. The actions are the paths of the disc's
        leading point (as in :mod:`simulators`); its centre runs ``radius``
        behind.
    n_steps : int
        Integration steps between first contact and the end of the push.

    Returns
    -------
    numpy.ndarray, shape (n_hyp, n_actions, 3)
        ``(theta, tx, ty)``: rotation CCW on screen and displacement of the
        mask's area centroid, pixels. Pushes that miss give zeros.

    Raises
    ------
    ValueError
        If a push starts inside the object.
    """
    delta = actions[:, 2:] - actions[:, :2]
    length = np.hypot(delta[:, 0], delta[:, 1])
    actions, radius = pusher_paths(field, actions, radius)
    travel, hit, _ = first_contact(field, actions, radius)
    step = np.where(hit, (length - travel) / n_steps, 0.0)
    ux, uy = delta[:, 0] / length, delta[:, 1] / length
    sx, sy = actions[:, 0] + travel * ux, actions[:, 1] + travel * uy  # first contact
    dx, dy = step * ux, step * uy  # pusher displacement per step (world)
    comx, comy = coms[:, 0:1], coms[:, 1:2]  # (H, 1)
    c2 = np.asarray(c2, dtype=float)
    directional = c2.ndim == 2
    if directional:
        sxx, sxy, syy = (c2[:, i : i + 1] for i in range(3))
    else:
        c2 = c2[:, None]
    mu = np.asarray(mu, dtype=float)[:, None]
    cos_a, sin_a = np.cos(np.arctan(mu)), np.sin(np.arctan(mu))
    theta = np.zeros((len(coms), len(actions)))
    px, py = comx + theta, comy + theta  # CoM position (world)
    for k in range(1, n_steps + 1):
        # comcore convention: R(theta) = [[c, s], [-s, c]]; the body frame is R(-theta).
        cos_t, sin_t = np.cos(theta), np.sin(theta)
        ox, oy = sx + k * dx - px, sy + k * dy - py
        qx = cos_t * ox - sin_t * oy + comx
        qy = sin_t * ox + cos_t * oy + comy
        dist, gx, gy = field.sample_xy(qx, qy)
        gap = dist - radius  # < 0: the pusher is inside by -gap
        nx, ny = -gx, -gy
        mx, my = cos_t * dx - sin_t * dy, sin_t * dx + cos_t * dy
        along = mx * nx + my * ny + gap
        if directional:  # c^2 = d^T S d along the pusher's direction in the body frame
            c2 = (sxx * mx * mx + 2.0 * sxy * mx * my + syy * my * my) / np.maximum(
                mx * mx + my * my, 1e-300
            )
            c2 = np.maximum(c2, 1.0 / 12.0)
        vx, vy, omega, _ = _twist(
            qx - dist * gx - comx,
            qy - dist * gy - comy,
            nx,
            ny,
            mx - along * nx,
            my - along * ny,
            c2,
            mu,
            cos_a,
            sin_a,
        )
        pushing = (gap < 0) & hit
        px = px + np.where(pushing, cos_t * vx + sin_t * vy, 0.0)
        py = py + np.where(pushing, -sin_t * vx + cos_t * vy, 0.0)
        theta = theta + np.where(pushing, omega, 0.0)
    cx, cy = mask.centroid
    bx, by = cx - comx, cy - comy
    cos_t, sin_t = np.cos(theta), np.sin(theta)
    tx = cos_t * bx + sin_t * by + px - cx
    ty = -sin_t * bx + cos_t * by + py - cy
    return np.stack([theta, tx, ty], axis=-1)
