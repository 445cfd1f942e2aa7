"""The quasi-static pusher-slider with an ellipsoidal limit surface, vectorised.

Physics (Lynch, Maekawa and Tanie 1992; Howe and Cutkosky 1996), in the
object's body frame with the CoM as origin and everything in pixels:

* The limit surface is the ellipsoid ``fx^2 + fy^2 + (m / c)^2 = (mu_f N)^2``,
  with ``c`` the support's characteristic length (see
  :func:`predictors.ellipsoid._support.characteristic_length_sq`). By maximum
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

from typing import NamedTuple

import numpy as np

from comcore.conventions import rotate_components

__all__ = ["body_twist", "simulate"]


class _Cone(NamedTuple):
    """The contact's friction cone, per hypothesis (arrays that broadcast)."""

    mu: np.ndarray
    """The contact friction (``inf``: the contact always sticks)."""
    cos: np.ndarray
    """Cosine of the cone's half-angle ``atan(mu)``."""
    sin: np.ndarray
    """Its sine."""

    @classmethod
    def of(cls, mu) -> _Cone:
        """The cone of friction ``mu`` (array_like)."""
        mu = np.asarray(mu, dtype=float)
        return cls(mu, np.cos(np.arctan(mu)), np.sin(np.arctan(mu)))


def _twist(r, normal, u, c2, cone: _Cone):
    """Component form of :func:`body_twist` (the hot loop of :func:`simulate`).

    ``r``, ``normal`` and ``u`` are ``(x, y)`` pairs of component arrays (the
    contact minus the CoM, the inward normal, the contact's displacement),
    ``c2`` the squared characteristic length, ``cone`` the friction cone.
    """
    (rx, ry), (nx, ny), (ux, uy) = r, normal, u
    mu, cos_a, sin_a = cone
    # w = (r_y, -r_x): the contact's velocity per unit CCW-on-screen rotation about the CoM.
    wx, wy = ry, -rx
    wu = wx * ux + wy * uy
    omega_stick = wu / (c2 + rx * rx + ry * ry)
    fx = ux - omega_stick * wx  # A^-1 u: the force that makes the contact stick
    fy = uy - omega_stick * wy
    f_normal = fx * nx + fy * ny
    f_tangent = ny * fx - nx * fy  # comcore.conventions.ccw_cross(n, f)
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
    cone = _Cone.of(mu)
    vx, vy, omega, sticking = _twist(
        (r[..., 0], r[..., 1]), (normal[..., 0], normal[..., 1]), (u[..., 0], u[..., 1]), c2, cone
    )
    return np.stack([vx, vy], axis=-1), omega, sticking


def simulate(mask, field, actions, coms, c2, mu, *, radius=0.0, n_steps=24) -> np.ndarray:
    """Integrate each push for each CoM hypothesis.

    Parameters
    ----------
    mask : Mask
    field : comcore.geometry.OutlineField
        ``comcore.geometry.outline_field(mask)``: the smoothed signed distance to the outline
        (shared with :class:`comcore.LimitSurfaceModel`).
    actions : numpy.ndarray, shape (n_actions, 4)
    coms : numpy.ndarray, shape (n_hyp, 2)
    c2 : numpy.ndarray, shape (n_hyp,) or (n_hyp, 3)
        Squared characteristic length of each hypothesis, or the support's
        second-moment tensor (``limit_surface="directional"`` of
        :func:`predictors.ellipsoid._support.characteristic_length_sq`),
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
    first, unit, after, hit, radius = field.pusher_paths(actions, radius)
    step = after / n_steps  # 0 for a push that misses
    ux, uy = unit[:, 0], unit[:, 1]
    sx, sy = first[:, 0], first[:, 1]  # the disc's centre at first contact
    dx, dy = step * ux, step * uy  # pusher displacement per step (world)
    comx, comy = coms[:, 0:1], coms[:, 1:2]  # (H, 1)
    c2 = np.asarray(c2, dtype=float)
    directional = c2.ndim == 2
    if directional:
        sxx, sxy, syy = (c2[:, i : i + 1] for i in range(3))
    else:
        c2 = c2[:, None]
    cone = _Cone.of(np.asarray(mu, dtype=float)[:, None])
    theta = np.zeros((len(coms), len(first)))
    px, py = comx + theta, comy + theta  # CoM position (world)
    for k in range(1, n_steps + 1):
        # comcore convention: R(theta) = [[c, s], [-s, c]]; the body frame is R(-theta).
        cos_t, sin_t = np.cos(theta), np.sin(theta)
        ox, oy = sx + k * dx - px, sy + k * dy - py
        qx, qy = rotate_components(ox, oy, cos_t, sin_t, inverse=True)
        qx, qy = qx + comx, qy + comy
        dist, gx, gy = field.sample(qx, qy)
        gap = dist - radius  # < 0: the pusher is inside by -gap
        nx, ny = -gx, -gy
        mx, my = rotate_components(dx, dy, cos_t, sin_t, inverse=True)
        along = mx * nx + my * ny + gap
        if directional:  # c^2 = d^T S d along the pusher's direction in the body frame
            c2 = (sxx * mx * mx + 2.0 * sxy * mx * my + syy * my * my) / np.maximum(
                mx * mx + my * my, 1e-300
            )
            c2 = np.maximum(c2, 1.0 / 12.0)
        contact = (qx - dist * gx - comx, qy - dist * gy - comy)  # from the CoM, body frame
        vx, vy, omega, _ = _twist(contact, (nx, ny), (mx - along * nx, my - along * ny), c2, cone)
        pushing = (gap < 0) & hit
        wx, wy = rotate_components(vx, vy, cos_t, sin_t)
        px = px + np.where(pushing, wx, 0.0)
        py = py + np.where(pushing, wy, 0.0)
        theta = theta + np.where(pushing, omega, 0.0)
    cx, cy = mask.centroid
    bx, by = cx - comx, cy - comy
    rx, ry = rotate_components(bx, by, np.cos(theta), np.sin(theta))
    tx = rx + px - cx
    ty = ry + py - cy
    return np.stack([theta, tx, ty], axis=-1)
