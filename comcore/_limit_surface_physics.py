"""Quasi-static pushing with the exact limit surface of a pixel footprint, vectorised.

Physics (Goyal et al. 1991; Mason 1986; Lynch and Mason 1996), pixel frame,
origin at the mask's area centroid. The floor presses on support point ``j``
(``r_j``, pressure ``p_j``) and resists its sliding with Coulomb friction, so
a body twist ``xi = (v, omega)`` dissipates ``D(xi) = sum_j p_j |v + omega J r_j|``
(``J r = (r_y, -r_x)``: the velocity of ``r`` per unit counter-clockwise-on-screen
``omega``); the gradient of ``D`` is the wrench the pusher applies. At the
contact ``c`` (inward normal ``n``, contact friction ``mu``) the pusher

* sticks: the contact moves with the pusher (``u``), ``omega`` minimises
  ``sum_j p_j |u + omega J (r_j - c)|`` (one unknown, convex), valid when the
  force that takes lies in the friction cone; or
* slides: the force lies on the cone's edge on that force's side and the
  twist minimises ``D`` on the plane ``wrench . xi = 1`` (two unknowns).

Both are solved by safeguarded Newton steps on ``|.|`` smoothed over half a
support cell, a fixed number of them, vectorised over rows (hypotheses x
pushes). The push is integrated in steps: the pusher's position at the end of
each step, taken into the body frame, gives the contact point, normal and
penetration from the outline's smoothed signed distance; the twist removes
the penetration, so the contact slides along the outline as the object turns.
"""

from __future__ import annotations

import weakref

import numpy as np
from scipy import ndimage

from ._mask import Mask

__all__ = ["OutlineField", "outline_field", "push_motions", "slide_twist", "stick_omega"]

#: Gaussian sigma (pixels) smoothing the pixel outline's signed distance.
SDF_SMOOTHING_PX = 1.0
#: Padding (pixels) of the distance field around the mask image.
FIELD_PAD_PX = 24
#: March step (pixels) and bisections of the search for the first contact.
CONTACT_MARCH_PX, CONTACT_BISECTIONS = 0.25, 8
#: Smoothing of ``|u|`` in units of the support cell's side.
SMOOTHING_CELLS = 0.5
#: Newton steps of the sticking and sliding solves (first step; later ones warm-start).
STICK_ITERATIONS, SLIDE_ITERATIONS = (8, 4), (10, 4)
#: Largest rotation per pixel of pusher travel (0.5 rad/px: a pivot 2 px from the contact).
MAX_TURN_PER_PX = 0.5
#: Longest Newton step of the sliding solve (normalised twist units).
MAX_SLIDE_STEP = 0.5


class OutlineField:
    """Smoothed signed distance (px, > 0 outside) to a mask's pixel outline, and its gradient."""

    def __init__(self, mask: Mask, pad: int = FIELD_PAD_PX):
        img = np.pad(mask.data, pad)
        outside = ndimage.distance_transform_edt(~img)
        inside = ndimage.distance_transform_edt(img)
        sdf = ndimage.gaussian_filter(
            np.where(img, 0.5 - inside, outside - 0.5), SDF_SMOOTHING_PX, mode="nearest"
        )
        gy, gx = np.gradient(sdf)
        self.pad = pad
        self._fields = (sdf, gx, gy)

    def sample(self, x, y):
        """Distance and unit outward gradient ``(gx, gy)`` at points ``(x, y)`` (bilinear)."""
        shape = np.shape(x)
        coords = np.vstack([np.ravel(y) + self.pad, np.ravel(x) + self.pad])
        d, gx, gy = (
            ndimage.map_coordinates(f, coords, order=1, mode="nearest") for f in self._fields
        )
        norm = np.maximum(np.hypot(gx, gy), 1e-12)
        return d.reshape(shape), (gx / norm).reshape(shape), (gy / norm).reshape(shape)


_FIELDS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def outline_field(mask: Mask) -> OutlineField:
    """The (cached) :class:`OutlineField` of an immutable mask."""
    field = _FIELDS.get(mask)
    if field is None:
        field = _FIELDS[mask] = OutlineField(mask)
    return field


def _plane_dissipation(p, rx, ry, vx, vy, om, eps2):
    ux = vx[:, None] + om[:, None] * ry
    uy = vy[:, None] + om[:, None] * -rx
    return ux, uy, np.sqrt(ux * ux + uy * uy + eps2)


