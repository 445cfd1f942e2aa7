"""The quasi-static engine: exact limit-surface pushing, batched over pushes in numpy.

Physics (Mason 1986; Goyal et al. 1991; Lynch & Mason 1996). The floor
resists the sliding of support point ``j`` (body frame ``r_j``, mass ``m_j``)
with Coulomb friction ``mu_floor m_j g`` against its velocity. For a body twist
``xi = (v, omega)`` the frictional power is ``D(xi) = sum_j m_j |v + omega J r_j|``
(times ``mu_floor g``, which cancels), a convex function whose gradient is the
wrench the pusher must apply: the limit surface. At the contact (point ``c``,
inward normal ``n``, friction ``mu``) the pusher either

* sticks: the contact point moves with the pusher (direction ``p``) and the
  wrench's line of action passes through ``c``; ``omega`` minimises
  ``sum_j m_j |p + omega J (r_j - c)|`` (convex, one unknown); valid when the
  force it needs lies inside the friction cone; or
* slides: the force lies on the cone's edge ``e`` on the side where the
  sticking force left it; the twist is the limit surface's normal there,
  ``argmin D(xi)`` subject to ``(e, c x e) . xi = 1`` (convex, two unknowns).

Each step advances every pusher by the same fraction of its path; the twist
is scaled so that the body moves out of the pusher's disc exactly (a
position-level step: no drift, no tunnelling). Convex problems are solved by
damped Newton on a smoothed ``|u|``, warm-started from the previous step and
vectorised over all pushes. A pusher in a concave notch can touch two edges:
each step resolves the deepest contact, then the next one (``projections``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["BatchOutcome", "QuasiStaticEngine", "closest_points", "first_contacts"]

#: Smoothing of |u| in units of the grid spacing (normalised): blurs each support
#: point over about that distance from the centre of rotation, so the limit surface
#: is that of a continuous pressure distribution rather than faceted by the grid.
SMOOTHING_CELLS = 0.5
#: Newton stops when every decrement ``g' H^-1 g`` is below this, or after this many steps.
NEWTON_DECREMENT, MAX_NEWTON_ITERATIONS = 1e-11, 30
#: A full Newton step taken from a decrement below this ends the iterations.
NEWTON_FINAL_DECREMENT = 1e-6
#: Steps are this many times shorter while the pusher touches a vertex of the outline.
VERTEX_REFINEMENT = 8
#: Halvings of a Newton step tried before it is accepted.
LINE_SEARCH_STEPS = 30
#: A contact point may move out of the pusher at no less than this fraction of its speed.
MIN_NORMAL_FRACTION = 0.05


@dataclass(frozen=True)
class BatchOutcome:
    """Result of :meth:`QuasiStaticEngine.push_batch` (world metres, ``y`` up)."""

    poses: np.ndarray  # (n, 3) final CoM x, y and angle
    hit: np.ndarray  # (n,) whether the pusher touched the object
    contact: np.ndarray  # (n, 2) first contact point (NaN for a miss)
    normal: np.ndarray  # (n, 2) inward normal there (NaN for a miss)
    blocked: np.ndarray  # (n,) the disc overlapped the object at the start of the path
    trajectories: list | None  # per push, (k + 1, 3) poses along it


def _rot(angle):
    c, s = np.cos(angle), np.sin(angle)
    return c, s


def _perp(v):
    """``J v``: turn 2-vectors a quarter turn counter-clockwise (``y`` up)."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def closest_points(outline: np.ndarray, points: np.ndarray, with_vertex: bool = False):
    """Closest point of a closed outline (E, 2) to each of ``points`` (m, 2), and distances.

    With ``with_vertex``, also whether each closest point is a vertex of the outline.
    """
    a = outline[None, :, :]
    ab = np.roll(outline, -1, axis=0)[None, :, :] - a
    rel = points[:, None, :] - a
    t = np.clip(np.einsum("mek,mek->me", rel, ab) / np.einsum("mek,mek->me", ab, ab), 0.0, 1.0)
    q = a + t[..., None] * ab
    d = np.hypot(q[..., 0] - points[:, None, 0], q[..., 1] - points[:, None, 1])
    i = np.argmin(d, axis=1)
    rows = np.arange(len(points))
    if with_vertex:
        t_best = t[rows, i]
        return q[rows, i], d[rows, i], (t_best <= 0.0) | (t_best >= 1.0)
    return q[rows, i], d[rows, i]


