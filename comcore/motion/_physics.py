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

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..conventions import rotate_components

__all__ = ["Contact", "Footprint", "push_motions", "slide_twist", "stick_omega"]

#: Smoothing of ``|u|`` in units of the support cell's side.
SMOOTHING_CELLS = 0.5
#: Newton steps of the sticking and sliding solves (first step; later ones warm-start).
STICK_ITERATIONS, SLIDE_ITERATIONS = (8, 4), (5, 4)
#: Largest rotation per pixel of pusher travel (0.5 rad/px: a pivot 2 px from the contact).
MAX_TURN_PER_PX = 0.5
#: A sliding contact must move into the pusher at this fraction of its speed, at least.
MIN_NORMAL_FRACTION = 0.05
#: Longest Newton step of the sliding solve (normalised twist units).
MAX_SLIDE_STEP = 0.5


class Footprint(NamedTuple):
    """The support points the floor presses on, as the sticking and sliding solves read them."""

    rx: np.ndarray
    """(N,) x of the support points, pixels from the mask's area centroid."""
    ry: np.ndarray
    """(N,) y (down) of the support points, pixels from the centroid."""
    eps2: float
    """Square of the smoothing of ``|.|``, for a unit contact speed."""
    length: float
    """Root mean square of the support points' distances from the centroid, pixels: the
    sliding solve divides lengths by it, so that forces and moments weigh alike."""

    @classmethod
    def of(cls, support: np.ndarray, eps2: float) -> Footprint:
        """The footprint of ``support`` (N, 2) points relative to the centroid."""
        rx, ry = support[:, 0], support[:, 1]
        return cls(rx, ry, eps2, float(np.sqrt(np.mean(rx * rx + ry * ry))))


class Contact(NamedTuple):
    """Where the pusher touches the object at one step, one row each, in the body frame."""

    x: np.ndarray
    """(n,) x of the contact on the outline, pixels from the mask's area centroid."""
    y: np.ndarray
    """(n,) y (down) of the contact, pixels from the centroid."""
    nx: np.ndarray
    """(n,) x of the outline's unit inward normal at the contact."""
    ny: np.ndarray
    """(n,) y of the unit inward normal."""
    gap: np.ndarray
    """(n,) the pusher's signed distance from the outline, pixels (< 0: it presses in)."""

    def take(self, index) -> Contact:
        """The contacts of the rows ``index``."""
        return Contact(*(v[index] for v in self))


def _rowdot(a, b):
    """Row-wise sums of products of two (m, N) arrays."""
    return np.einsum("ij,ij->i", a, b)


def stick_omega(p, footprint: Footprint, contact: Contact, u, omega, iterations: int):
    """Sticking: ``argmin_omega sum_j p_j |u + omega J (r_j - c)|`` per row, and the force.

    ``p`` (m, N) pressures over the ``footprint``; ``contact`` the m contacts
    ``c`` (only their points are read); ``u`` the pair ``(ux, uy)`` of (m,)
    contact displacements; ``omega`` (m,) the starting rotations. Newton steps
    clipped to a bracket that holds the root (the derivative is monotone), so
    a bad step is replaced by bisection. Returns ``omega`` and the force's x and
    y components, (m,) each.
    """
    f = np.float32  # single precision, as in slide_twist
    p, rx, ry, cx, cy, ux, uy = (
        np.asarray(a, dtype=f) for a in (p, footprint.rx, footprint.ry, contact.x, contact.y, *u)
    )
    omega, eps2 = np.asarray(omega, dtype=f), f(footprint.eps2)
    bx, by = ry[None, :] - cy[:, None], cx[:, None] - rx[None, :]  # J (r_j - c)
    b2 = bx * bx + by * by
    speed = np.hypot(ux, uy)
    reach = np.maximum(np.sqrt(_rowdot(p, b2) / p.sum(axis=1)), 1e-9)
    lo, hi = -4.0 * speed / reach, 4.0 * speed / reach
    omega = np.clip(omega, lo, hi)
    ux, uy = ux[:, None], uy[:, None]
    for _ in range(iterations):
        vx, vy = ux + omega[:, None] * bx, uy + omega[:, None] * by
        inv = 1.0 / np.sqrt(vx * vx + vy * vy + eps2)
        vb = vx * bx + vy * by
        pin = p * inv
        grad = _rowdot(pin, vb)
        vb *= inv
        hess = _rowdot(pin, b2 - vb * vb)
        lo, hi = np.where(grad < 0, omega, lo), np.where(grad > 0, omega, hi)
        step = omega - grad / np.maximum(hess, f(1e-30))
        omega = np.where((step >= lo) & (step <= hi), step, 0.5 * (lo + hi))
    vx, vy = ux + omega[:, None] * bx, uy + omega[:, None] * by
    pin = p / np.sqrt(vx * vx + vy * vy + eps2)
    d = np.float64
    return omega.astype(d), _rowdot(pin, vx).astype(d), _rowdot(pin, vy).astype(d)


