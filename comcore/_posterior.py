"""The grid posterior of :func:`comcore.estimate_active`: CoM pixels x contact friction.

The state is a joint belief over the CoM (a grid of candidate pixels) and the
contact friction ``mu`` (a grid of cone half-angles). Friction is one value
for the whole experiment, so it is kept jointly with the CoM and marginalised
only when the CoM is reported, never assumed.

Force lines
-----------
Mason's Voting Theorem reduces to one line per push and ``mu``. The three rays
all leave the contact point, so each vote depends only on the direction from
the contact to the CoM, and the majority of three monotone votes is the vote
of the median ray: the push direction clipped to the friction cone, i.e. the
direction of the contact force. The sense of rotation is the side of that
force line the CoM lies on (tested against :func:`comcore.vt.rotation_sense`).
The signed distance of a pixel to the line is linear in the pixel, so all
pushes x frictions x pixels are one matrix product.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import logsumexp

from ._conventions import ccw_cross, rotate_vectors

__all__ = [
    "GridPosterior",
    "binary_entropy",
    "force_lines",
    "line_distances",
    "push_log_likelihood",
    "sense_information",
    "side_probability",
]

#: Scale (pixels) of the soft edge of a force line at the default 2.5 mm/px and
#: an exact pusher (the estimators derive it from metres: ``LINE_BLUR_M`` and
#: ``pusher_error`` in :mod:`comcore._active_setup`). The Voting Theorem's sense
#: is taken to be wrong for a CoM at distance d from the line with probability
#: ``1 / (1 + exp(d / scale))`` (plus ``flip_prob``): pixel outlines, the
#: smoothed normal, the pusher's radius and the object turning during the push
#: blur the line. Against the simulator (docs/active.md) the sense is wrong
#: 15 % of the time at 1-2 px, 10 % at 2-3 px, 5 % at 3-5 px, 3 % at 5-8 px.
LINE_SCALE_PX = 1.2
#: Above this many pixels, hypotheses are gathered into blocks to score candidates.
MAX_SCORING_POINTS = 2500
#: Posterior mass below which pixels are skipped when scoring candidates.
PRUNE_MASS = 1e-7


def force_lines(contact, normal, direction, alphas) -> np.ndarray:
    """Coefficients ``(a, b, k)`` of each push's force line for each cone half-angle.

    The signed distance of a point ``p`` is ``a p_x + b p_y + k``, positive on
    the counter-clockwise side (a CoM there turns the object counter-clockwise).

    Parameters
    ----------
    contact, normal, direction : numpy.ndarray, shape (n, 2)
        Contact points, unit inward normals and unit push directions.
    alphas : numpy.ndarray, shape (m,)
        Friction cone half-angles ``atan(mu)``.

    Returns
    -------
    numpy.ndarray, shape (n, m, 3)

    Examples
    --------
    A push to the right along the normal at (0, 5): points above it (smaller
    row) are on its counter-clockwise side.

    >>> lines = force_lines(np.array([[0.0, 5.0]]), np.array([[1.0, 0.0]]),
    ...                     np.array([[1.0, 0.0]]), np.array([0.3]))
    >>> line_distances(np.array([[5.0, 3.0], [5.0, 7.0]]), lines)[:, 0, 0].tolist()
    [2.0, -2.0]
    """
    beta = np.arctan2(ccw_cross(normal, direction), np.einsum("ij,ij->i", normal, direction))
    delta = np.clip(beta[:, None], -alphas[None, :], alphas[None, :])  # (n, m)
    n_b = np.broadcast_to(normal[:, None, :], (*delta.shape, 2))
    force = rotate_vectors(n_b, delta)  # (n, m, 2)
    a, b = force[..., 1], -force[..., 0]
    k = -(a * contact[:, None, 0] + b * contact[:, None, 1])
    return np.stack([a, b, k], axis=-1)


def line_distances(points, lines) -> np.ndarray:
    """Signed distances, shape (n_points, *lines.shape[:-1])."""
    pts = np.asarray(points, dtype=lines.dtype)
    flat = lines.reshape(-1, 3)
    out = pts @ flat[:, :2].T + flat[:, 2]
    return out.reshape(len(pts), *lines.shape[:-1])


def side_probability(distance, scale: float = LINE_SCALE_PX):
    """Probability of the positive sense at a signed distance from the force line.

    The logistic ``1 / (1 + exp(-d / scale)) = 0.5 + 0.5 tanh(d / (2 scale))``.

    Examples
    --------
    >>> side_probability(np.array([-100.0, 0.0, 1.2]), 1.2).round(3)
    array([0.   , 0.5  , 0.731])
    """
    return 0.5 + 0.5 * np.tanh(np.asarray(distance, dtype=float) / (2 * scale))


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


class GridPosterior:
    """Joint log-posterior over CoM pixels, friction values and models (internal, mutable).

    ``log_w`` has shape (p, m, k): pixel, friction value, and motion model x
    model-error scale factor (``k = n_models * n_scales``, model-major; ``k = 1``
    without a model).

    With ``n_tempers > 1`` it is a mixture of ``n_tempers`` posteriors, each of
    which raised the motion model's likelihood to its own power (the
    *learned tempering* of :func:`comcore.estimate_active`'s ``model_weight``),
    weighted by how well each predicted every push before that push was seen:
    the weight of member ``e`` is ``exp(S_e) / sum_f exp(S_f)`` with
    ``S_e = sum_i log sum_h post_e,i-1(h) p(y_i | h)`` the log-probability its
    posterior before each push gave that push's motion under the untempered
    likelihood (Grünwald's SafeBayes, with the posterior predictive as the
    loss: a power that leaves the posterior too narrow for the model's errors
    predicts the next push badly, one too wide predicts it vaguely).
    ``log_w`` is the mixture.
    """

    def __init__(
        self, pixels, prior_weights, mus, n_models: int = 1, n_scales: int = 1, n_tempers: int = 1
    ):
        self.pixels = np.asarray(pixels, dtype=float)
        self.mus = np.asarray(mus, dtype=float)
        self.n_models, self.n_scales = int(n_models), int(n_scales)
        log_prior = np.log(np.asarray(prior_weights, dtype=float))
        shape = (len(self.pixels), len(self.mus), self.n_models * self.n_scales)
        self.log_w = np.broadcast_to(log_prior[:, None, None], shape).copy()
        self._normalise()
        self.n_tempers = int(n_tempers)
        #: Each temper's log predictive score S_e (nats) so far.
        self.temper_scores = np.zeros(self.n_tempers)
        self._members = np.stack([self.log_w] * self.n_tempers)  # (n_tempers, p, m, k)

    def _normalise(self) -> float:
        top = self.log_w.max()
        self.log_w -= top
        total = np.log(np.exp(self.log_w).sum())
        self.log_w -= total
        return float(top + total)

    @property
    def temper_weights(self) -> np.ndarray:
        """Weight of each temper in the mixture, shape (n_tempers,), summing to 1."""
        z = self.temper_scores - self.temper_scores.max()
        w = np.exp(z)
        return w / w.sum()

    def _member_predictive(self, full) -> np.ndarray:
        """Each member's log-probability of an observation of log-likelihood ``full``."""
        return logsumexp(self._members + full, axis=(1, 2, 3))

    def predictive(self, full) -> float:
        """Log-probability the posterior gave an observation of log-likelihood ``full``."""
        return float(logsumexp(self._member_predictive(full), b=self.temper_weights))

    def update(self, log_likelihood, full=None) -> float:
        """Multiply in a likelihood given as logs, broadcast to (p, m, k).

        With tempers, ``log_likelihood`` has shape (n_tempers, p, m, k), one
        tempered likelihood per member, and ``full`` (p, m, k) is the
        untempered one that scores them (without tempers, ``full`` defaults
        to ``log_likelihood``). Returns the log-probability the posterior
        before gave the observation under ``full``: its log marginal
        likelihood.
        """
        loglik = np.asarray(log_likelihood, dtype=float)
        if loglik.ndim < 4:
            loglik = loglik[None]
        if full is None:
            if self.n_tempers > 1:
                raise ValueError("a tempered posterior needs the untempered likelihood (full)")
            full = loglik[0]
        per = self._member_predictive(full)
        evidence = float(logsumexp(per, b=self.temper_weights))
        self.temper_scores = self.temper_scores + per
        members = self._members + loglik
        self._members = members - logsumexp(members, axis=(1, 2, 3), keepdims=True)
        weights = self.temper_weights[:, None, None, None]
        self.log_w = logsumexp(self._members, axis=0, b=np.broadcast_to(weights, members.shape))
        self._normalise()
        return evidence

    @property
    def weights(self) -> np.ndarray:
        """Joint posterior (p, m, k), summing to 1."""
        return np.exp(self.log_w)

    @property
    def sense_weights(self) -> np.ndarray:
        """Posterior of (pixel, friction), shape (p, m): what the Voting Theorem sees."""
        return self.weights.sum(axis=2)

    @property
    def marginal(self) -> np.ndarray:
        """Posterior of the CoM pixel, shape (p,)."""
        return self.weights.sum(axis=(1, 2))

    @property
    def mu_marginal(self) -> np.ndarray:
        """Posterior of the friction values, shape (m,)."""
        return self.weights.sum(axis=(0, 2))

    @property
    def model_marginal(self) -> np.ndarray:
        """Posterior of the models, shape (n_models,)."""
        return self.weights.sum(axis=(0, 1)).reshape(self.n_models, self.n_scales).sum(axis=1)

    @property
    def scale_marginal(self) -> np.ndarray:
        """Posterior of the model-error scale factors, shape (n_scales,)."""
        return self.weights.sum(axis=(0, 1)).reshape(self.n_models, self.n_scales).sum(axis=0)

    def mean(self) -> np.ndarray:
        """Posterior mean of the CoM (x, y) in pixels."""
        return self.marginal @ self.pixels

    def covariance(self) -> np.ndarray:
        """Posterior covariance (px^2), plus the 1/12 px^2 spread within a pixel."""
        w = self.marginal
        centred = self.pixels - w @ self.pixels
        return (centred * w[:, None]).T @ centred + np.eye(2) / 12.0

    def entropy_bits(self) -> float:
        """Entropy of the CoM-pixel posterior in bits."""
        w = self.marginal
        w = w[w > 0]
        return float(-(w * np.log2(w)).sum())

    def credible(self, level: float) -> tuple[np.ndarray, float]:
        """Highest-posterior pixels holding ``level`` of the mass, and their area (px^2).

        The area counts the last pixel in proportion to the mass it must
        contribute, so it varies smoothly as the posterior sharpens.
        """
        w = self.marginal
        order = np.argsort(-w, kind="stable")
        cum = np.cumsum(w[order])
        k = min(int(np.searchsorted(cum, level * cum[-1])), len(w) - 1)
        before = cum[k - 1] if k > 0 else 0.0
        fraction = (level * cum[-1] - before) / w[order[k]] if w[order[k]] > 0 else 1.0
        chosen = np.zeros(len(w), dtype=bool)
        chosen[order[: k + 1]] = True
        return chosen, float(k + min(max(fraction, 0.0), 1.0))


