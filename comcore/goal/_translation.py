"""Pushes along a direction, their outcomes over CoM hypotheses, and :func:`translation_push`.

A candidate push here is a straight line parallel to a direction, at an
offset across the object, started a standoff before the round pusher first
touches the outline (:func:`comcore.geometry.disc_contacts`) and carried on for a
travel after it. Its motion is predicted by the motion model for every
(CoM, friction) hypothesis at once (:func:`predict_motions`), in the first
mask's frame, where the posterior lives; :func:`camera_motions` turns the
predictions into the camera frame of the object's pose now.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._checks import check_finite
from .._mask import Mask
from .._types import Action, Motion
from .._validation import check_count, check_mask, check_motions, check_physical
from ..active._options import DEFAULT_PUSHER_RADIUS
from ..camera._pose_tracking import camera_from_object
from ..conventions import apply_motion, rotate_vectors
from ..geometry._contacts import contacts
from ..geometry._disc_contacts import disc_contacts
from ..motion._limit_surface import LimitSurfaceModel, check_push_lengths
from ..motion._predictor import check_model_output
from ._types import PLANNING_PARTICLES, CoMHypotheses, hypotheses_from

__all__ = [
    "STANDOFF_M",
    "TranslationPush",
    "camera_motions",
    "line_pushes",
    "planning_model",
    "predict_motions",
    "translation_push",
]

#: Distance (metres) from a push's start to where the pusher first touches the object.
STANDOFF_M = 0.012


def planning_model(pusher_radius: float) -> LimitSurfaceModel:
    """The default motion model of the planner: every hypothesis integrated, no lattice."""
    return LimitSurfaceModel(pusher_radius=pusher_radius, node_spacing=0.0)


def line_pushes(first: Mask, pose: Motion, directions, offsets, lengths, pusher_radius: float):
    """Pushes along camera directions at offsets across the object, each for several lengths.

    Parameters
    ----------
    first : Mask
        The object's frame (the first mask).
    pose : Motion
        The object's pose now, relative to ``first``.
    directions : numpy.ndarray, shape (d,)
        Push directions, radians in the camera frame (0: +x, pi/2: +y down).
    offsets : numpy.ndarray, shape (d, o)
        Signed offsets (px) of each line from the first centroid, across its direction.
    lengths : numpy.ndarray, shape (l,)
        Travels after contact (px).

    Returns
    -------
    actions : numpy.ndarray, shape (n, 4)
        The pushes that touch the object, in the first mask's frame.
    meta : numpy.ndarray, shape (n, 3)
        Their direction index, offset (px) and length (px).
    """
    c0 = np.asarray(first.centroid, float)
    reach = float(np.hypot(*(first.pixels - c0).T).max()) + pusher_radius / first.resolution + 2
    standoff = STANDOFF_M / first.resolution
    d_idx, o_idx = np.meshgrid(np.arange(len(directions)), np.arange(offsets.shape[1]))
    d_idx, o_idx = d_idx.ravel(), o_idx.ravel()
    camera = np.asarray(directions, float)[d_idx]
    # the object turned pose.theta from the first mask: turn back into its frame
    unit = rotate_vectors(np.column_stack([np.cos(camera), np.sin(camera)]), -pose.theta)
    across = np.column_stack([-unit[:, 1], unit[:, 0]])
    off = offsets[d_idx, o_idx]
    start = c0 + off[:, None] * across - (reach + standoff) * unit
    probe = np.hstack([start, start + 2 * (reach + standoff) * unit])
    con = disc_contacts(first, probe, pusher_radius)
    ok = con.hit & ~con.starts_inside
    # the leading point's own line must meet the outline too: a push only its disc's side
    # touches has no force line for the posterior's evidence
    line_hits = contacts(first, probe)
    ok &= line_hits.hit & ~line_hits.starts_inside
    lead = start[ok] + con.travel[ok, None] * unit[ok]
    begin = lead - standoff * unit[ok]
    n_l = len(lengths)
    ends = lead[:, None, :] + np.asarray(lengths, float)[None, :, None] * unit[ok][:, None, :]
    actions = np.concatenate([np.repeat(begin[:, None, :], n_l, axis=1), ends], axis=2)
    meta = np.stack(
        np.broadcast_arrays(d_idx[ok][:, None], off[ok][:, None], np.asarray(lengths)[None]),
        axis=-1,
    )
    return actions.reshape(-1, 4), meta.reshape(-1, 3).astype(float)


def predict_motions(model, first: Mask, actions: np.ndarray, hyps: CoMHypotheses) -> np.ndarray:
    """Each push's motion for each hypothesis, first mask's frame: shape (n_h, n_a, 3).

    One model call per distinct friction value, vectorised over the pushes and
    that friction's CoMs (one call for all with the planner's own
    :class:`comcore.LimitSurfaceModel`, which integrates a friction per row).
    """
    out = np.zeros((len(hyps.coms), len(actions), 3))
    if len(actions) == 0:
        return out
    if isinstance(model, LimitSurfaceModel) and model.node_spacing == 0:
        # one batch for every friction: the integration takes a friction per pressure row
        check_push_lengths(first, np.asarray(actions, float))
        press = model._pressures(first, hyps.coms)
        return model._motions(first, np.asarray(actions, float), press, hyps.mus)
    for mu in np.unique(hyps.mus):
        rows = np.flatnonzero(hyps.mus == mu)
        pred = model.predict_hypotheses(first, actions, hyps.coms[rows], float(mu))
        out[rows] = check_model_output(model, pred, actions, hyps.coms[rows], mu, first)
    return out


def camera_motions(motions: np.ndarray, pose: Motion) -> np.ndarray:
    """Object-frame motions (..., 3) as the camera sees them at ``pose`` (about the centroid)."""
    out = np.array(motions, dtype=float)
    out[..., 1:] = rotate_vectors(out[..., 1:], pose.theta)
    return out


class TranslationPush(NamedTuple):
    """The push :func:`comcore.goal.translation_push` chose, and what it expects of it."""

    action: Action
    """The push, camera pixels (the path of the pusher's leading point)."""
    expected_rotation: float
    """Posterior mean of the object's rotation over the push (radians, CCW on screen)."""
    rotation_spread: float
    """Posterior standard deviation of that rotation (radians)."""
    expected_travel: float
    """Posterior mean of the centroid's displacement along the direction (metres)."""
    expected_drift: float
    """Posterior mean of its displacement across the direction (metres, CCW side positive)."""


def _cross_offsets(
    first: Mask, angle: float, hyps: CoMHypotheses, n: int, halves: bool = True
) -> np.ndarray:
    """Offsets across the object (px), evenly spaced, plus the hypotheses' mean, +-1 sd (+-0.5)."""
    c0 = np.asarray(first.centroid, float)
    across = np.array([-math.sin(angle), math.cos(angle)])
    proj = (first.pixels - c0) @ across
    lo, hi = proj.min() + 0.5, proj.max() - 0.5
    com = (hyps.coms - c0) @ across
    mean = float(hyps.weights @ com)
    sd = math.sqrt(float(hyps.weights @ (com - mean) ** 2))
    extra = [mean, mean - sd, mean + sd] + ([mean - 0.5 * sd, mean + 0.5 * sd] if halves else [])
    return np.clip(np.concatenate([np.linspace(lo, hi, n), extra]), lo, hi)


def translation_push(
    mask,
    posterior,
    direction,
    travel,
    *,
    pose=None,
    pusher_radius: float = DEFAULT_PUSHER_RADIUS,
    model=None,
    n_offsets: int = 25,
    n_particles: int = PLANNING_PARTICLES,
) -> TranslationPush:
    """The push that moves the object along a direction with the least expected rotation.

    Candidates are pushes parallel to ``direction`` at ``n_offsets`` offsets
    across the object (and at the posterior mean's offset and +-0.5 and 1
    standard deviations of it), each ``travel`` long after contact. Each is
    predicted by the motion model for ``n_particles`` (CoM, friction)
    particles of the posterior. The push kept minimises the **root mean square
    rotation** over the posterior, ``sqrt(mean^2 + spread^2)``: the expected
    squared rotation, so that a push whose mean rotation is zero but which the
    posterior says may turn the object either way loses to one that surely
    turns it a little. Its mean rotation and spread are returned.

    Parameters
    ----------
    mask : Mask
        The object as the camera sees it now; or, with ``pose``, the first
        mask (the posterior's frame).
    posterior : Estimate, array_like or (coms, weights)
        The CoM posterior, pixels of ``mask``: an active estimator's
        :class:`comcore.Estimate` (its posterior image and friction
        posterior), CoM hypotheses ``(k, 2)`` or ``(coms, weights)``
        (frictions: the :class:`comcore.Likelihood` grid).
    direction : float
        Radians in the camera frame (0: +x, pi/2: +y, down the screen).
    travel : float
        Metres the pusher travels after contact.
    pose : Motion or (theta, tx, ty), optional
        The object's pose now relative to ``mask`` (default: where ``mask`` is).
    pusher_radius : float, optional
        Metres (default 4 mm).
    model : comcore.Predictor, optional
        Default :class:`comcore.LimitSurfaceModel` with ``pusher_radius``,
        every hypothesis integrated.
    n_offsets, n_particles : int, optional

    Returns
    -------
    TranslationPush

    Raises
    ------
    TypeError, ValueError
        On invalid arguments (named).

    Examples
    --------
    A 7.5 x 5 cm plate whose CoM sits 5 px below its centroid, pushed to the
    right: the chosen line passes by the CoM and the plate barely turns.

    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((20, 30), bool), 20))
    >>> com = (34.5, 34.5)
    >>> push = comcore.goal.translation_push(mask, [com], 0.0, 0.03, n_offsets=9)
    >>> abs(push.action.sy - com[1]) < 1.5, abs(push.expected_rotation) < 0.01
    (True, True)
    """
    mask = check_mask(mask)
    pose = Motion.identity() if pose is None else Motion(*check_motions(pose, n=1, name="pose")[0])
    angle = check_finite(direction, "direction")
    travel_m = check_physical(travel, "travel", "push_length")
    pusher_radius = check_physical(pusher_radius, "pusher_radius", "pusher_radius", allow_zero=True)
    n_offsets = check_count(n_offsets, "n_offsets", 1)
    n_particles = check_count(n_particles, "n_particles", 1)
    travel_px = travel_m / mask.resolution
    if travel_px < 1:
        raise ValueError(f"travel {travel_m:g} m is under a pixel ({mask.resolution:g} m/px)")
    hyps = hypotheses_from(posterior, mask, int(n_particles))
    model = planning_model(pusher_radius) if model is None else model
    offsets = _cross_offsets(mask, angle + pose.theta, hyps, int(n_offsets))[None]
    actions, _ = line_pushes(mask, pose, np.array([angle]), offsets, [travel_px], pusher_radius)
    if len(actions) == 0:
        raise ValueError("no push along direction touches the object")
    motions = predict_motions(model, mask, actions, hyps)  # (h, a, 3)
    w = hyps.weights[:, None]
    mean = (w * motions[..., 0]).sum(axis=0)
    spread = np.sqrt((w * (motions[..., 0] - mean) ** 2).sum(axis=0))
    best = int(np.argmin(mean**2 + spread**2))
    cam = camera_motions(motions[:, best], pose)
    moved = (w * cam[:, 1:]).sum(axis=0) * mask.resolution
    unit = np.array([math.cos(angle), math.sin(angle)])
    action = camera_from_object(actions[best : best + 1], pose, mask.centroid)[0]
    return TranslationPush(
        Action(*action),
        float(mean[best]),
        float(spread[best]),
        float(moved @ unit),
        float(moved @ np.array([unit[1], -unit[0]])),
    )


def centroid_now(first: Mask, pose: Motion) -> np.ndarray:
    """Where the first mask's centroid is in the camera at ``pose`` (px)."""
    c0 = np.asarray(first.centroid, float)
    return apply_motion(c0[None], pose.theta, (pose.tx, pose.ty), c0)[0]