def stick_omega(p, rx, ry, cx, cy, ux, uy, omega, eps2, iterations):
    """Sticking: ``argmin_omega sum_j p_j |u + omega J (r_j - c)|`` per row, and the force.

    ``p`` (m, N) pressures; ``rx, ry`` (N,) support points; ``cx, cy, ux, uy,
    omega`` (m,) contact, contact displacement and the starting ``omega``.
    Newton steps clipped to a bracket that holds the root (the derivative is
    monotone), so a bad step is replaced by bisection.
    """
    bx, by = ry[None, :] - cy[:, None], cx[:, None] - rx[None, :]  # J (r_j - c)
    speed = np.hypot(ux, uy)
    reach = np.sqrt((p * (bx * bx + by * by)).sum(axis=1) / p.sum(axis=1))
    lo, hi = -4.0 * speed / np.maximum(reach, 1e-9), 4.0 * speed / np.maximum(reach, 1e-9)
    omega = np.clip(omega, lo, hi)
    for _ in range(iterations):
        vx, vy = ux[:, None] + omega[:, None] * bx, uy[:, None] + omega[:, None] * by
        s = np.sqrt(vx * vx + vy * vy + eps2)
        vb = vx * bx + vy * by
        grad = (p * vb / s).sum(axis=1)
        hess = (p * ((bx * bx + by * by) * s * s - vb * vb) / s**3).sum(axis=1)
        lo, hi = np.where(grad < 0, omega, lo), np.where(grad > 0, omega, hi)
        step = omega - grad / np.maximum(hess, 1e-300)
        omega = np.where((step >= lo) & (step <= hi), step, 0.5 * (lo + hi))
    vx, vy = ux[:, None] + omega[:, None] * bx, uy[:, None] + omega[:, None] * by
    s = np.sqrt(vx * vx + vy * vy + eps2)
    return omega, (p * vx / s).sum(axis=1), (p * vy / s).sum(axis=1)


def slide_twist(p, rx, ry, wrench, xi, eps2, iterations, length):
    """Sliding: ``argmin D(xi)`` subject to ``wrench . xi = 1`` per row, (m, 3).

    Newton on the plane (lengths divided by ``length``, so that forces and
    moments weigh alike), steps at most ``MAX_SLIDE_STEP`` long and halved up
    to three times where they do not lower ``D``; warm-started from ``xi``
    (rescaled onto the plane).
    """
    rx, ry = rx / length, ry / length
    wrench = wrench * [1.0, 1.0, 1.0 / length]
    xi = xi * [1.0, 1.0, length]
    unit = wrench / np.linalg.norm(wrench, axis=1, keepdims=True)
    axis = np.eye(3)[np.argmin(np.abs(unit), axis=1)]
    e1 = np.cross(unit, axis)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(unit, e1)
    base = wrench / np.einsum("mk,mk->m", wrench, wrench)[:, None]
    power = np.einsum("mk,mk->m", wrench, xi)
    ok = power > 1e-12
    xi = np.where(ok[:, None], xi / np.where(ok, power, 1.0)[:, None], base)
    z = np.column_stack([np.einsum("mk,mk->m", xi, e1), np.einsum("mk,mk->m", xi, e2)])
    ex, ey = rx[None, :], ry[None, :]

    def point(z):
        x = base + z[:, :1] * e1 + z[:, 1:] * e2
        return x[:, 0], x[:, 1], x[:, 2]

    for _ in range(iterations):
        vx, vy, om = point(z)
        ux, uy, s = _plane_dissipation(p, ex, ey, vx, vy, om, eps2)
        hx, hy = ux / s, uy / s
        # d(u)/d(xi): (1, 0, ry) and (0, 1, -rx)
        a11, a12, a22 = p * (1 - hx * hx) / s, -p * hx * hy / s, p * (1 - hy * hy) / s
        grad = np.column_stack([(p * hx).sum(1), (p * hy).sum(1), (p * (hx * ey - hy * ex)).sum(1)])
        h = np.empty((len(z), 3, 3))
        h[:, 0, 0], h[:, 0, 1], h[:, 1, 1] = a11.sum(1), a12.sum(1), a22.sum(1)
        h[:, 0, 2] = (a11 * ey - a12 * ex).sum(1)
        h[:, 1, 2] = (a12 * ey - a22 * ex).sum(1)
        h[:, 2, 2] = (a11 * ey * ey - 2 * a12 * ex * ey + a22 * ex * ex).sum(1)
        h[:, 1, 0], h[:, 2, 0], h[:, 2, 1] = h[:, 0, 1], h[:, 0, 2], h[:, 1, 2]
        basis = np.stack([e1, e2], axis=2)  # (m, 3, 2)
        g2 = np.einsum("mkj,mk->mj", basis, grad)
        h2 = np.einsum("mki,mkl,mlj->mij", basis, h, basis) + 1e-12 * np.eye(2)
        step = -np.linalg.solve(h2, g2[..., None])[..., 0]
        norm = np.hypot(step[:, 0], step[:, 1])
        step *= np.minimum(1.0, MAX_SLIDE_STEP / np.maximum(norm, 1e-300))[:, None]
        f0 = (p * s).sum(1)
        alpha = np.ones(len(z))
        for _ in range(3):
            f1 = (
                p * _plane_dissipation(p, ex, ey, *point(z + alpha[:, None] * step), eps2)[2]
            ).sum(1)
            alpha = np.where(f1 > f0 * (1 + 1e-12), 0.5 * alpha, alpha)
        z = z + alpha[:, None] * step
    vx, vy, om = point(z)
    return np.column_stack([vx, vy, om / length])