def push_log_likelihood(
    distances,
    motion,
    flip_prob: float,
    theta_tol: float,
    model_term=None,
    flipped_term=None,
    scale: float = LINE_SCALE_PX,
):
    """Log-likelihood of one observed push over the grid, shape (p, m, 1) or (p, m, k).

    With probability ``1 - flip_prob`` the observed sense is the true one; with
    ``flip_prob`` it is flipped (and then the unflipped rotation is what the
    motion model must explain). The Voting Theorem term is the soft side of
    the force line (:func:`side_probability`); a rotation within ``theta_tol``
    carries no sense information.

    Parameters
    ----------
    distances : numpy.ndarray, shape (p, m, 1)
        Signed distances of the grid pixels to the push's force lines.
    motion : numpy.ndarray, shape (3,)
    flip_prob, theta_tol : float
    model_term, flipped_term : numpy.ndarray, shape (p, m, k), optional
        :func:`motion_log_likelihood` of the motion as observed and with its
        rotation negated (both or neither).
    scale : float, optional
        Logistic scale (pixels) of the force line's soft edge.
    """
    theta = float(motion[0])
    sense = 0 if abs(theta) <= theta_tol else (1 if theta > 0 else -1)
    floor = 1e-300
    if sense == 0:
        log_same = log_flip = np.zeros_like(distances)
    else:
        log_same = np.log(np.maximum(side_probability(sense * distances, scale), floor))
        log_flip = np.log(np.maximum(side_probability(-sense * distances, scale), floor))
    if model_term is not None:
        log_same = log_same + model_term
        log_flip = log_flip + flipped_term
    return np.logaddexp(np.log1p(-flip_prob) + log_same, np.log(flip_prob) + log_flip)
