"""The grid posterior of the active estimator: CoM pixels x friction x model.

The state is a joint belief over the CoM (a grid of candidate pixels), the
contact friction ``mu`` (a grid of cone half-angles) and the motion model (with
its error-scale factor). Friction is one value for the whole experiment, so it
is kept jointly with the CoM and marginalised only when the CoM is reported,
never assumed. What multiplies into it is :mod:`comcore.active._likelihood`'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage, sparse, special

from .._mask import Mask
from ..conventions import pixel_centres

__all__ = [
    "GridPosterior",
    "Lattice",
    "lattice_stride",
    "model_lattice",
    "prior_grid",
]


# scipy.special.logsumexp's numbers without its second pass (the grid's hot path):
# the shifted sum's floating-point operations in scipy's order, so the same bits
# (tests/active/test_logsumexp.py compares them); non-finite results and other dtypes go to scipy.
def logsumexp(a, axis=None, b=None, keepdims: bool = False):
    """``scipy.special.logsumexp(a, axis, b, keepdims)`` for real float64 arrays.

    The largest term is taken out of the sum and added back through ``log1p``, as
    scipy does; where a result is not finite (all weights zero, an infinite or NaN
    term) scipy computes it instead.

    Examples
    --------
    >>> x = np.log([[1.0, 2.0], [3.0, 4.0]])
    >>> bool(logsumexp(x) == special.logsumexp(x))
    True
    >>> logsumexp(x, axis=1, b=[[1.0, 0.0], [1.0, 1.0]]).round(6).tolist()
    [0.0, 1.94591]
    """
    arr = np.asarray(a)
    weights = None if b is None else np.asarray(b)
    if arr.dtype != np.float64 or (weights is not None and weights.dtype != np.float64):
        return special.logsumexp(a, axis=axis, b=b, keepdims=keepdims)
    if weights is not None:
        arr, weights = np.broadcast_arrays(arr, weights)
    if arr.ndim == 0 or arr.size == 0:
        return special.logsumexp(a, axis=axis, b=b, keepdims=keepdims)
    axes = tuple(range(arr.ndim)) if axis is None else axis
    with np.errstate(divide="ignore", invalid="ignore"):
        if weights is not None:
            arr = np.where(weights == 0, -np.inf, arr)
        top = np.max(arr, axis=axes, keepdims=True)
        at_top = arr == top
        arr = np.where(at_top, -np.inf, arr)
        count = at_top.astype(np.float64) if weights is None else weights * at_top
        m = np.sum(count, axis=axes, keepdims=True, dtype=np.float64)
        terms = np.exp(arr - top) if weights is None else weights * np.exp(arr - top)
        s = np.sum(terms, axis=axes, keepdims=True, dtype=np.float64)
        s = np.where(s == 0, s, s / m)
        out = np.log1p(s) + np.log(m) + top
    if not (np.isfinite(out).all() and (m > 0).all() and (s >= -1).all()):
        return special.logsumexp(a, axis=axis, b=b, keepdims=keepdims)
    if not keepdims:
        out = np.squeeze(out, axis=axes)
    return out[()] if out.ndim == 0 else out


def prior_grid(mask: Mask, prior) -> tuple[np.ndarray, np.ndarray]:
    """Pixels with positive prior weight and their normalised weights."""
    if prior is None:
        return mask.pixels, np.full(mask.area_px, 1.0 / mask.area_px)
    try:
        weights = np.asarray(prior, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"prior must be an array_like of numbers of shape {mask.shape}") from e
    if weights.shape != mask.shape:
        raise ValueError(f"prior must have the mask's shape {mask.shape}, got {weights.shape}")
    if not np.isfinite(weights).all() or (weights < 0).any() or weights.sum() <= 0:
        raise ValueError("prior must be finite, non-negative and not all zero")
    support = weights > 0
    w = weights[support]
    return pixel_centres(support), w / w.sum()


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
        self,
        pixels,
        prior_weights,
        mus,
        *,
        n_models: int = 1,
        n_scales: int = 1,
        n_tempers: int = 1,
        mu_weights=None,
    ):
        self.pixels = np.asarray(pixels, dtype=float)
        self.mus = np.asarray(mus, dtype=float)
        self.n_models, self.n_scales = int(n_models), int(n_scales)
        log_prior = np.log(np.asarray(prior_weights, dtype=float))[:, None, None]
        if mu_weights is not None:  # a prior over the friction values too (else uniform)
            log_prior = log_prior + np.log(np.asarray(mu_weights, dtype=float))[None, :, None]
        shape = (len(self.pixels), len(self.mus), self.n_models * self.n_scales)
        self.log_w = np.broadcast_to(log_prior, shape).copy()
        self._normalise()
        self.n_tempers = int(n_tempers)
        #: Each temper's log predictive score S_e (nats) so far.
        self.temper_scores = np.zeros(self.n_tempers)
        self._members = np.stack([self.log_w] * self.n_tempers)  # (n_tempers, p, m, k)
        self._lattices: dict = {}

    def model_lattice(self, stride: int):
        """The lattice of every ``stride``-th pixel the model's terms are computed on.

        None for stride 1 (every pixel asked); kept for the session
        (:func:`comcore.active._grid.model_lattice`).
        """
        if stride not in self._lattices:
            self._lattices[stride] = model_lattice(self.pixels, stride)
        return self._lattices[stride]

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
        """Each member's log-probability of an observation of log-likelihood ``full``.

        Remembered for the last ``full`` (the same array) and members: a push's reading
        asks for it (:meth:`predictive`) before :meth:`update` multiplies the push in.
        """
        last = getattr(self, "_last_predictive", None)
        if last is not None and last[0] is full and last[1] is self._members:
            return last[2]
        per = logsumexp(self._members + full, axis=(1, 2, 3))
        self._last_predictive = (full, self._members, per)
        return per

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

    def covariance(self, weights=None) -> np.ndarray:
        """Posterior covariance (px^2), plus the 1/12 px^2 spread within a pixel.

        With ``weights`` (p,) over the same pixels (a bagged posterior's): their
        spread about the posterior's mean, the estimate.
        """
        w = self.marginal if weights is None else np.asarray(weights, dtype=float)
        centred = self.pixels - self.mean()
        return (centred * w[:, None]).T @ centred + np.eye(2) / 12.0

    def entropy_bits(self) -> float:
        """Entropy of the CoM-pixel posterior in bits."""
        w = self.marginal
        w = w[w > 0]
        return float(-(w * np.log2(w)).sum())

    def region_weights(self, blur_px: float = 0.0, marginal=None) -> np.ndarray:
        """The pixel weights a credible region is read from, shape (p,), summing to 1.

        The CoM-pixel marginal, or ``marginal`` given over the same pixels (a
        bagged posterior's, :mod:`comcore.active._posterior`); with ``blur_px`` > 0
        blurred by a Gaussian of that standard deviation (pixels) over the
        grid's pixels (mass blurred off them is dropped and the rest
        renormalised): an error on the CoM that no number of pushes averages
        away (``Likelihood.systematic_error``). Works on the grid's bounding box
        (plus four standard deviations), not a whole camera frame.
        """
        w = self.marginal if marginal is None else np.asarray(marginal, dtype=float)
        if blur_px <= 0:
            return w
        cols = np.rint(self.pixels[:, 0]).astype(np.int64)
        rows = np.rint(self.pixels[:, 1]).astype(np.int64)
        height, width = rows.max() - rows.min() + 1, cols.max() - cols.min() + 1
        radius = int(4.0 * blur_px + 0.5)  # gaussian_filter's kernel half-width at truncate=4
        if radius > DIRECT_BLUR_RADIUS and height * width * (height + width) < (
            (height + 2 * radius) * (width + 2 * radius) * 2 * (2 * radius + 1)
        ):
            blurred = _box_blur(rows - rows.min(), cols - cols.min(), w, blur_px, radius)
            return np.maximum(blurred, 0.0) / np.maximum(blurred, 0.0).sum()
        pad = math.ceil(4.0 * blur_px) + 1
        r0, c0 = rows.min() - pad, cols.min() - pad
        image = np.zeros((rows.max() - r0 + pad + 1, cols.max() - c0 + pad + 1))
        np.add.at(image, (rows - r0, cols - c0), w)
        blurred = ndimage.gaussian_filter(image, blur_px, mode="constant", truncate=4.0)
        w = np.maximum(blurred[rows - r0, cols - c0], 0.0)
        return w / w.sum()

    def credible(
        self, level: float, blur_px: float = 0.0, marginal=None
    ) -> tuple[np.ndarray, float]:
        """Highest-posterior pixels holding ``level`` of the mass, and their area (px^2).

        Read from :meth:`region_weights` (``blur_px``, ``marginal``). The area
        counts the last pixel in proportion to the mass it must contribute, so
        it varies smoothly as the posterior sharpens.
        """
        w = self.region_weights(blur_px, marginal)
        order = np.argsort(-w, kind="stable")
        cum = np.cumsum(w[order])
        k = min(int(np.searchsorted(cum, level * cum[-1])), len(w) - 1)
        before = cum[k - 1] if k > 0 else 0.0
        fraction = (level * cum[-1] - before) / w[order[k]] if w[order[k]] > 0 else 1.0
        chosen = np.zeros(len(w), dtype=bool)
        chosen[order[: k + 1]] = True
        return chosen, float(k + min(max(fraction, 0.0), 1.0))


#: Widest kernel half-width (pixels) :meth:`GridPosterior.region_weights` blurs with
#: ``scipy.ndimage.gaussian_filter``; a wider one (a camera finer than about 0.4 mm per
#: pixel for a 1.5 mm blur) is applied as two kernel matrices over the grid's box
#: (:func:`_box_blur`) where that costs less, its cost then independent of the blur's width.
DIRECT_BLUR_RADIUS = 16


def _box_blur(rows, cols, w, sigma: float, radius: int) -> np.ndarray:
    """The weights ``w`` at pixels (``rows``, ``cols``) of their box, blurred, at those pixels.

    The same Gaussian as ``gaussian_filter(..., mode="constant", truncate=4.0)``
    (half-width ``radius``, normalised over it), applied as ``K_rows @ image @
    K_cols``: the pixels outside the box hold no mass, so only the box's rows and
    columns are needed.
    """
    taps = np.arange(-radius, radius + 1, dtype=float)
    kernel = np.exp(-0.5 * (taps / sigma) ** 2)
    kernel /= kernel.sum()

    def matrix(n: int) -> np.ndarray:
        lag = np.abs(np.arange(n)[:, None] - np.arange(n)[None, :])
        return np.where(lag <= radius, kernel[np.minimum(lag, radius) + radius], 0.0)

    image = np.zeros((int(rows.max()) + 1, int(cols.max()) + 1))
    np.add.at(image, (rows, cols), w)
    blurred = matrix(image.shape[0]) @ image @ matrix(image.shape[1])
    return blurred[rows, cols]


def lattice_stride(spacing_m: float, resolution: float) -> int:
    """Pixels between lattice nodes for a spacing (metres) on a camera of ``resolution``."""
    if spacing_m <= 0:
        return 1
    return max(1, int(np.floor(spacing_m / resolution + 1e-9)))


@dataclass(frozen=True)
class Lattice:
    """Nodes (indices into the posterior's pixels) and the interpolation weights.

    ``weights`` is a sparse (p, n) matrix whose rows sum to 1: pixel ``i``'s term is
    ``weights[i] @ node_terms``.
    """

    nodes: np.ndarray
    weights: sparse.csr_matrix

    def gather_any(self, flags: np.ndarray) -> np.ndarray:
        """Per node: whether any pixel that reads it is flagged; ``flags`` (p, ...) bool."""
        flat = flags.reshape(len(flags), -1).astype(float)
        return (self.weights.T @ flat > 0).reshape(len(self.nodes), *flags.shape[1:])

    def gather_sum(self, values: np.ndarray) -> np.ndarray:
        """Per node: the sum of ``values`` (p, ...) over the pixels it stands for.

        Each pixel's value is shared among the nodes it reads by its weights, so the
        nodes' total is the pixels'.
        """
        flat = values.reshape(len(values), -1)
        return np.asarray(self.weights.T @ flat).reshape(len(self.nodes), *values.shape[1:])

    def spread(self, node_values: np.ndarray, usable: np.ndarray) -> np.ndarray:
        """Per pixel: ``node_values`` (n, ...) interpolated; nodes not ``usable`` count 0.

        A pixel is only as good as its nodes: callers ask the model about every node a
        live pixel reads (:meth:`gather_any`), so a live pixel never reads an unusable one.
        """
        vals = np.where(usable, node_values, 0.0)
        flat = vals.reshape(len(self.nodes), -1)
        n_pix = self.weights.shape[0]
        return np.asarray(self.weights @ flat).reshape(n_pix, *node_values.shape[1:])


def model_lattice(pixels: np.ndarray, stride: int) -> Lattice | None:
    """The lattice of every ``stride``-th pixel of ``pixels`` (p, 2), or None for stride 1.

    ``pixels`` are pixel centres ``(x, y)`` on the integer grid (as
    :func:`comcore.conventions.pixel_centres` gives them), the nodes those whose
    column and row are multiples of ``stride`` counted from the first pixel's.
    Hypotheses off the integer grid (none a session makes) get None: every one asked.
    """
    if stride <= 1 or len(pixels) == 0:
        return None
    offsets = pixels - pixels.min(axis=0)
    if np.abs(offsets - np.rint(offsets)).max() > 1e-9:  # not a pixel grid: every one asked
        return None
    grid = np.rint(offsets).astype(np.intp)  # (p, 2) column, row
    cell = grid // stride
    on_node = (grid % stride == 0).all(axis=1)
    # the index of the pixel on each lattice node, -1 where the node is off the object
    lookup = np.full((int(cell[:, 1].max()) + 2, int(cell[:, 0].max()) + 2), -1, dtype=np.intp)
    lookup[cell[on_node, 1], cell[on_node, 0]] = np.flatnonzero(on_node)
    frac = (grid - cell * stride) / stride  # (p, 2) in [0, 1)
    rows, cols, vals = [], [], []
    for dx, dy in ((0, 0), (1, 0), (0, 1), (1, 1)):
        w = (frac[:, 0] if dx else 1 - frac[:, 0]) * (frac[:, 1] if dy else 1 - frac[:, 1])
        found = lookup[cell[:, 1] + dy, cell[:, 0] + dx]
        use = (found >= 0) & (w > 0)
        rows.append(np.flatnonzero(use))
        cols.append(found[use])
        vals.append(w[use])
    rows, cols, vals = np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)
    total = np.bincount(rows, weights=vals, minlength=len(pixels))
    lonely = np.flatnonzero(total == 0)  # no node of its cell on the object: its own node
    rows = np.concatenate([rows, lonely])
    cols = np.concatenate([cols, lonely])
    vals = np.concatenate([vals / total[rows[: len(vals)]], np.ones(len(lonely))])
    nodes, column = np.unique(cols, return_inverse=True)
    weights = sparse.csr_matrix((vals, (rows, column)), shape=(len(pixels), len(nodes)))
    return Lattice(nodes=nodes, weights=weights)
