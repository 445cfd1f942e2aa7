"""Pushes planned in the simulator's world frame (metres), as comcore Actions in pixels."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

import comcore
from comcore.checks import check_point

__all__ = [
    "AcceptedPushes",
    "action_from_world",
    "normal_pushes_through_com",
    "sample_accepted_pushes",
]

#: Rounds of fresh draws :func:`sample_accepted_pushes` makes before it gives up.
PUSH_DRAWS = 20


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


class AcceptedPushes(NamedTuple):
    """What :func:`sample_accepted_pushes` returns."""

    pushes: np.ndarray
    """The accepted pushes, shape (n, 4), pixels, in the order they were drawn."""
    motions: np.ndarray
    """Their motions ``(theta, tx, ty)``, shape (n, 3)."""
    refused: int
    """How many drawn pushes were refused (and replaced by fresh draws)."""


def _count(n) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise TypeError(f"n must be an integer, got {type(n).__name__}")
    if n < 0:
        raise ValueError(f"n must be >= 0, got {n}")
    return int(n)


def _together(respond, batch: np.ndarray) -> np.ndarray | None:
    """The motions of ``batch`` answered in one call, or ``None`` if it refuses any."""
    try:
        return np.asarray(respond(batch), float)
    except ValueError:
        return None


def _one_by_one(respond, batch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each push of ``batch`` answered alone: ``(motions (k, 3), accepted (k,) bool)``."""
    motions, ok = np.zeros((len(batch), 3)), np.zeros(len(batch), bool)
    for i, push in enumerate(batch):
        try:
            motions[i], ok[i] = np.asarray(respond(push[None]), float)[0], True
        except ValueError:
            pass
    return motions, ok


def sample_accepted_pushes(
    simulator,
    n: int,
    *,
    cone: float = 0.0,
    rng=None,
    respond=None,
    batched: bool = True,
    draws: int = PUSH_DRAWS,
    **sampling,
) -> AcceptedPushes:
    """``n`` pushes from :func:`comcore.sample_pushes` that the simulator accepts, with motions.

    The simulator refuses a push whose start lies inside the object's true
    outline (the sampler keeps its starts off the mask's pixels, a pixel's
    width coarser); each refused push is replaced by a fresh draw from the
    same stream, in rounds of at most ``draws``.

    Parameters
    ----------
    simulator : PushSimulator
        Or anything with its ``mask`` and ``push_motions`` (a wrapper that
        answers pushes differently).
    n : int
        Number of pushes (>= 0).
    cone : float, optional
        Half-angle (radians) of the push directions about the inward normal.
    rng : None, int or numpy.random.Generator, optional
        The draws' stream (a Generator is shared, not copied).
    respond : callable, optional
        ``respond(pushes (k, 4)) -> motions (k, 3)``, raising ValueError when it
        refuses a push; default ``simulator.push_motions``.
    batched : bool, optional
        Hand each round's pushes to ``respond`` together (one batched call;
        after a refusal they are tried one by one). ``False`` hands each push
        alone: the batched engine's motions differ from a single push's in the
        last bits, so choose the one your results were made with.
    draws : int, optional
        Rounds of draws before giving up.
    **sampling
        Other keywords of :func:`comcore.sample_pushes` (``travel``, ...).

    Returns
    -------
    AcceptedPushes
        ``(pushes (n, 4), motions (n, 3), refused)``.

    Raises
    ------
    RuntimeError
        If ``draws`` rounds leave fewer than ``n`` accepted pushes.

    Examples
    --------
    >>> import simulators
    >>> sim = simulators.random_simulator("Obj9", friction="low", rng=0)  # a U: concave
    >>> pushes, motions, refused = simulators.sample_accepted_pushes(sim, 5, cone=0.3, rng=0)
    >>> pushes.shape, motions.shape, refused
    ((5, 4), (5, 3), 0)
    """
    n = _count(n)
    mask = simulator.mask
    respond = simulator.push_motions if respond is None else respond
    rng = comcore.checks.check_rng(rng)
    pushes, motions = np.empty((0, 4)), np.empty((0, 3))
    refused = 0
    for _ in range(draws):
        if len(pushes) >= n:
            break
        batch = comcore.sample_pushes(mask, n - len(pushes), cone=cone, rng=rng, **sampling)
        answers = _together(respond, batch) if batched else None
        if answers is not None:
            ok = np.ones(len(batch), bool)
        else:
            answers, ok = _one_by_one(respond, batch)
            refused += int((~ok).sum())
        pushes, motions = np.vstack([pushes, batch[ok]]), np.vstack([motions, answers[ok]])
    if len(pushes) < n:
        raise RuntimeError(
            f"the simulator refused {refused} pushes: {len(pushes)} of {n} accepted in "
            f"{draws} rounds of draws"
        )
    return AcceptedPushes(pushes, motions, refused)