def _first_contact(field, start, unit, length, radius):
    """Travel to first contact of a disc of ``radius`` along each path, and a hit flag."""
    n = int(np.ceil(length.max(initial=0.0) / CONTACT_MARCH_PX)) + 1
    t = np.minimum(np.arange(n)[None, :] * CONTACT_MARCH_PX, length[:, None])
    px, py = start[:, :1] + t * unit[:, :1], start[:, 1:] + t * unit[:, 1:]
    touching = field.sample(px, py)[0] <= radius[:, None]
    hit = touching.any(axis=1) & ~touching[:, 0]
    first = np.argmax(touching, axis=1)
    rows = np.arange(len(start))
    lo = np.where(hit, t[rows, np.maximum(first - 1, 0)], 0.0)
    hi = np.where(hit, t[rows, first], 0.0)
    for _ in range(CONTACT_BISECTIONS):
        mid = 0.5 * (lo + hi)
        inside = field.sample(start[:, 0] + mid * unit[:, 0], start[:, 1] + mid * unit[:, 1])[0]
        inside = inside <= radius
        hi, lo = np.where(inside, mid, hi), np.where(inside, lo, mid)
    return np.where(hit, hi, 0.0), hit


def pusher_paths(field, actions, radius):
    """Centre start, unit direction, travel after first contact, contact flag and radius per action.

    An action is the path of the disc's leading point; its centre runs
    ``radius`` behind. Where that disc would overlap the outline at the start
    (a notch), the largest disc that surely fits (0.45 of the leading point's
    distance to the outline) is used instead. Raises ValueError for an action
    whose leading point starts inside the object.
    """
    delta = actions[:, 2:] - actions[:, :2]
    length = np.hypot(delta[:, 0], delta[:, 1])
    unit = delta / length[:, None]
    lead = field.sample(actions[:, 0], actions[:, 1])[0]
    if (lead <= 0).any():
        bad = np.flatnonzero(lead <= 0)[:5].tolist()
        raise ValueError(f"actions must start outside the object; action(s) {bad} start inside it")
    radii = np.full(len(actions), float(radius))
    if radius > 0:
        back = actions[:, :2] - radius * unit
        overlap = field.sample(back[:, 0], back[:, 1])[0] <= radius
        radii[overlap] = np.minimum(radius, 0.45 * lead[overlap])
    start = actions[:, :2] - radii[:, None] * unit
    travel, hit = _first_contact(field, start, unit, length, radii)
    return start + travel[:, None] * unit, unit, np.where(hit, length - travel, 0.0), hit, radii