def _inside(outline: np.ndarray, points: np.ndarray) -> np.ndarray:
    a, b = outline[None, :, :], np.roll(outline, -1, axis=0)[None, :, :]
    py, px = points[:, None, 1], points[:, None, 0]
    crosses = (a[..., 1] > py) != (b[..., 1] > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_at = a[..., 0] + (py - a[..., 1]) * (b[..., 0] - a[..., 0]) / (b[..., 1] - a[..., 1])
    return (np.count_nonzero(crosses & (x_at > px), axis=1) % 2).astype(bool)


def first_contacts(outline, starts, directions, lengths, radius):
    """Distance along each straight path at which a disc first touches the outline.

    Exact: the disc's centre meets the outline dilated by ``radius`` (edges
    offset outwards and discs at the vertices). The outline is counter-clockwise.

    Returns
    -------
    numpy.ndarray, shape (n,)
        Distance from the start; ``inf`` if the disc does not touch the outline
        within ``lengths``; ``-1`` if it already overlaps it at the start.
    """
    s, d = np.asarray(starts, float), np.asarray(directions, float)
    a = outline[None]
    ab = np.roll(outline, -1, axis=0)[None] - a
    seg = np.hypot(ab[..., 0], ab[..., 1])
    a_off = a + radius * np.stack([ab[..., 1], -ab[..., 0]], axis=-1) / seg[..., None]
    denom = d[:, None, 0] * ab[..., 1] - d[:, None, 1] * ab[..., 0]
    rel = a_off - s[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        t_edge = (rel[..., 0] * ab[..., 1] - rel[..., 1] * ab[..., 0]) / denom
        u_edge = (rel[..., 0] * d[:, None, 1] - rel[..., 1] * d[:, None, 0]) / denom
    ok = (np.abs(denom) > 1e-15) & (u_edge >= 0) & (u_edge <= 1) & (t_edge >= 0)
    rel = s[:, None] - a
    bq = np.einsum("mek,mk->me", rel, d)
    disc = bq**2 - (np.einsum("mek,mek->me", rel, rel) - radius**2)
    t_vert = -bq - np.sqrt(np.maximum(disc, 0.0))
    t_vert = np.where((disc >= 0) & (t_vert >= 0), t_vert, np.inf)
    t = np.minimum(np.where(ok, t_edge, np.inf).min(axis=1), t_vert.min(axis=1))
    t = np.where(t <= lengths, t, np.inf)
    _, dist = closest_points(outline, s)
    return np.where((dist <= radius) | _inside(outline, s), -1.0, t)


class QuasiStaticEngine:
    """Quasi-static pushes of one rigid footprint, many at a time.

    Parameters
    ----------
    outline_body, support_body : numpy.ndarray
        Outline (E, 2, counter-clockwise) and support points (N, 2) in metres,
        relative to the CoM at angle 0.
    masses : numpy.ndarray, shape (N,)
    pusher_radius, mu_contact : float
    step_m : float
        Nominal pusher travel per step (metres).
    projections : int
        Contacts resolved per step (2 handles a pusher touching two edges).
    """

    def __init__(
        self, outline_body, support_body, masses, *, pusher_radius, mu_contact, step_m, projections
    ):
        self.length = math.sqrt(abs(_signed_area(outline_body)))  # normalising length
        self.outline = np.asarray(outline_body, float) / self.length
        self.support = np.asarray(support_body, float) / self.length
        self.weights = np.asarray(masses, float) / np.sum(masses)
        self.radius = pusher_radius / self.length
        self.tan_cone = float(mu_contact)
        self.cone = math.atan(mu_contact)
        self.step = step_m / self.length
        self.projections = int(projections)
        spacing = math.sqrt(1.0 / len(self.support))  # grid cell side, normalised
        self._eps2 = (SMOOTHING_CELLS * spacing) ** 2
        r, w = self.support, self.weights
        self._rho = _perp(r)  # velocity of each support point per unit omega
        rx, ry = self._rho[:, 0], self._rho[:, 1]
        self._moments = (w, None, w * rx, w * ry, w * rx * rx, w * rx * ry, w * ry * ry)

    # -- the two convex problems ------------------------------------------------------
    def _stick(self, c, p, omega):
        """Sticking: minimise sum_j w_j |p + omega J (r_j - c)| over omega; (m,) each.

        Newton with backtracking; a row stops as soon as it has converged, so its
        result does not depend on the other rows of the batch.
        """
        w, rx, ry = self.weights, self.support[:, 0], self.support[:, 1]
        omega = omega.copy()
        force = np.zeros((len(c), 2))
        live = np.arange(len(c))
        for _ in range(MAX_NEWTON_ITERATIONS + 1):
            cx, cy = c[live, 0:1], c[live, 1:2]
            bx, by = cy - ry, rx - cx  # J (r_j - c), (m, N)
            px, py, om = p[live, 0:1], p[live, 1:2], omega[live, None]
            ux, uy = px + om * bx, py + om * by
            s = np.sqrt(ux * ux + uy * uy + self._eps2)
            force[live, 0], force[live, 1] = (ux / s) @ w, (uy / s) @ w
            ub = ux * bx + uy * by
            grad = (ub / s) @ w
            hess = np.maximum((((bx * bx + by * by) * s * s - ub * ub) / s**3) @ w, 1e-12)
            keep = grad * grad / hess >= NEWTON_DECREMENT
            if not keep.any():
                break
            live, grad, hess = live[keep], grad[keep], hess[keep]
            bx, by, px, py, om = bx[keep], by[keep], px[keep], py[keep], om[keep]
            f0 = s[keep] @ w
            step = -grad / hess
            alpha = np.ones(len(live))
            todo = np.arange(len(live))
            for _ in range(LINE_SEARCH_STEPS):  # backtracking: Newton alone can cycle
                o1 = om[todo] + (alpha[todo] * step[todo])[:, None]
                u1x, u1y = px[todo] + o1 * bx[todo], py[todo] + o1 * by[todo]
                f1 = np.sqrt(u1x * u1x + u1y * u1y + self._eps2) @ w
                bound = f0[todo] * (1 + 1e-14) + 1e-4 * alpha[todo] * step[todo] * grad[todo]
                todo = todo[f1 > bound]
                if not len(todo):
                    break
                alpha[todo] *= 0.5
            omega[live] += alpha * step
        return omega, force

    def _slide(self, wrench, xi):
        """Sliding: argmin D(xi) subject to wrench . xi = 1, for each row; (m, 3).

        Newton on the plane ``wrench . xi = 1`` with backtracking; rows stop
        independently, as in :meth:`_stick`.
        """
        unit = wrench / np.linalg.norm(wrench, axis=1, keepdims=True)
        axis = np.eye(3)[np.argmin(np.abs(unit), axis=1)]
        e1 = np.cross(unit, axis)
        e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
        basis = np.stack([e1, np.cross(unit, e1)], axis=2)  # (m, 3, 2)
        base = wrench / np.einsum("mk,mk->m", wrench, wrench)[:, None]
        power = np.einsum("mk,mk->m", wrench, xi)  # warm start rescaled onto the plane
        xi = np.where(
            power[:, None] > 1e-12, xi / np.where(power > 1e-12, power, 1.0)[:, None], base
        )
        z = np.einsum("mkj,mk->mj", basis, xi)
        m = self._moments
        live = np.arange(len(wrench))
        for _ in range(MAX_NEWTON_ITERATIONS):
            bl, b0 = basis[live], base[live]
            x = b0 + np.einsum("mkj,mj->mk", bl, z[live])
            ux = x[:, 0:1] + x[:, 2:3] * self._rho[:, 0]
            uy = x[:, 1:2] + x[:, 2:3] * self._rho[:, 1]
            s = np.sqrt(ux * ux + uy * uy + self._eps2)
            hx, hy = ux / s, uy / s
            a11, a12, a22 = (1.0 - hx * hx) / s, -hx * hy / s, (1.0 - hy * hy) / s
            grad = np.column_stack([hx @ m[0], hy @ m[0], hx @ m[2] + hy @ m[3]])
            hess = np.empty((len(x), 3, 3))
            hess[:, 0, 0], hess[:, 0, 1], hess[:, 1, 1] = a11 @ m[0], a12 @ m[0], a22 @ m[0]
            hess[:, 0, 2] = a11 @ m[2] + a12 @ m[3]
            hess[:, 1, 2] = a12 @ m[2] + a22 @ m[3]
            hess[:, 2, 2] = a11 @ m[4] + 2.0 * (a12 @ m[5]) + a22 @ m[6]
            hess[:, 1, 0], hess[:, 2, 0], hess[:, 2, 1] = (
                hess[:, 0, 1],
                hess[:, 0, 2],
                hess[:, 1, 2],
            )
            g2 = np.einsum("mkj,mk->mj", bl, grad)
            h2 = np.einsum("mki,mkl,mlj->mij", bl, hess, bl) + 1e-12 * np.eye(2)
            step = -np.linalg.solve(h2, g2[..., None])[..., 0]
            slope = np.einsum("mj,mj->m", g2, step)
            keep = -slope >= NEWTON_DECREMENT
            if not keep.any():
                break
            live, step, slope = live[keep], step[keep], slope[keep]
            f0 = s[keep] @ self.weights
            alpha = np.ones(len(live))
            todo = np.arange(len(live))
            for _ in range(LINE_SEARCH_STEPS):  # backtracking: Newton alone can cycle
                r = live[todo]
                trial = base[r] + np.einsum(
                    "mkj,mj->mk", basis[r], z[r] + alpha[todo, None] * step[todo]
                )
                bound = f0[todo] * (1 + 1e-14) + 1e-4 * alpha[todo] * slope[todo]
                todo = todo[self._power(trial) > bound]
                if not len(todo):
                    break
                alpha[todo] *= 0.5
            z[live] += alpha[:, None] * step
            # A full Newton step from a small decrement lands within the tolerance
            # (quadratic convergence): those rows need no further evaluation.
            live = live[(alpha < 1.0) | (-slope >= NEWTON_FINAL_DECREMENT)]
            if not len(live):
                break
        return base + np.einsum("mkj,mj->mk", basis, z)

    def _power(self, x):
        """Smoothed frictional power ``D(xi)`` of twists (m, 3)."""
        ux = x[:, 0:1] + x[:, 2:3] * self._rho[:, 0]
        uy = x[:, 1:2] + x[:, 2:3] * self._rho[:, 1]
        return np.sqrt(ux * ux + uy * uy + self._eps2) @ self.weights

    def _twist(self, c, n, p, depth, state):
        """Body-frame displacement twists (m, 3) that push each body out by ``depth``."""
        omega, force = self._stick(c, p, state[:, 0])
        state[:, 0] = omega
        t = _perp(n)
        fn, ft = np.einsum("mk,mk->m", force, n), np.einsum("mk,mk->m", force, t)
        pn = np.einsum("mk,mk->m", p, n)
        stick = (fn > 0) & (np.abs(ft) <= self.tan_cone * fn) & (pn > 1e-9)
        xi = np.empty((len(c), 3))
        xi[:, :2] = p - omega[:, None] * _perp(c)
        xi[:, 2] = omega
        slide = ~stick
        if slide.any():
            side = np.where(ft[slide] >= 0, 1.0, -1.0)[:, None]
            edge = math.cos(self.cone) * n[slide] + side * math.sin(self.cone) * t[slide]
            cs = c[slide]
            wrench = np.column_stack([edge, cs[:, 0] * edge[:, 1] - cs[:, 1] * edge[:, 0]])
            xi[slide] = self._slide(wrench, state[slide, 1:])
            state[slide, 1:] = xi[slide]
        u_c = xi[:, :2] + xi[:, 2:3] * _perp(c)
        un = np.einsum("mk,mk->m", u_c, n)
        speed = np.hypot(u_c[:, 0], u_c[:, 1])
        # The contact point moves out by `depth` along n; a twist that would move it
        # (nearly) tangentially is degenerate (a pusher grazing a vertex): cap it.
        scale = depth / np.maximum(un, MIN_NORMAL_FRACTION * speed)
        return xi * scale[:, None]

    # -- the integrator --------------------------------------------------------------
    def push_batch(self, poses, starts, ends, record: bool = False) -> BatchOutcome:
        """Push from ``poses`` (n, 3) along the leading-point paths ``starts`` -> ``ends``.

        Raises ValueError if a pusher overlaps the object at its start.
        """
        L = self.length
        poses = np.array(poses, dtype=float).reshape(-1, 3)
        n = len(poses)
        x, ang = poses[:, :2] / L, poses[:, 2].copy()
        start, end = np.asarray(starts, float) / L, np.asarray(ends, float) / L
        delta = end - start
        total = np.hypot(delta[:, 0], delta[:, 1])
        d = delta / total[:, None]
        centre0 = start - self.radius * d  # the disc's centre trails its leading point
        c, s = _rot(ang)
        rel = centre0 - x
        centre_body = np.column_stack(
            [c * rel[:, 0] + s * rel[:, 1], -s * rel[:, 0] + c * rel[:, 1]]
        )
        dir_body = np.column_stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]])
        t_hit = first_contacts(self.outline, centre_body, dir_body, total, self.radius)
        # A disc that overlaps the object where its path starts (a notch narrower than
        # the pusher) is lowered farther back on the same line, beyond the object.
        blocked = t_hit < 0
        if blocked.any():
            back = 2.0 * np.abs(self.outline).max() + 2.0 * self.radius + np.hypot(*rel[blocked].T)
            centre0[blocked] -= back[:, None] * d[blocked]
            centre_body[blocked] -= back[:, None] * dir_body[blocked]
            total[blocked] += back
            t_hit[blocked] = first_contacts(
                self.outline, centre_body[blocked], dir_body[blocked], total[blocked], self.radius
            )
        hit = np.isfinite(t_hit)
        contact = np.full((n, 2), np.nan)
        normal = np.full((n, 2), np.nan)
        if hit.any():
            cb = centre_body[hit] + t_hit[hit, None] * dir_body[hit]
            q, _, first_vertex = closest_points(self.outline, cb, with_vertex=True)
            nb = (q - cb) / self.radius
            ch, sh = c[hit, None], s[hit, None]
            contact[hit] = (x[hit] + _to_world(q, ch, sh)) * L
            normal[hit] = _to_world(nb, ch, sh)
        idx = np.flatnonzero(hit)
        remaining = total[idx] - t_hit[idx]
        # Each push advances by its own steps, so its result does not depend on the
        # other pushes of the batch; steps are refined while the pusher is on a
        # vertex, where the contact normal turns quickly.
        n_steps = np.maximum(np.ceil(remaining / self.step - 1e-9), 1)
        base = remaining / n_steps
        xs, angs = x[idx], ang[idx]
        state = np.zeros((len(idx), 4))  # sticking omega, sliding twist
        c0, d0 = centre0[idx] + t_hit[idx, None] * d[idx], d[idx]
        progress = np.zeros(len(idx))
        on_vertex = first_vertex.copy() if len(idx) else np.zeros(0, bool)
        traj = [[] for _ in idx] if record else None
        while True:
            run = np.flatnonzero(progress < remaining)
            if not len(run):
                break
            ds = np.where(on_vertex[run], base[run] / VERTEX_REFINEMENT, base[run])
            progress[run] = np.where(
                progress[run] + ds > remaining[run] - 1e-9 * base[run],
                remaining[run],
                progress[run] + ds,
            )
            centre = c0[run] + progress[run, None] * d0[run]
            on_vertex[run] = False
            for _ in range(self.projections):
                cs_, sn_ = _rot(angs[run])
                rel = centre - xs[run]
                pb = np.column_stack(
                    [cs_ * rel[:, 0] + sn_ * rel[:, 1], -sn_ * rel[:, 0] + cs_ * rel[:, 1]]
                )
                q, dist, vertex = closest_points(self.outline, pb, with_vertex=True)
                depth = self.radius - dist
                act = np.flatnonzero(depth > 1e-3 * self.step)
                if not len(act):
                    break
                rows = run[act]
                on_vertex[rows] |= vertex[act]
                nb = (q[act] - pb[act]) / dist[act, None]
                pdir = np.column_stack(
                    [cs_[act] * d0[rows, 0] + sn_[act] * d0[rows, 1],
                     -sn_[act] * d0[rows, 0] + cs_[act] * d0[rows, 1]]
                )  # fmt: skip
                sub = state[rows]
                xi = self._twist(q[act], nb, pdir, depth[act], sub)
                state[rows] = sub
                dx_body = _exp_translation(xi)
                xs[rows] += _to_world(dx_body, cs_[act, None], sn_[act, None])
                angs[rows] += xi[:, 2]
            if record:
                for j in run:
                    traj[j].append((xs[j, 0] * L, xs[j, 1] * L, angs[j]))
        out = poses.copy()
        out[idx, :2] = xs * L
        out[idx, 2] = angs
        trajectories = None
        if record:
            trajectories = [poses[i : i + 1].copy() for i in range(n)]
            for j, i in enumerate(idx):
                trajectories[i] = np.vstack([poses[i : i + 1], np.array(traj[j]).reshape(-1, 3)])
        return BatchOutcome(out, hit, contact, normal, blocked, trajectories)


def _to_world(v, c, s):
    return np.column_stack(
        [c[:, 0] * v[:, 0] - s[:, 0] * v[:, 1], s[:, 0] * v[:, 0] + c[:, 0] * v[:, 1]]
    )


def _exp_translation(xi):
    """Translation of the CoM for body-frame twists ``(vx, vy, omega)`` applied for unit time."""
    w = xi[:, 2]
    small = np.abs(w) < 1e-9
    ws = np.where(small, 1.0, w)
    a = np.where(small, 1.0 - w * w / 6.0, np.sin(ws) / ws)
    b = np.where(small, w / 2.0, (1.0 - np.cos(ws)) / ws)
    return np.column_stack([a * xi[:, 0] - b * xi[:, 1], b * xi[:, 0] + a * xi[:, 1]])


def _signed_area(v) -> float:
    v = np.asarray(v, float)
    return 0.5 * float(
        np.dot(v[:, 0], np.roll(v[:, 1], -1)) - np.dot(np.roll(v[:, 0], -1), v[:, 1])
    )