def _ellipsoid_twist(p, rx, ry, wrench):
    """The sliding twist under the ellipsoidal approximation of the limit surface, (m, 3).

    About the centre of pressure ``q`` the ellipsoid's twist is ``(f, m_q / c^2)``,
    ``c^2 = <|r - q|^2> / 2``: a start for :func:`slide_twist` close to its answer.
    """
    qx, qy = p @ rx, p @ ry
    c2 = np.maximum(0.5 * (p @ (rx * rx + ry * ry) - qx * qx - qy * qy), 1e-9)
    fx, fy = wrench[:, 0], wrench[:, 1]
    omega = (wrench[:, 2] - (fx * qy - fy * qx)) / c2
    return np.column_stack([fx - omega * qy, fy + omega * qx, omega])


def slide_twist(p, footprint: Footprint, wrench, xi, iterations: int, backtrack: bool = True):
    """Sliding: ``argmin D(xi)`` subject to ``wrench . xi = 1`` per row, (m, 3).

    ``p`` (m, N) pressures over the ``footprint``. Newton on the plane
    (lengths divided by ``footprint.length``, so that forces and moments weigh
    alike), steps at most ``MAX_SLIDE_STEP`` long and, with ``backtrack``,
    halved up to twice where they do not lower ``D``; warm-started from ``xi``
    (rescaled onto the plane).
    """
    length = footprint.length
    rx, ry = footprint.rx / length, footprint.ry / length
    wrench = wrench * [1.0, 1.0, 1.0 / length]
    xi = xi * [1.0, 1.0, length]
    unit = wrench / np.linalg.norm(wrench, axis=1, keepdims=True)
    axis = np.eye(3)[np.argmin(np.abs(unit), axis=1)]
    e1 = np.cross(unit, axis)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(unit, e1)
    basis = np.stack([e1, e2], axis=2)  # (m, 3, 2)
    base = wrench / np.einsum("mk,mk->m", wrench, wrench)[:, None]
    power = np.einsum("mk,mk->m", wrench, xi)
    ok = power > 1e-12
    xi = np.where(ok[:, None], xi / np.where(ok, power, 1.0)[:, None], base)
    z = np.matmul(xi[:, None, :], basis)[:, 0]
    # The (rows x support points) work in single precision: twice as fast, and
    # the answer is needed to far less than its 1e-7.
    f = np.float32
    p, rx, ry, eps2 = p.astype(f), rx.astype(f), ry.astype(f), f(footprint.eps2)
    rxx, rxy, ryy = rx * rx, rx * ry, ry * ry

    def velocities(z):
        x = (base + np.matmul(basis, z[:, :, None])[..., 0]).astype(f)
        ux = x[:, :1] + x[:, 2:] * ry[None, :]
        uy = x[:, 1:2] - x[:, 2:] * rx[None, :]
        return ux, uy, np.sqrt(ux * ux + uy * uy + eps2)

    for _ in range(iterations):
        ux, uy, s = velocities(z)
        inv = 1.0 / s
        hx, hy = ux * inv, uy * inv
        pin = p * inv
        a11, a12, a22 = pin * (f(1) - hx * hx), -pin * hx * hy, pin * (f(1) - hy * hy)
        grad = np.column_stack([_rowdot(p, hx), _rowdot(p, hy), (p * hx) @ ry - (p * hy) @ rx])
        h = np.empty((len(z), 3, 3))
        h[:, 0, 0], h[:, 0, 1], h[:, 1, 1] = a11.sum(1), a12.sum(1), a22.sum(1)
        h[:, 0, 2] = a11 @ ry - a12 @ rx
        h[:, 1, 2] = a12 @ ry - a22 @ rx
        h[:, 2, 2] = a11 @ ryy - 2 * (a12 @ rxy) + a22 @ rxx
        h[:, 1, 0], h[:, 2, 0], h[:, 2, 1] = h[:, 0, 1], h[:, 0, 2], h[:, 1, 2]
        g2 = np.matmul(grad[:, None, :], basis)[:, 0]
        h2 = np.matmul(basis.transpose(0, 2, 1), np.matmul(h, basis)) + 1e-12 * np.eye(2)
        det = h2[:, 0, 0] * h2[:, 1, 1] - h2[:, 0, 1] * h2[:, 1, 0]
        along_e1 = h2[:, 1, 1] * g2[:, 0] - h2[:, 0, 1] * g2[:, 1]
        along_e2 = h2[:, 0, 0] * g2[:, 1] - h2[:, 1, 0] * g2[:, 0]
        step = -np.column_stack([along_e1, along_e2]) / det[:, None]
        norm = np.hypot(step[:, 0], step[:, 1])
        step *= np.minimum(1.0, MAX_SLIDE_STEP / np.maximum(norm, 1e-300))[:, None]
        if backtrack:
            f0, alpha = _rowdot(p, s), np.ones(len(z))
            for _ in range(2):
                f1 = _rowdot(p, velocities(z + alpha[:, None] * step)[2])
                alpha = np.where(f1 > f0 * (1 + 1e-12), 0.5 * alpha, alpha)
            step *= alpha[:, None]
        z = z + step
    x = base + np.matmul(basis, z[:, :, None])[..., 0]
    return np.column_stack([x[:, 0], x[:, 1], x[:, 2] / length])


