"""The pymunk engine: one quasi-static push of a rigid footprint by a round pusher.

Model (see docs/simulators.md for the measurements behind the numbers):

* Top-down view, no gravity. The body is the footprint's outline (pymunk
  segments, so concave outlines need no decomposition) with the mass and
  moment of inertia of its :class:`~simulators._mass.MassDistribution`.
* Floor friction is distributed Coulomb friction: one ``PivotJoint`` from the
  static body to each support point, with ``max_bias = 0`` (a pure velocity
  constraint) and ``max_force = mu_floor * m_i * g``. Each joint resists the
  sliding of its point with at most its Coulomb force, in any direction, so
  the body's response comes from the limit surface of the whole support.
* ``g`` is a model constant, not 9.81: it is set so that friction can stop the
  body within ``1 / QUASI_STATIC_RATIO`` of a step; inertia is then
  negligible (quasi-static) while the solver stays well conditioned. In the
  quasi-static limit the motion does not depend on ``mu_floor`` or ``g``.
* The pusher is a kinematic disc moving at a constant speed of ``step_m`` per
  time step along the action; contact friction is ``mu_contact``.

Internally lengths are millimetres relative to the CoM at the start pose.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._deps import require_pymunk

__all__ = ["EngineSettings", "PushOutcome", "first_contact", "simulate_push"]


@dataclass(frozen=True)
class EngineSettings:
    """Numerical settings of the engine (defaults measured in docs/simulators.md).

    Attributes
    ----------
    step_m : float
        Pusher travel per time step, metres.
    iterations : int
        Solver iterations per step.
    quasi_static_ratio : float
        ``mu_floor * g * dt**2 / step``: how many times per step friction could
        stop the body. Larger is more quasi-static but converges more slowly.
    settle_steps : int
        Steps run after the pusher stops, so the body comes to rest.
    """

    step_m: float = 0.0005
    iterations: int = 10
    quasi_static_ratio: float = 10.0
    settle_steps: int = 4

    def __post_init__(self):
        if not (self.step_m > 0 and math.isfinite(self.step_m)):
            raise ValueError(f"step_m must be > 0, got {self.step_m}")
        if int(self.iterations) != self.iterations or self.iterations < 1:
            raise ValueError(f"iterations must be a positive integer, got {self.iterations}")
        if not self.quasi_static_ratio > 0:
            raise ValueError(f"quasi_static_ratio must be > 0, got {self.quasi_static_ratio}")


@dataclass(frozen=True)
class PushOutcome:
    """What one simulated push did (world metres, ``y`` up)."""

    pose: tuple[float, float, float]
    contact_m: tuple[float, float] | None
    normal: tuple[float, float] | None
    trajectory: np.ndarray | None


def _rotate(v: np.ndarray, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return v @ np.array([[c, s], [-s, c]])


def _closest_on_outline(outline: np.ndarray, point: np.ndarray):
    """Closest point of a closed outline (k, 2) to ``point`` and its distance."""
    a, b = outline, np.roll(outline, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    q = a + t[:, None] * ab
    d = np.hypot(q[:, 0] - point[0], q[:, 1] - point[1])
    i = int(np.argmin(d))
    return q[i], float(d[i])


def _inside(outline: np.ndarray, point: np.ndarray) -> bool:
    a, b = outline, np.roll(outline, -1, axis=0)
    crosses = (a[:, 1] > point[1]) != (b[:, 1] > point[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        x_at = a[:, 0] + (point[1] - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(crosses & (x_at > point[0])) % 2)


def first_contact(outline: np.ndarray, start, direction, length: float, radius: float):
    """Distance along a straight path at which a disc first touches an outline.

    Exact: the disc's centre meets the outline dilated by ``radius`` (edges
    offset outwards and discs at the vertices).

    Returns
    -------
    float or None
        Distance from ``start`` (``None`` if the disc does not touch it within
        ``length``); ``-1.0`` when the disc already overlaps the outline at
        ``start``.
    """
    s = np.asarray(start, dtype=float)
    d = np.asarray(direction, dtype=float)
    _, dist = _closest_on_outline(outline, s)
    if dist <= radius or _inside(outline, s):
        return -1.0
    a, b = outline, np.roll(outline, -1, axis=0)
    ab = b - a
    seg_len = np.hypot(ab[:, 0], ab[:, 1])
    out_normal = np.column_stack([ab[:, 1], -ab[:, 0]]) / seg_len[:, None]  # CCW outline
    a_off = a + radius * out_normal
    # Ray s + t d against offset segments a_off + u ab.
    denom = d[0] * ab[:, 1] - d[1] * ab[:, 0]
    rel = a_off - s
    with np.errstate(divide="ignore", invalid="ignore"):
        t_edge = (rel[:, 0] * ab[:, 1] - rel[:, 1] * ab[:, 0]) / denom
        u_edge = (rel[:, 0] * d[1] - rel[:, 1] * d[0]) / denom
    ok = (np.abs(denom) > 1e-15) & (u_edge >= 0) & (u_edge <= 1) & (t_edge >= 0)
    # Ray against the discs at the vertices: |s + t d - a|^2 = r^2.
    rel = s - a
    bq = rel @ d
    cq = np.einsum("ij,ij->i", rel, rel) - radius**2
    disc = bq**2 - cq
    t_vert = np.where(disc >= 0, -bq - np.sqrt(np.maximum(disc, 0.0)), np.inf)
    t_vert = np.where(t_vert >= 0, t_vert, np.inf)
    t = min(float(np.min(np.where(ok, t_edge, np.inf))), float(t_vert.min()))
    return t if t <= length else None


def simulate_push(
    outline_body: np.ndarray,
    support_body: np.ndarray,
    masses: np.ndarray,
    moment: float,
    pose,
    start_m,
    end_m,
    *,
    pusher_radius: float,
    mu_contact: float,
    mu_floor: float,
    settings: EngineSettings,
    record: bool = False,
) -> PushOutcome:
    """Simulate one push from ``pose``; see the module docstring for the model.

    ``outline_body`` and ``support_body`` are in metres relative to the CoM at
    angle 0; ``pose`` is the CoM position (metres) and angle; ``start_m`` and
    ``end_m`` are the path of the pusher's leading point in world metres.
    """
    pymunk = require_pymunk()
    x0, y0, a0 = (float(v) for v in pose)
    mm = 1000.0
    start = (np.asarray(start_m, float) - (x0, y0)) * mm
    end = (np.asarray(end_m, float) - (x0, y0)) * mm
    length = float(np.hypot(*(end - start)))
    direction = (end - start) / length
    radius = pusher_radius * mm
    centre0 = start - radius * direction  # the disc's centre trails its leading point
    outline = _rotate(outline_body * mm, a0)
    t_hit = first_contact(outline, centre0, direction, length, radius)
    if t_hit is not None and t_hit < 0:
        raise ValueError("the pusher overlaps the object at the start of the action")
    if t_hit is None:
        traj = np.array([[x0, y0, a0]]) if record else None
        return PushOutcome((x0, y0, a0), None, None, traj)
    centre_hit = centre0 + t_hit * direction
    touch, _ = _closest_on_outline(outline, centre_hit)
    inward = (touch - centre_hit) / radius
    step = settings.step_m * mm
    t_begin = max(0.0, t_hit - 0.5 * step)

    space = pymunk.Space()
    space.iterations = int(settings.iterations)
    space.collision_slop = 1e-3 * step
    g = settings.quasi_static_ratio * step / mu_floor
    body = pymunk.Body(float(masses.sum()), float(moment) * mm * mm)
    body.angle = a0
    space.add(body)
    segments = []
    for p, q in zip(outline_body * mm, np.roll(outline_body, -1, axis=0) * mm):
        seg = pymunk.Segment(body, (float(p[0]), float(p[1])), (float(q[0]), float(q[1])), 0.0)
        seg.friction = 1.0
        segments.append(seg)
    space.add(*segments)
    joints = []
    for p, m in zip(support_body * mm, masses):
        joint = pymunk.PivotJoint(space.static_body, body, (0.0, 0.0), (float(p[0]), float(p[1])))
        joint.max_bias = 0.0
        joint.max_force = float(mu_floor * m * g)
        joints.append(joint)
    space.add(*joints)
    pusher = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    pusher.position = tuple(centre0 + t_begin * direction)
    disc = pymunk.Circle(pusher, radius)
    disc.friction = float(mu_contact)
    space.add(pusher, disc)

    remaining = length - t_begin
    n_steps = max(1, math.ceil(remaining / step))
    pusher.velocity = tuple(direction * (remaining / n_steps))
    traj = [] if record else None
    for _ in range(n_steps):
        space.step(1.0)
        if record:
            traj.append((*body.position, body.angle))
    pusher.velocity = (0.0, 0.0)
    for _ in range(settings.settle_steps):
        space.step(1.0)
    if record:
        traj.append((*body.position, body.angle))
        t = np.array(traj)
        t[:, :2] = t[:, :2] / mm + (x0, y0)
        traj = np.vstack([[x0, y0, a0], t])
    px, py = body.position
    final = (x0 + px / mm, y0 + py / mm, float(body.angle))
    contact = (x0 + touch[0] / mm, y0 + touch[1] / mm)
    return PushOutcome(final, contact, (float(inward[0]), float(inward[1])), traj)
