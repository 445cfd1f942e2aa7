"""The quasi-static engine: pushes integrated step by step, batched over pushes.

Each step advances every pusher along its path by its own nominal step (shorter
while it touches a vertex, where the contact normal turns fast); the object is
then moved out of the pusher's disc exactly (a position-level step: no drift, no
tunnelling). The twist of each step comes from
:class:`~simulators.engines._limit_surface.LimitSurface` (the physics is described there).
A pusher in a concave notch can touch two edges: each step resolves the deepest
contact, then the next one (``projections``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from comcore.conventions import rotate_components

from ._contact import (
    closest_points,
    exp_translation,
    first_contacts,
    rotation,
    signed_area,
    to_world,
)
from ._limit_surface import LimitSurface

__all__ = ["BatchOutcome", "QuasiStaticEngine"]

#: Steps are this many times shorter while the pusher touches a vertex of the outline.
VERTEX_REFINEMENT = 4


@dataclass(frozen=True)
class BatchOutcome:
    """Result of :meth:`QuasiStaticEngine.push_batch` (world metres, ``y`` up).

    ``trajectories`` and ``travel`` (``None`` unless ``record``) go together, row for
    row: per push, the poses along it, (k + 1, 3), and how far (metres) the pusher's
    leading point had come from the commanded path's start at each of them, (k + 1,).
    Row 0 is the start pose, at the travel of the first contact (the object has not
    moved before it); then one row per step. The travel never decreases and ends at
    the path's length. A miss has a single row, at travel 0. A blocked push (the disc
    lowered farther back on the line, ``blocked``) is still measured from the
    commanded start, so it may start negative: the disc touched the object before its
    leading point reached the commanded start.
    """

    poses: np.ndarray  # (n, 3) final CoM x, y and angle
    hit: np.ndarray  # (n,) whether the pusher touched the object
    contact: np.ndarray  # (n, 2) first contact point (NaN for a miss)
    normal: np.ndarray  # (n, 2) inward normal there (NaN for a miss)
    blocked: np.ndarray  # (n,) the disc overlapped the object at the start of the path
    trajectories: list | None  # per push, (k + 1, 3) poses along it
    travel: list | None = None  # per push, (k + 1,) leading point's travel (m) at each row


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
        self.length = math.sqrt(abs(signed_area(outline_body)))  # normalising length
        self.outline = np.asarray(outline_body, float) / self.length
        self.support = np.asarray(support_body, float) / self.length
        self.weights = np.asarray(masses, float) / np.sum(masses)
        self.radius = pusher_radius / self.length
        self.step = step_m / self.length
        self.projections = int(projections)
        self.surface = LimitSurface(self.support, self.weights, mu_contact)

    # -- the integrator --------------------------------------------------------------
    def push_batch(self, poses, starts, ends, record: bool = False) -> BatchOutcome:
        """Push from ``poses`` (n, 3) along the leading-point paths ``starts`` -> ``ends``.

        Raises ValueError if a pusher overlaps the object at its start. ``record``: also
        the poses along each push and the pusher's travel at each (:class:`BatchOutcome`).
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
        c, s = rotation(ang)
        rel = centre0 - x
        centre_body = np.column_stack(rotate_components(rel[:, 0], rel[:, 1], c, s))  # to body
        dir_body = np.column_stack(rotate_components(d[:, 0], d[:, 1], c, s))
        t_hit = first_contacts(self.outline, centre_body, dir_body, total, self.radius)
        # A disc that overlaps the object where its path starts (a notch narrower than
        # the pusher) is lowered farther back on the same line, beyond the object.
        blocked = t_hit < 0
        lowered = np.zeros(n)  # how far each disc was lowered behind the commanded start
        if blocked.any():
            back = 2.0 * np.abs(self.outline).max() + 2.0 * self.radius + np.hypot(*rel[blocked].T)
            lowered[blocked] = back
            centre0[blocked] -= back[:, None] * d[blocked]
            centre_body[blocked] -= back[:, None] * dir_body[blocked]
            total[blocked] += back
            t_hit[blocked] = first_contacts(
                self.outline, centre_body[blocked], dir_body[blocked], total[blocked], self.radius
            )
        hit = np.isfinite(t_hit)
        contact = np.full((n, 2), np.nan)
        normal = np.full((n, 2), np.nan)
        first_vertex = np.zeros(0, bool)
        if hit.any():
            cb = centre_body[hit] + t_hit[hit, None] * dir_body[hit]
            q, _, first_vertex = closest_points(self.outline, cb, with_vertex=True)
            nb = (q - cb) / self.radius
            ch, sh = c[hit, None], s[hit, None]
            contact[hit] = (x[hit] + to_world(q, ch, sh)) * L
            normal[hit] = to_world(nb, ch, sh)
        idx = np.flatnonzero(hit)
        xs, angs, traj = self._follow(
            x[idx], ang[idx], centre0[idx] + t_hit[idx, None] * d[idx], d[idx],
            total[idx] - t_hit[idx], first_vertex, record=record,
        )
        out = poses.copy()
        out[idx, :2] = xs * L
        out[idx, 2] = angs
        trajectories = travel = None
        if record:
            trajectories = [poses[i : i + 1].copy() for i in range(n)]
            travel = [np.zeros(1) for _ in range(n)]
            for j, i in enumerate(idx):
                rows = np.array(traj[j]).reshape(-1, 4)  # x, y, angle, progress after contact
                trajectories[i] = np.vstack([poses[i : i + 1], rows[:, :3]])
                # the leading point is t_hit - lowered past the commanded start at contact
                progress = np.concatenate([[0.0], rows[:, 3]])
                travel[i] = (t_hit[i] - lowered[i] + progress) * L
        return BatchOutcome(out, hit, contact, normal, blocked, trajectories, travel)

    def _follow(self, xs, angs, c0, d0, remaining, first_vertex, *, record):
        """Step the pushers from their first contacts ``c0`` along ``d0`` by ``remaining``.

        ``xs`` (n, 2) and ``angs`` (n,) are the objects' poses (normalised
        lengths), updated in place and returned with the recorded trajectories
        (``None`` unless ``record``): per push, rows ``(x, y, angle, progress)``,
        metres and radians but ``progress``, the disc's normalised travel since
        ``c0``.
        """
        L = self.length
        # Each push advances by its own steps, so its result does not depend on the
        # other pushes of the batch; steps are refined while the pusher is on a
        # vertex, where the contact normal turns quickly.
        n_steps = np.maximum(np.ceil(remaining / self.step - 1e-9), 1)
        base = remaining / n_steps
        state = np.zeros((len(xs), 5))  # sticking omega, sliding twist, mode
        progress = np.zeros(len(xs))
        on_vertex = first_vertex.copy()
        traj = [[] for _ in range(len(xs))] if record else None
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
                cs_, sn_ = rotation(angs[run])
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
                )
                sub = state[rows]
                xi = self.surface.twist(q[act], nb, pdir, depth[act], sub)
                state[rows] = sub
                dx_body = exp_translation(xi)
                xs[rows] += to_world(dx_body, cs_[act, None], sn_[act, None])
                angs[rows] += xi[:, 2]
            if record:
                for j in run:
                    traj[j].append((xs[j, 0] * L, xs[j, 1] * L, angs[j], progress[j]))
        return xs, angs, traj
