"""Pushes planned in the simulator's world frame (metres), as comcore Actions in pixels."""

from __future__ import annotations

import math

import numpy as np

from comcore import check_point

__all__ = ["action_from_world", "normal_pushes_through_com"]


def action_from_world(sim, start_m, direction, travel_m: float = 0.03, standoff_m: float = 0.01):
    """The Action (pixels) of a straight push planned in the world frame.

    The pusher's leading point starts at ``start_m`` and moves
    ``standoff_m + travel_m`` metres along ``direction``; ``sim.to_pixels``
    maps it to the mask's pixel frame (the one place that knows the y flip).

    Parameters
    ----------
    sim : PushSimulator
    start_m : array_like, shape (2,)
        Start of the leading point, metres, world frame (y up).
    direction : array_like, shape (2,)
        Push direction in the world frame (normalised here; not zero).
    travel_m, standoff_m : float, optional
        Metres of travel; their sum is the path's length (defaults: the paper's
        3 cm after a 1 cm approach).

    Returns
    -------
    numpy.ndarray, shape (4,)
        ``(sx, sy, ex, ey)`` in pixels.

    Raises
    ------
    ValueError
        If a point is not a finite 2-vector, ``direction`` is zero or the
        length is not positive.

    Examples
    --------
    >>> import simulators
    >>> sim = simulators.PushSimulator.from_polygon([(0, 0), (0.04, 0), (0.04, 0.02), (0, 0.02)])
    >>> a = simulators.action_from_world(sim, (-0.01, 0.01), (1.0, 0.0))
    >>> round(float(a[2] - a[0]) * sim.resolution, 3), float(a[3] - a[1])  # 4 cm, level
    (0.04, 0.0)
    """
    start = check_point(start_m, "start_m")
    d = check_point(direction, "direction")
    norm = math.hypot(d[0], d[1])
    if norm == 0.0:
        raise ValueError("direction must not be zero")
    length = float(travel_m) + float(standoff_m)
    if not (math.isfinite(length) and length > 0):
        raise ValueError(f"travel_m + standoff_m must be a finite length > 0, got {length}")
    end = start + length * d / norm
    return np.concatenate(sim.to_pixels(np.array([start, end])))


def normal_pushes_through_com(sim, travel_m: float = 0.03, standoff_m: float = 0.01):
    """Pushes along each outline edge's inward normal whose line passes through the CoM.

    The first check of a simulator: by symmetry of the friction about the push
    line none of them may turn the object. Edges whose foot of the CoM lies within
    the pusher's radius (plus 2 mm) of a corner are skipped.

    Parameters
    ----------
    sim : PushSimulator
    travel_m, standoff_m : float, optional
        As in :func:`action_from_world`; each push starts ``standoff_m`` outside its edge.

    Returns
    -------
    numpy.ndarray, shape (n, 4)
        Actions in pixels (possibly none).

    Examples
    --------
    >>> import simulators
    >>> sim = simulators.PushSimulator.from_polygon([(0, 0), (0.08, 0), (0.08, 0.05), (0, 0.05)])
    >>> pushes = simulators.normal_pushes_through_com(sim)
    >>> len(pushes), bool(abs(sim.push_motions(pushes)[:, 0]).max() < 1e-9)
    (4, True)
    """
    outline = sim.outline_at()
    com = np.asarray(sim.com_m)
    pushes = []
    for a, b in zip(outline, np.roll(outline, -1, axis=0)):
        edge = b - a
        length = np.linalg.norm(edge)
        t = (com - a) @ edge / length**2
        margin = (sim.pusher_radius + 0.002) / length
        if not margin < t < 1 - margin:
            continue
        inward = np.array([-edge[1], edge[0]]) / length  # CCW outline: left is inside
        start = a + t * edge - standoff_m * inward
        pushes.append(action_from_world(sim, start, inward, travel_m, standoff_m))
    return np.array(pushes).reshape(-1, 4)
