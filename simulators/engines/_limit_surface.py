"""The limit surface of a support distribution and the single-contact pushing problem.

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

Both are solved by Newton's method with backtracking on a smoothed ``|u|``,
warm-started from the previous step and vectorised over pushes; each row stops
on its own, so a push's result does not depend on the batch it is in.
"""

from __future__ import annotations

import math

import numpy as np

from ._contact import perp

__all__ = ["LimitSurface"]

#: Smoothing of |u| in units of the grid spacing (normalised): blurs each support
#: point over about that distance from the centre of rotation, so the limit surface
#: is that of a continuous pressure distribution rather than faceted by the grid.
SMOOTHING_CELLS = 0.5
#: Newton stops when every decrement ``g' H^-1 g`` is below this, or after this many steps.
NEWTON_DECREMENT, MAX_NEWTON_ITERATIONS = 1e-11, 30
#: A full Newton step taken from a decrement below this ends the iterations.
NEWTON_FINAL_DECREMENT = 1e-6
#: Halvings of a Newton step tried before it is accepted.
LINE_SEARCH_STEPS = 30
#: A contact point may move out of the pusher at no less than this fraction of its speed.
MIN_NORMAL_FRACTION = 0.05


class LimitSurface:
    """Pushing a body whose floor friction comes from weighted support points.

    Parameters
    ----------
    support : numpy.ndarray, shape (N, 2)
        Support points relative to the CoM (normalised lengths).
    weights : numpy.ndarray, shape (N,)
        Their masses, summing to 1.
    mu_contact : float
        Pusher-object friction coefficient.
    """

    def __init__(self, support, weights, mu_contact: float):
        self.support = np.asarray(support, float)
        self.weights = np.asarray(weights, float)
        self.tan_cone = float(mu_contact)
        self.cone = math.atan(mu_contact)
        spacing = math.sqrt(1.0 / len(self.support))  # grid cell side, normalised
        self._eps2 = (SMOOTHING_CELLS * spacing) ** 2
        w = self.weights
        self._rho = perp(self.support)  # velocity of each support point per unit omega
        rx, ry = self._rho[:, 0], self._rho[:, 1]
        self._moments = (w, None, w * rx, w * ry, w * rx * rx, w * rx * ry, w * ry * ry)

    def stick(self, c, p, omega):
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

    def slide(self, wrench, xi):
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
                todo = todo[self.power(trial) > bound]
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

    def power(self, x):
        """Smoothed frictional power ``D(xi)`` of twists (m, 3)."""
        ux = x[:, 0:1] + x[:, 2:3] * self._rho[:, 0]
        uy = x[:, 1:2] + x[:, 2:3] * self._rho[:, 1]
        return np.sqrt(ux * ux + uy * uy + self._eps2) @ self.weights

    def wrench(self, c, n, side):
        """Unit contact wrenches on the friction cone's edge ``side`` (+1 or -1), (m, 3)."""
        edge = math.cos(self.cone) * n + side[:, None] * math.sin(self.cone) * perp(n)
        return np.column_stack([edge, c[:, 0] * edge[:, 1] - c[:, 1] * edge[:, 0]])

    def twist(self, c, n, p, depth, state):
        """Body-frame displacement twists (m, 3) that push each body out by ``depth``.

        ``state`` (m, 5) carries each push's last sticking omega, sliding twist and
        mode (0 stick, +-1 the cone edge it slid on) from step to step.
        """
        m = len(c)
        xi = np.empty((m, 3))
        t = perp(n)
        pn = np.einsum("mk,mk->m", p, n)
        done = np.zeros(m, bool)
        # A push that slid on the previous step most likely still slides on the same
        # edge: solve that first and keep it if its slip opposes the friction force
        # (the single-contact solution is unique, so a consistent one is the one).
        again = np.flatnonzero(state[:, 4] != 0)
        if len(again):
            side = state[again, 4]
            trial = self.slide(self.wrench(c[again], n[again], side), state[again, 1:4])
            u_c = trial[:, :2] + trial[:, 2:3] * perp(c[again])
            un = np.einsum("mk,mk->m", u_c, n[again])
            ut = np.einsum("mk,mk->m", u_c, t[again])
            slip = ut / np.maximum(un, 1e-12) - np.einsum("mk,mk->m", p[again], t[again]) / (
                np.maximum(pn[again], 1e-12)
            )
            ok = (side * slip <= 0) | (pn[again] <= 1e-9)
            xi[again[ok]] = trial[ok]
            state[again[ok], 1:4] = trial[ok]
            done[again[ok]] = True
        rest = np.flatnonzero(~done)
        if len(rest):
            cr, nr, pr = c[rest], n[rest], p[rest]
            omega, force = self.stick(cr, pr, state[rest, 0])
            state[rest, 0] = omega
            fn = np.einsum("mk,mk->m", force, nr)
            ft = np.einsum("mk,mk->m", force, t[rest])
            stick = (fn > 0) & (np.abs(ft) <= self.tan_cone * fn) & (pn[rest] > 1e-9)
            xi[rest, :2] = pr - omega[:, None] * perp(cr)
            xi[rest, 2] = omega
            state[rest, 4] = 0.0
            slide = np.flatnonzero(~stick)
            if len(slide):
                rows = rest[slide]
                side = np.where(ft[slide] >= 0, 1.0, -1.0)
                xi[rows] = self.slide(self.wrench(c[rows], n[rows], side), state[rows, 1:4])
                state[rows, 1:4] = xi[rows]
                state[rows, 4] = side
        u_c = xi[:, :2] + xi[:, 2:3] * perp(c)
        un = np.einsum("mk,mk->m", u_c, n)
        speed = np.hypot(u_c[:, 0], u_c[:, 1])
        # The contact point moves out by `depth` along n; a twist that would move it
        # (nearly) tangentially is degenerate (a pusher grazing a vertex): cap it.
        scale = depth / np.maximum(un, MIN_NORMAL_FRACTION * speed)
        return xi * scale[:, None]
