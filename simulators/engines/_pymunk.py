"""The pymunk engine: rigid-body pushes with one floor-friction joint per support point.

Model (the measurements behind the numbers are in docs/results/simulators.md):

* Top-down view, no gravity. The body is the footprint's outline (pymunk
  segments, so concave outlines need no decomposition) with the mass and
  moment of inertia of its :class:`~simulators.MassDistribution`.
* Floor friction is distributed Coulomb friction: one ``PivotJoint`` from the
  static body to each support point, with ``max_bias = 0`` (a pure velocity
  constraint) and ``max_force = mu_floor * m_i * g``: each joint resists the
  sliding of its point with at most its Coulomb force, in any direction.
* ``g`` is a model constant, not 9.81: it is set so that friction could stop
  the body ``quasi_static_ratio`` times over within one step, which makes
  inertia negligible (quasi-static); the motion then does not depend on
  ``mu_floor`` or ``g``.
* The pusher is a kinematic disc moving ``step_m`` per time step along the
  action, with contact friction ``mu_contact``.

The space is built once and reset exactly before every push (joint impulses
cleared, cached contacts dropped, a spatial hash whose contact order does not
depend on history), so a push's result does not depend on earlier pushes.
Internally lengths are millimetres relative to the CoM at the start pose.
"""

from __future__ import annotations

import math

import numpy as np

from comcore.conventions import rotation_matrix

from .._deps import require_pymunk
from .._settings import EngineSettings
from ._contact import closest_points, first_contacts
from ._quasistatic import BatchOutcome

__all__ = ["PymunkEngine"]

#: Millimetres per metre: the engine works in millimetres.
MM = 1000.0
#: Where the pusher waits between pushes (mm).
FAR_AWAY = (1e7, 1e7)


def _rotate(v: np.ndarray, angle: float) -> np.ndarray:
    return v @ rotation_matrix(angle)  # body to world (y up)


