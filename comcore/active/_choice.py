"""Choosing the next push: the candidates, and what each is expected to teach.

Open this file to change how pushes are chosen. What a user sets is
:class:`PushChoice` (``comcore.PushChoice``). Candidates are drawn (or given)
once, on the first mask: in the object's frame, with their force lines there,
so the posterior (which lives on the object) is scored with them whatever the
pose. What moves with the object is where the robot must push:
:meth:`Candidates.offerable` maps each candidate through the pose and keeps the
ones that start outside the object as it is now, stay in the image and hit it.
:meth:`Candidates.choose` scores the offered ones (:func:`sense_information`,
or :func:`model_gains` with ``PushChoice(selection="model")``) and returns the
best; whether it is worth making is the stop rule's call (:mod:`comcore.active._stop`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import logsumexp

from .._mask import Mask
from .._types import Motion
from .._validation import check_actions, check_physical, check_positive
from ..camera._pose_tracking import camera_from_object
from ..conventions import DEFAULT_TRAVEL_M
from ..geometry._disc_contacts import pusher_contacts, usable_pushes
from ..geometry._sampling import sample_pushes
from ..vt._voting import LINE_SCALE_PX, force_line_distances, push_force_lines
from ._grid import GridPosterior
from ._motion_term import STUDENT_DOF, com_shift, model_predictions, student_t, theta_scale
from ._options import _bounded_count

__all__ = [
    "MAX_CANDIDATES",
    "SELECTIONS",
    "Candidates",
    "PushChoice",
    "model_gains",
    "sense_information",
]

#: Hypotheses (pixel, friction) drawn from the posterior to score candidates with the model.
MODEL_PARTICLES = 64
#: Above this many pixels, hypotheses are gathered into blocks to score candidates.
MAX_SCORING_POINTS = 2500
#: Posterior mass below which pixels are skipped when scoring candidates.
PRUNE_MASS = 1e-7
#: Ways to choose the next push.
SELECTIONS = ("sense", "model")
#: Most default candidates drawn (:func:`comcore.sample_pushes`): a session's cost grows with
#: them (benchmarks/timing/bench_active.py times it).
MAX_CANDIDATES = 20_000


@dataclass(frozen=True)
class PushChoice:
    """How the next push is chosen among the candidates (:class:`Candidates`).

    Attributes
    ----------
    selection : {"sense", "model"}
        ``"sense"``: the candidate whose observed sense of rotation is expected
        to tell the most about the CoM (exact over the whole posterior).
        ``"model"``: the candidate whose whole motion, as the motion model
        predicts it, is expected to tell the most (slower; it steers towards
        pushes where the model is least right, docs/explanation/method.md).
    n_candidates : int
        Number of default candidates (:func:`comcore.sample_pushes`), at most
        :data:`MAX_CANDIDATES`.
    cone : float
        Half-angle (radians, in [0, pi/2)) of the default candidates'
        directions about the inward normal; 0 pushes along the normal, where
        the contact sticks for any friction.
    travel : float
        How far (metres) the default candidates push past first contact: set
        it from your workspace. Longer pushes tell more per push, and the
        model errs more on them. At most 0.5 m (``comcore.conventions.PLAUSIBLE``).

    Examples
    --------
    >>> import comcore
    >>> comcore.PushChoice(selection="rotation")
    Traceback (most recent call last):
    ...
    ValueError: selection must be one of ('sense', 'model'), got 'rotation'
    """

    selection: str = "sense"
    n_candidates: int = 200
    cone: float = 0.0
    travel: float = DEFAULT_TRAVEL_M

    def __post_init__(self):
        if self.selection not in SELECTIONS:
            raise ValueError(f"selection must be one of {SELECTIONS}, got {self.selection!r}")
        n_candidates = _bounded_count(self.n_candidates, "n_candidates", MAX_CANDIDATES, "pushes")
        cone = check_positive(self.cone, "cone", allow_zero=True)
        if cone >= math.pi / 2:
            raise ValueError(f"cone must be a half-angle in [0, pi/2) radians, got {cone}")
        travel = check_physical(self.travel, "travel", "push_length")
        for name, value in (("n_candidates", n_candidates), ("cone", cone), ("travel", travel)):
            object.__setattr__(self, name, value)


class Candidates:
    """Object-frame candidate pushes with their force lines (internal, mutable).

    Parameters
    ----------
    mask : Mask
        The first mask.
    candidates : array_like, shape (n, 4), or None
        Given pushes, or None to draw ``choice.n_candidates`` with
        :func:`comcore.sample_pushes`. Given pushes that start inside the
        first mask or never touch it are not offered (:attr:`skipped` says
        which and why); a ValueError if none is usable.
    choice : PushChoice
    mus : numpy.ndarray, shape (m,)
        The friction values of the force lines.
    rng : numpy.random.Generator
    name : str, optional
        The argument's name in error messages.
    pusher_radius : float
        Radius (metres) of the round pusher: contacts are where its disc first
        touches the object (:func:`comcore.geometry._disc_contacts.pusher_contacts`).
    """

    def __init__(
        self, mask: Mask, candidates, choice: PushChoice, mus, rng, name: str = "candidates",
        *, pusher_radius: float,
    ):
        if candidates is None:
            actions = sample_pushes(
                mask, choice.n_candidates, cone=choice.cone, travel=choice.travel, rng=rng
            )
        else:
            actions = check_actions(candidates, name, allow_empty=False)
        self.pusher_radius = pusher_radius
        con = pusher_contacts(mask, actions, pusher_radius)
        usable, self.skipped = usable_pushes(con, name, most=False)
        self.mask = mask
        self.actions = np.array(actions, dtype=float)
        self.actions.setflags(write=False)
        self.lines = push_force_lines(con, actions, mus)
        self.available = usable.copy()
        self._centroid = np.asarray(mask.centroid, dtype=float)
        self._in_view = self._inside_image(self.actions)

    def __len__(self) -> int:
        return len(self.actions)

    def made(self, index: int) -> None:
        """Mark a candidate made: neither it nor an identical candidate is offered again."""
        self.available &= ~np.all(self.actions == self.actions[index], axis=1)

    def in_pose(self, pose: Motion, index=None) -> np.ndarray:
        """The candidates (or those at ``index``) in the camera frame at ``pose``."""
        acts = self.actions if index is None else self.actions[index]
        return camera_from_object(acts, pose, self._centroid)

    def _inside_image(self, actions) -> np.ndarray:
        h, w = self.mask.shape
        x, y = actions[:, 0::2], actions[:, 1::2]
        inside = (x >= -0.5) & (x <= w - 0.5) & (y >= -0.5) & (y <= h - 0.5)
        return inside.all(axis=1)

    def offerable(self, pose: Motion, mask_now: Mask | None) -> np.ndarray:
        """Candidates not yet made that can be pushed on the object at ``pose``.

        ``mask_now`` is the object as seen now (an observed mask, or the first
        mask moved to ``pose``; None when it left the image). A candidate is
        offered when, mapped through the pose, it starts and ends inside the
        image, starts outside the object and its pusher touches it.
        """
        ok = self.available.copy()
        if mask_now is None:
            return np.zeros_like(ok)
        if pose == Motion.identity() and mask_now is self.mask:
            return ok & self._in_view  # every candidate hits the first mask
        idx = np.flatnonzero(ok)
        if len(idx):
            moved = self.in_pose(pose, idx)
            con = pusher_contacts(mask_now, moved, self.pusher_radius)
            ok[idx] = self._inside_image(moved) & con.hit & ~con.starts_inside
        return ok

    def choose(self, post: GridPosterior, offered, scoring, selection: str):
        """The most informative offered candidate: ``(index, gain_bits)``, or ``(None, None)``.

        ``(None, None)`` when no candidate is offered. ``scoring`` is the
        session's :class:`comcore.active._likelihood.Scoring` (the friction values,
        the flip probability, the force line's blur and, for ``selection``
        ``"model"``, the models and their error scales).
        """
        idx = np.flatnonzero(offered)
        if len(idx) == 0:
            return None, None
        if selection == "model":
            noise = scoring.model_noise
            gains = model_gains(
                scoring.models, self.mask, post, self.actions[idx], self.lines[idx], noise
            ) / math.log(2)
        else:
            gains = sense_information(
                post.pixels, post.sense_weights, self.lines[idx], scoring.flip_prob,
                scoring.line_scale_px,
            )
        best = first_best(gains)
        return int(idx[best]), float(gains[best])


#: Gains (bits) within this of the best are a tie, broken by the candidate's order: a
#: symmetric object offers candidates whose gains differ only by rounding, which differs
#: between CPUs (numpy's SIMD paths), and the session must choose the same push on every one.
TIE_BITS = 1e-12


def first_best(gains) -> int:
    """Index of the first gain within :data:`TIE_BITS` of the largest.

    Examples
    --------
    >>> first_best([0.5, 1.0, 1.0 + 1e-15, 0.9])  # 1.0 and 1.0 + 1e-15: a tie
    1
    """
    gains = np.asarray(gains, dtype=float)
    return int(np.flatnonzero(gains >= gains.max() - TIE_BITS)[0])


def binary_entropy(q):
    """Entropy in bits of Bernoulli(q), elementwise; ``q`` must lie in (0, 1)."""
    q = np.asarray(q, dtype=float)
    return -(q * np.log2(q) + (1 - q) * np.log2(1 - q))


def _tanh_into(out, tmp, x, y, lines, scale: float):
    """``out = 2 side_probability(distance) - 1`` for lines (n, 3), float32, in place.

    ``x`` and ``y`` are pixel columns of shape (p, 1); ``tmp`` is scratch space
    of ``out``'s shape. Broadcasting, not a matrix product: with an inner
    dimension of 3 BLAS gains nothing, and its threads are slow to wake on a
    busy machine.
    """
    scaled = lines * np.float32(0.5 / scale)
    np.multiply(x, scaled[:, 0], out=out)
    np.multiply(y, scaled[:, 1], out=tmp)
    tmp += scaled[:, 2]
    out += tmp
    return np.tanh(out, out=out)


def _coarse(pixels, weights):
    """Hypotheses with posterior mass, gathered into square blocks when there are many.

    Pixels below ``PRUNE_MASS`` of the largest mass are dropped. Above
    ``MAX_SCORING_POINTS`` pixels, blocks of ``b x b`` pixels become one
    hypothesis at their mass-weighted mean with their summed (pixel, friction)
    mass: a choice of push does not need the grid finer than the force lines
    are sharp (``b`` <= 2 px for masks up to 10,000 pixels).
    """
    marginal = weights.sum(axis=1)
    keep = marginal > PRUNE_MASS * marginal.max()
    pts, w = pixels[keep], weights[keep]
    block = math.ceil(math.sqrt(len(pts) / MAX_SCORING_POINTS))
    if block <= 1:
        return pts, w
    cells = np.floor(pts / block).astype(np.int64)
    cells -= cells.min(axis=0)
    _, index = np.unique(cells[:, 0] * (cells[:, 1].max() + 1) + cells[:, 1], return_inverse=True)
    mass = np.bincount(index, weights=w.sum(axis=1))
    joint = np.stack([np.bincount(index, weights=w[:, j]) for j in range(w.shape[1])], axis=1)
    centre = np.stack(
        [np.bincount(index, weights=w.sum(axis=1) * pts[:, k]) for k in range(2)], axis=1
    )
    return centre / np.maximum(mass, 1e-300)[:, None], joint


def sense_information(pixels, weights, lines, flip_prob: float, scale: float = LINE_SCALE_PX):
    """Expected information (bits) about the CoM from the observed sense of each push.

    ``I(com; s) = H(s) - E_com H(s | com)`` where the sense ``s`` of a CoM
    hypothesis is its side of the force line, marginalised over the friction
    posterior of that hypothesis, and flipped with probability ``flip_prob``.

    Cost: the friction values are sorted by cone angle, so for each push the
    values whose cone contains the push direction share one force line (the
    push line) and only the narrower cones need their own edge line.

    Parameters
    ----------
    pixels : numpy.ndarray, shape (p, 2)
    weights : numpy.ndarray, shape (p, m)
        Joint posterior over (pixel, friction) with friction values in
        increasing order, summing to 1.
    lines : numpy.ndarray, shape (n, m, 3)
        From :func:`force_lines` with increasing cone angles.
    flip_prob : float

    Returns
    -------
    numpy.ndarray, shape (n,)
    """
    n_lines, n_mu = lines.shape[:2]
    points, joint = _coarse(pixels, weights)
    x = points[:, :1].astype(np.float32)
    y = points[:, 1:].astype(np.float32)
    w_pix = joint.sum(axis=1)
    cond = joint / w_pix[:, None]
    w_pix = (w_pix / w_pix.sum()).astype(np.float32)
    # Tail sums over the wider cones: tail[:, k] = sum_{j >= k} cond[:, j], tail[:, m] = 0.
    tail = np.zeros((len(x), n_mu + 1), dtype=np.float32)
    tail[:, :n_mu] = np.cumsum(cond[:, ::-1], axis=1)[:, ::-1]
    cond = cond.astype(np.float32)
    # n_edges[a]: friction values whose cone excludes push a's direction (they slide).
    differs = np.any(np.abs(lines - lines[:, -1:]) > 1e-9, axis=2)
    n_edges = differs.sum(axis=1)  # differs[a] is True for a prefix of the sorted cones
    order = np.argsort(-n_edges, kind="stable")
    lines32 = lines[order].astype(np.float32)
    n_edges = n_edges[order]
    # u = 2 P(positive sense | pixel) - 1, friction marginalised per pixel.
    u = np.empty((len(x), n_lines), dtype=np.float32)
    buf = np.empty_like(u)
    tmp = np.empty_like(u)
    _tanh_into(u, tmp, x, y, lines32[:, -1], scale)
    starts = np.flatnonzero(np.r_[True, n_edges[1:] != n_edges[:-1]])
    for lo, hi in zip(starts, np.r_[starts[1:], n_lines]):
        u[:, lo:hi] *= tail[:, n_edges[lo] : n_edges[lo] + 1]
    for j in range(n_mu):
        count = int((n_edges > j).sum())
        if count == 0:
            break
        part = _tanh_into(buf[:, :count], tmp[:, :count], x, y, lines32[:count, j], scale)
        part *= cond[:, j : j + 1]
        u[:, :count] += part
    u *= np.float32(1 - 2 * flip_prob)  # now q = (1 + u) / 2 with the flips
    total = 0.5 + 0.5 * np.einsum("p,pa->a", w_pix, u, dtype=float)
    # H((1 + u) / 2) = 1 - [(1 + u) log2(1 + u) + (1 - u) log2(1 - u)] / 2, with 0 log 0 = 0:
    # a tiny flip_prob leaves |u| = 1 in float32, and the log's argument is floored.
    tiny = np.finfo(np.float32).tiny
    np.add(u, 1, out=buf)
    np.log2(np.maximum(buf, tiny, out=tmp), out=tmp)
    buf *= tmp
    np.subtract(1, u, out=u)
    np.log2(np.maximum(u, tiny, out=tmp), out=tmp)
    u *= tmp
    buf += u
    expected = 1 - 0.5 * np.einsum("p,pa->a", w_pix, buf, dtype=float)
    gain = binary_entropy(np.clip(total, 1e-12, 1 - 1e-12)) - expected
    out = np.empty(n_lines)
    out[order] = gain
    return out


def model_information(predicted, lever, offset, weights, noise):
    """Expected information (nats) from each push's motion about weighted hypotheses.

    ``I = sum_i w_i [log p(y_i | i) - log sum_j w_j p(y_i | j)]`` with ``y_i``
    the motion hypothesis ``i`` predicts: how well the observed motion will
    tell the hypotheses apart, with the error model of
    :func:`comcore.active._motion_term.motion_terms`.

    Parameters
    ----------
    predicted : numpy.ndarray, shape (n, a, 3)
        Motions of ``a`` candidate pushes under ``n`` hypotheses.
    lever : numpy.ndarray, shape (n, a)
    offset : numpy.ndarray, shape (n, 2)
        Each hypothesis' CoM minus the mask's centroid.
    weights : numpy.ndarray, shape (n,)
        Hypothesis weights, summing to 1.
    noise : comcore.active._motion_term.ModelNoise
        The model's error scales (radians, pixels).

    Returns
    -------
    numpy.ndarray, shape (a,)
    """
    pred = np.moveaxis(predicted, 1, 0)  # (a, n, 3)
    th_scale = theta_scale(lever.T, noise.theta, noise.near_px)  # (a, n)
    # Observation i (axis 1) seen from hypothesis j (axis 2): both moved at j's CoM.
    theta_i, theta_j = pred[:, :, None, 0], pred[:, None, :, 0]
    off_j = offset[None, None, :, :]
    moved_obs = pred[:, :, None, 1:] + com_shift(theta_i, off_j)
    moved_pred = pred[:, None, :, 1:] + com_shift(theta_j, off_j)
    tr_abs, tr_rel = noise.translation_px
    tr_scale = tr_abs + tr_rel * np.hypot(moved_pred[..., 0], moved_pred[..., 1])
    log_p = student_t((theta_i - theta_j) ** 2, th_scale[:, None, :], STUDENT_DOF, 1)
    log_p += student_t(((moved_obs - moved_pred) ** 2).sum(axis=-1), tr_scale, STUDENT_DOF, 2)
    own = np.einsum("aii->ai", log_p)
    log_mix = logsumexp(log_p + np.log(weights)[None, None, :], axis=2)
    return (own - log_mix) @ weights


def particles(post: GridPosterior, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Deterministic systematic draw of ``n`` CoM pixels from the posterior.

    Returns the distinct pixel indices drawn and their weights (counts / n).
    """
    cum = np.cumsum(post.marginal)
    picks = np.searchsorted(cum, (np.arange(n) + 0.5) / n * cum[-1])
    index, counts = np.unique(np.minimum(picks, len(cum) - 1), return_counts=True)
    return index, counts / n


def model_gains(models, mask, post, actions, lines, noise):
    """Expected information (nats) about the CoM from each candidate's motion.

    The CoM hypotheses are 64 particles drawn from the posterior; the friction
    and the model are held at their most probable values, so that what is
    measured is information about the CoM, not about the friction (a push
    that only tells the friction apart is worth nothing here).

    Parameters
    ----------
    actions : numpy.ndarray, shape (a, 4)
    lines : numpy.ndarray, shape (a, m, 3)
        Force lines of the candidates for each friction value of ``post``.
    noise : comcore.active._motion_term.ModelNoise
        The model's error scales (radians, pixels): ``Scoring.model_noise``.
    """
    index, weights = particles(post, MODEL_PARTICLES)
    j = int(np.argmax(post.mu_marginal))
    k = int(np.argmax(post.model_marginal))
    pixels = post.pixels[index]
    alive = np.ones((len(pixels), 1, 1), dtype=bool)
    pred = model_predictions(models[k : k + 1], mask, actions, pixels, post.mus[j : j + 1], alive)
    lever = np.abs(force_line_distances(pixels, lines[:, j]))
    offset = pixels - np.asarray(mask.centroid)
    return model_information(pred[:, 0, 0], lever, offset, weights, noise)