class _Friction(NamedTuple):
    """The contact's friction cone per row (pressure x action), and who a sticking row follows."""

    tan: np.ndarray
    """(rows,) the contact friction ``mu`` (``inf``: the contact sticks)."""
    cos: np.ndarray
    """(rows,) cosine of the cone's half-angle ``atan(mu)``."""
    sin: np.ndarray
    """(rows,) its sine."""
    rep: np.ndarray
    """(rows,) the row a row moves with while it sticks (:func:`push_motions`' ``same_as``)."""


def _friction_rows(mu, same_as, n_p: int, n_a: int) -> tuple[_Friction, np.ndarray]:
    """The friction of every row (pressure x action), and whether it moves with another row."""
    rows = np.arange(n_p * n_a)
    tan_mu = np.broadcast_to(np.asarray(mu, dtype=float), (n_p,))[rows // n_a]
    cos_a, sin_a = np.cos(np.arctan(tan_mu)), np.sin(np.arctan(tan_mu))
    same = np.arange(n_p) if same_as is None else np.asarray(same_as, dtype=np.intp)
    rep = same[rows // n_a] * n_a + rows % n_a
    return _Friction(tan_mu, cos_a, sin_a, rep), rep != rows


class _Pushes(NamedTuple):
    """What stays fixed while the pushes are integrated: the pushes and the floor."""

    field: object
    """The outline's smoothed signed distance (:func:`comcore.geometry.outline_field`)."""
    pressure: np.ndarray
    """(n_p, N) pressures over the footprint, one row per pressure distribution."""
    footprint: Footprint
    """The support points the pressures are given at."""
    first: np.ndarray
    """(n_a, 2) the pusher disc's centre at first contact, pixels."""
    unit: np.ndarray
    """(n_a, 2) unit push directions."""
    step: np.ndarray
    """(n_a,) the pusher's travel per step, pixels."""
    radii: np.ndarray
    """(n_a,) the pusher disc's radius per action, pixels."""
    act: np.ndarray
    """(rows,) each row's action (a row is a pressure x an action)."""


@dataclass
class _State:
    """Each row's state while the pushes are integrated, updated step by step."""

    centre: tuple[float, float]
    """The mask's area centroid, pixels."""
    x: np.ndarray
    """(rows,) x of the material point that started under the centroid, pixels."""
    y: np.ndarray
    """(rows,) its y."""
    theta: np.ndarray
    """(rows,) the rotation so far, radians (CCW on screen)."""
    omega_rate: np.ndarray
    """(rows,) the last sticking rotation per pixel of contact travel (NaN: none yet)."""
    xi_slide: np.ndarray
    """(rows, 3) the last sliding twist (zeros: the row has not slid)."""
    friction: _Friction
    """The friction cone per row."""
    attached: np.ndarray
    """(rows,) whether the row moves with its ``friction.rep`` (it has only stuck so far)."""
    where: np.ndarray
    """(rows,) scratch: a row's place among the rows in contact at this step."""

    @classmethod
    def start(cls, centroid, friction: _Friction, attached: np.ndarray) -> _State:
        """Every row at rest, before the push."""
        n, (cx0, cy0) = len(attached), (float(centroid[0]), float(centroid[1]))
        x, y, theta = np.full(n, cx0), np.full(n, cy0), np.zeros(n)
        rate, xi = np.full(n, np.nan), np.zeros((n, 3))
        return cls((cx0, cy0), x, y, theta, rate, xi, friction, attached, np.full(n, -1))

    def motion(self) -> np.ndarray:
        """The motion so far, ``(rows, 3)``: ``(theta, tx, ty)``."""
        return np.stack([self.theta, self.x - self.centre[0], self.y - self.centre[1]], axis=-1)

    def move(self, live: np.ndarray, twist, cap: np.ndarray) -> None:
        """Move the rows ``live`` by the body twist ``(vx, vy, om)``, ``om`` clipped to ``cap``."""
        vx, vy, om = twist
        om = np.clip(np.nan_to_num(om), -cap, cap)
        vx, vy = np.nan_to_num(vx), np.nan_to_num(vy)
        half = self.theta[live] + 0.5 * om
        dx, dy = rotate_components(vx, vy, np.cos(half), np.sin(half))
        self.x[live] += dx
        self.y[live] += dy
        self.theta[live] += om


def push_motions(
    field,
    actions,
    pressure,
    support,
    centroid,
    *,
    mu,
    radius: float,
    n_steps: int,
    eps2: float,
    same_as=None,
    path: bool = False,
):
    """Integrate every push for every pressure distribution: ``(n_p, n_actions, 3)`` motions.

    ``pressure`` (n_p, N) over ``support`` (N, 2) points relative to ``centroid``
    (pixels); ``mu`` the contact friction, a number or one per pressure row
    (``inf``: the contact sticks); ``radius`` the pusher's in pixels; ``eps2``
    the square of the smoothing of ``|.|`` for a unit contact speed.
    ``same_as`` (n_p,) optionally names, for each row, a row with the same
    pressure and a friction at least as high: while a row sticks, it moves as
    that one does, so its sticking solve is not repeated. Motions ``(theta, tx,
    ty)``: rotation (CCW on screen) and displacement of the material point
    under the centroid; zeros for a miss. ``path=True``: after every step (:func:`_path`).
    """
    n_p, n_a = len(pressure), len(actions)
    first, unit, travel, hit, radii = field.pusher_paths(actions, radius)
    rows = np.arange(n_p * n_a)
    act = rows % n_a
    pushes = _Pushes(
        field, pressure, Footprint.of(support, eps2), first, unit, travel / n_steps, radii, act
    )
    state = _State.start(centroid, *_friction_rows(mu, same_as, n_p, n_a))
    before = []  # with path: the state before each step
    for k in range(1, n_steps + 1):
        if path:
            before.append(state.motion())
        live = rows[hit[act]]
        if not len(live):
            break
        _step(pushes, state, live, k)
    out = state.motion()
    if path:
        return _path(before, out, n_steps).reshape(n_p, n_a, n_steps + 1, 3)
    return out.reshape(n_p, n_a, 3)


def _step(pushes: _Pushes, state: _State, live: np.ndarray, k: int) -> None:
    """Step ``k`` of the rows ``live`` (those whose push hits): move the ones the pusher touches."""
    found = _touching(pushes, state, live, k)
    if found is None:
        return
    live, contact, (ux, uy) = found
    speed = np.maximum(np.hypot(ux, uy), 1e-12)
    # Solved for a unit contact speed: the smoothing of |.| is relative to it.
    om, fx, fy = _sticking(pushes, state, live, contact, (ux / speed, uy / speed), k)
    state.omega_rate[live] = om
    om = om * speed
    vx, vy = ux - om * contact.y, uy + om * contact.x  # v = u - omega J c
    f_n = fx * contact.nx + fy * contact.ny
    f_t = contact.ny * fx - contact.nx * fy
    slide = ~((f_n > 0) & (np.abs(f_t) <= state.friction.tan[live] * f_n))
    if slide.any():
        j = np.flatnonzero(slide)
        state.attached[live[j]] = False  # from here on it moves on its own
        good, twist = _sliding_twists(pushes, state, live[j], contact.take(j), f_t[j], k)
        j = j[good]
        vx[j], vy[j], om[j] = twist.T
    # A quasi-static step turns the object by about its length over the distance from
    # the contact to the centre of rotation: cap it where a degenerate pressure (all
    # on a few points) or an unconverged solve would make it blow up.
    state.move(live, (vx, vy, om), MAX_TURN_PER_PX * pushes.step[pushes.act[live]])


def _touching(pushes: _Pushes, state: _State, live: np.ndarray, k: int):
    """The rows of ``live`` the pusher presses into at step ``k``: rows, contacts, displacements.

    Returns None when it touches none, else ``(rows, contact, (ux, uy))``: the
    contact's displacement (body frame) were it to stick to the pusher.
    """
    a = pushes.act[live]
    first, unit, step = pushes.first, pushes.unit, pushes.step
    wx = first[a, 0] + k * step[a] * unit[a, 0] - state.x[live]
    wy = first[a, 1] + k * step[a] * unit[a, 1] - state.y[live]
    c, s = np.cos(state.theta[live]), np.sin(state.theta[live])
    cx0, cy0 = state.centre
    qx, qy = rotate_components(wx, wy, c, s, inverse=True, origin=(cx0, cy0))
    dist, gx, gy = pushes.field.sample(qx, qy)
    gap = dist - pushes.radii[a]
    touch = gap < 0
    live, a, c, s = live[touch], a[touch], c[touch], s[touch]
    if not len(live):
        return None
    nx, ny, gap = -gx[touch], -gy[touch], gap[touch]
    ccx = qx[touch] + dist[touch] * nx - cx0  # contact on the outline, from the centroid
    ccy = qy[touch] + dist[touch] * ny - cy0
    mx, my = rotate_components(unit[a, 0], unit[a, 1], c, s, inverse=True)
    mx, my = mx * step[a], my * step[a]  # the pusher's step, body frame
    mn = mx * nx + my * ny
    ux, uy = mx - (mn + gap) * nx, my - (mn + gap) * ny  # sticking contact displacement
    return live, Contact(ccx, ccy, nx, ny, gap), (ux, uy)


def _sticking(pushes: _Pushes, state: _State, live, contact: Contact, u, k: int):
    """The sticking ``omega`` (per unit contact travel ``u``) and force of the rows ``live``.

    Rows still attached to another (``state.attached``) take that row's solution.
    """
    rate = state.omega_rate[live]
    guess = np.where(np.isnan(rate), 0.0, rate)
    iters = STICK_ITERATIONS[0 if k == 1 else 1]
    own = np.flatnonzero(~state.attached[live])
    om, fx, fy = np.empty(len(live)), np.empty(len(live)), np.empty(len(live))
    p = pushes.pressure[live[own] // len(pushes.first)]
    om[own], fx[own], fy[own] = stick_omega(
        p, pushes.footprint, contact.take(own), (u[0][own], u[1][own]), guess[own], iters
    )
    clone = np.flatnonzero(state.attached[live])
    if len(clone):  # the same state as the row they follow: the same solution
        state.where[live] = np.arange(len(live))
        src = state.where[state.friction.rep[live[clone]]]
        om[clone], fx[clone], fy[clone] = om[src], fx[src], fy[src]
    return om, fx, fy


def _path(before: list, out: np.ndarray, n_steps: int) -> np.ndarray:
    """The motion after every step, ``(rows, n_steps + 1, 3)``, the first row zeros.

    Step ``k`` ends at the fraction ``k / n_steps`` of the push's travel after first
    contact; ``before`` holds the states before the steps taken (the loop stops early
    when no push touches any more: the rest are the final state ``out``).
    """
    rest = [out] * (n_steps + 1 - len(before))
    return np.stack([*before, *rest], axis=1)


def _sliding_twists(pushes: _Pushes, state: _State, rows, contact: Contact, f_t, k: int):
    """The step of the ``rows`` whose contacts slide: ``(kept, (n, 3) twists)``.

    The force lies on the friction cone's edge against the tangential force
    ``f_t``; the twist solves the limit surface from the row's last sliding
    twist (``state.xi_slide``, updated) or, on a first slide, from the
    ellipsoid's. Solves whose contact does not move into the pusher's way are
    dropped (``kept`` says which are not): those rows keep their sticking twist.
    """
    footprint = pushes.footprint
    p = pushes.pressure[rows // len(pushes.first)]
    cos_a, sin_a = state.friction.cos[rows], state.friction.sin[rows]
    sa = np.where(f_t >= 0, sin_a, -sin_a)
    ex = cos_a * contact.nx + sa * contact.ny
    ey = -sa * contact.nx + cos_a * contact.ny
    wrench = np.column_stack([ex, ey, ex * contact.y - ey * contact.x])
    iters = SLIDE_ITERATIONS[0 if k == 1 else 1]
    start = state.xi_slide[rows]
    fresh = ~start.any(axis=1)  # no earlier sliding: start from the sticking twist
    if fresh.any():
        start[fresh] = _ellipsoid_twist(p[fresh], footprint.rx, footprint.ry, wrench[fresh])
    xi = slide_twist(p, footprint, wrench, start, iters, k == 1)
    state.xi_slide[rows] = xi
    cvx, cvy = xi[:, 0] + xi[:, 2] * contact.y, xi[:, 1] - xi[:, 2] * contact.x
    normal = cvx * contact.nx + cvy * contact.ny
    # The contact must move into the pusher's way: a solve that is not there
    # (unconverged, or a pusher grazing a corner) keeps the sticking twist.
    good = np.isfinite(xi).all(axis=1) & (normal > MIN_NORMAL_FRACTION * np.hypot(cvx, cvy))
    scale = -contact.gap / np.where(good, normal, 1.0)
    return good, xi[good] * scale[good][:, None]