class PymunkEngine:
    """A pymunk space holding one body, its floor joints and the pusher (not thread-safe)."""

    def __init__(
        self,
        outline_body,
        support_body,
        masses,
        moment: float,
        *,
        pusher_radius: float,
        mu_contact: float,
        mu_floor: float,
        settings: EngineSettings,
    ):
        pymunk = require_pymunk()
        self.settings = settings
        self.outline_mm = np.asarray(outline_body, float) * MM
        self.radius_mm = float(pusher_radius) * MM
        step = settings.step_m * MM
        space = pymunk.Space()
        space.iterations = int(settings.iterations)
        space.collision_slop = 1e-3 * step
        space.collision_persistence = 1
        # Unlike the default tree, the spatial hash does not depend on the index's
        # history, so contacts are solved in the same order whatever came before.
        space.use_spatial_hash(4 * self.radius_mm, 1000)
        g = settings.quasi_static_ratio * step / mu_floor
        body = pymunk.Body(float(np.sum(masses)), float(moment) * MM * MM)
        space.add(body)
        for p, q in zip(self.outline_mm, np.roll(self.outline_mm, -1, axis=0)):
            seg = pymunk.Segment(body, (float(p[0]), float(p[1])), (float(q[0]), float(q[1])), 0.0)
            seg.friction = 1.0
            space.add(seg)
        self._joints, self._max_force = [], []
        for p, m in zip(np.asarray(support_body, float) * MM, masses):
            joint = pymunk.PivotJoint(
                space.static_body, body, (0.0, 0.0), (float(p[0]), float(p[1]))
            )
            joint.max_bias = 0.0
            joint.max_force = float(mu_floor * m * g)
            self._joints.append(joint)
            self._max_force.append(joint.max_force)
        space.add(*self._joints)
        self.pusher = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.pusher.position = FAR_AWAY
        disc = pymunk.Circle(self.pusher, self.radius_mm)
        disc.friction = float(mu_contact)
        space.add(self.pusher, disc)
        self.space, self.body = space, body

    def _reset(self, angle: float) -> None:
        """Clear every trace of earlier pushes and put the body at rest at ``angle``."""
        space, body = self.space, self.body
        self.pusher.position, self.pusher.velocity = FAR_AWAY, (0.0, 0.0)
        body.velocity, body.angular_velocity = (0.0, 0.0), 0.0
        for joint in self._joints:
            joint.max_force = 0.0
        space.step(1.0)  # joint impulses clamp to zero; the pusher's contacts expire
        for joint, f in zip(self._joints, self._max_force):
            joint.max_force = f
        body.position, body.angle = (0.0, 0.0), angle
        body.velocity, body.angular_velocity = (0.0, 0.0), 0.0
        body.force, body.torque = (0.0, 0.0), 0.0

    def _push_one(self, pose, start_mm, direction, length, t_hit, record):
        """The poses after each step (``record``) and after settling, (k, 3), world metres.

        With the disc centre's travel from ``start_mm`` (mm) at each row, (k,): the
        settling row keeps the final travel, ``length``.
        """
        step = self.settings.step_m * MM
        t_begin = max(0.0, t_hit - 0.5 * step)
        self._reset(pose[2])
        space, body, pusher = self.space, self.body, self.pusher
        pusher.position = tuple(start_mm + t_begin * direction)
        remaining = length - t_begin
        n_steps = max(1, math.ceil(remaining / step))
        pusher.velocity = tuple(direction * (remaining / n_steps))
        traj = []
        for _ in range(n_steps):
            space.step(1.0)
            if record:
                traj.append((*body.position, body.angle))
        pusher.velocity = (0.0, 0.0)
        for _ in range(self.settings.settle_steps):
            space.step(1.0)
        px, py = body.position
        traj.append((px, py, body.angle))
        t = np.array(traj)
        t[:, :2] = t[:, :2] / MM + pose[:2]
        travel = t_begin + remaining * np.arange(1, n_steps + 1) / n_steps if record else []
        return t, np.append(travel, length)

    def push_batch(self, poses, starts, ends, record: bool = False) -> BatchOutcome:
        """Same contract as :meth:`simulators.engines._quasistatic.QuasiStaticEngine.push_batch`."""
        poses = np.array(poses, dtype=float).reshape(-1, 3)
        n = len(poses)
        out = poses.copy()
        hit, blocked = np.zeros(n, bool), np.zeros(n, bool)
        contact, normal = np.full((n, 2), np.nan), np.full((n, 2), np.nan)
        trajs, travel = [], []
        for i in range(n):
            start = (np.asarray(starts[i], float) - poses[i, :2]) * MM
            end = (np.asarray(ends[i], float) - poses[i, :2]) * MM
            length = float(np.hypot(*(end - start)))
            d = (end - start) / length
            centre0 = start - self.radius_mm * d  # the disc's centre trails its leading point
            outline = _rotate(self.outline_mm, poses[i, 2])
            args = (outline, centre0[None], d[None], np.array([length]), self.radius_mm)
            t_hit = first_contacts(*args)[0]
            back = 0.0  # how far the disc was lowered behind the commanded start (mm)
            if t_hit < 0:  # lowered farther back on the line, beyond the object
                blocked[i] = True
                back = 2.0 * np.abs(outline).max() + 2.0 * self.radius_mm + np.hypot(*start)
                centre0, length = centre0 - back * d, length + back
                t_hit = first_contacts(outline, centre0[None], d[None], [length], self.radius_mm)[0]
            traj, along = np.array([poses[i]]), np.zeros(1)
            if np.isfinite(t_hit):
                hit[i] = True
                centre = centre0 + t_hit * d
                q, _ = closest_points(outline, centre[None])
                contact[i] = q[0] / MM + poses[i, :2]
                normal[i] = (q[0] - centre) / self.radius_mm
                moved, moved_travel = self._push_one(poses[i], centre0, d, length, t_hit, record)
                out[i] = moved[-1]
                traj = np.vstack([poses[i], moved])
                # the leading point's travel from the commanded start: the disc centre's
                # from centre0, less how far centre0 was lowered behind it
                along = (np.concatenate([[t_hit], moved_travel]) - back) / MM
            trajs.append(traj)
            travel.append(along)
        if not record:
            trajs = travel = None
        return BatchOutcome(out, hit, contact, normal, blocked, trajs, travel)