def push_motions(field, actions, pressure, support, centroid, mu, radius, n_steps, eps2):
    """Integrate every push for every pressure distribution: ``(n_p, n_actions, 3)`` motions.

    ``pressure`` (n_p, N) over ``support`` (N, 2) points relative to ``centroid``
    (pixels); ``mu`` the contact friction (``inf``: sticks); ``radius`` the
    pusher's in pixels. Motions ``(theta, tx, ty)``: rotation (CCW on screen)
    and displacement of the material point under the centroid; zeros for a miss.
    """
    n_p, n_a = len(pressure), len(actions)
    first, unit, travel, hit, radii = pusher_paths(field, actions, radius)
    step = travel / n_steps
    rows = np.arange(n_p * n_a)
    act = rows % n_a
    p_all = pressure[rows // n_a]
    rx, ry = support[:, 0], support[:, 1]
    length = float(np.sqrt(np.mean(rx * rx + ry * ry)))
    cx0, cy0 = float(centroid[0]), float(centroid[1])
    X, Y, theta = np.full(len(rows), cx0), np.full(len(rows), cy0), np.zeros(len(rows))
    omega_rate = np.full(len(rows), np.nan)  # sticking omega per pixel of contact travel
    xi_slide = np.zeros((len(rows), 3))
    tan_mu = np.inf if np.isinf(mu) else float(mu)
    cos_a, sin_a = np.cos(np.arctan(mu)), np.sin(np.arctan(mu))
    for k in range(1, n_steps + 1):
        live = rows[hit[act]]
        if not len(live):
            break
        a = act[live]
        wx = first[a, 0] + k * step[a] * unit[a, 0] - X[live]
        wy = first[a, 1] + k * step[a] * unit[a, 1] - Y[live]
        c, s = np.cos(theta[live]), np.sin(theta[live])
        qx, qy = cx0 + c * wx - s * wy, cy0 + s * wx + c * wy
        dist, gx, gy = field.sample(qx, qy)
        gap = dist - radii[a]
        touch = gap < 0
        live, a, c, s = live[touch], a[touch], c[touch], s[touch]
        if not len(live):
            continue
        nx, ny, gap = -gx[touch], -gy[touch], gap[touch]
        ccx = qx[touch] + dist[touch] * nx - cx0  # contact on the outline, from the centroid
        ccy = qy[touch] + dist[touch] * ny - cy0
        mx = (c * unit[a, 0] - s * unit[a, 1]) * step[a]  # the pusher's step, body frame
        my = (s * unit[a, 0] + c * unit[a, 1]) * step[a]
        mn = mx * nx + my * ny
        ux, uy = mx - (mn + gap) * nx, my - (mn + gap) * ny  # sticking contact displacement
        speed = np.maximum(np.hypot(ux, uy), 1e-12)
        guess = np.where(np.isnan(omega_rate[live]), 0.0, omega_rate[live])
        p = p_all[live]
        iters = STICK_ITERATIONS[0 if k == 1 else 1]
        # Solved for a unit contact speed: the smoothing of |.| is relative to it.
        om, fx, fy = stick_omega(p, rx, ry, ccx, ccy, ux / speed, uy / speed, guess, eps2, iters)
        omega_rate[live] = om
        om = om * speed
        vx, vy = ux - om * ccy, uy + om * ccx  # v = u - omega J c
        f_n = fx * nx + fy * ny
        f_t = ny * fx - nx * fy
        slide = ~((f_n > 0) & (np.abs(f_t) <= tan_mu * f_n))
        if slide.any():
            j = np.flatnonzero(slide)
            sa = np.where(f_t[j] >= 0, sin_a, -sin_a)
            ex = cos_a * nx[j] + sa * ny[j]
            ey = -sa * nx[j] + cos_a * ny[j]
            wrench = np.column_stack([ex, ey, ex * ccy[j] - ey * ccx[j]])
            iters = SLIDE_ITERATIONS[0 if k == 1 else 1]
            start = xi_slide[live[j]]
            fresh = ~start.any(axis=1)  # no earlier sliding: start from the sticking twist
            start[fresh] = np.column_stack([vx[j], vy[j], om[j]])[fresh]
            xi = slide_twist(p[j], rx, ry, wrench, start, eps2, iters, length)
            xi_slide[live[j]] = xi
            normal = (xi[:, 0] + xi[:, 2] * ccy[j]) * nx[j] + (xi[:, 1] - xi[:, 2] * ccx[j]) * ny[j]
            scale = -gap[j] / np.maximum(normal, 1e-3 * np.linalg.norm(xi, axis=1))
            vx[j], vy[j], om[j] = (xi * scale[:, None]).T
        # A quasi-static step turns the object by about its length over the distance from
        # the contact to the centre of rotation: cap it where a degenerate pressure (all
        # on a few points) or an unconverged solve would make it blow up.
        cap = MAX_TURN_PER_PX * step[a]
        om = np.clip(np.nan_to_num(om), -cap, cap)
        vx, vy = np.nan_to_num(vx), np.nan_to_num(vy)
        half = theta[live] + 0.5 * om
        ch, sh = np.cos(half), np.sin(half)
        X[live] += ch * vx + sh * vy
        Y[live] += -sh * vx + ch * vy
        theta[live] += om
    out = np.stack([theta, X - cx0, Y - cy0], axis=-1)
    return out.reshape(n_p, n_a, 3)
