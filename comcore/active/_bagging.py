"""The bagged posterior of a recording: its region when the pushes disagree.

A motion model that errs on a real object errs alike on pushes made alike, and
the posterior of many such pushes grows sure of a CoM their errors moved.
:func:`comcore.estimate_posterior` therefore reads its credible region (its
radius, covariance and :func:`comcore.credible_level`) from the *bagged*
posterior (BayesBag: Bühlmann 2014; Huggins and Miller, "Reproducible model
selection using bagged posteriors", Bayesian Analysis 2023): the average of the
posteriors of ``bootstrap`` resamplings of the pushes. Each resampling is a
Bayesian bootstrap (Rubin 1981): the pushes' log-likelihoods weighted by
``n`` Dirichlet(1, ..., 1) weights, so a push counts 0 to a few times. Where the
pushes agree the bagged posterior is about the posterior (at most about twice
its variance, where the pushes scatter as much as the likelihood says); where
some pushes pull the CoM one way and others another, it spreads over both. It
widens by what the data show, with no constant to tune (docs/explanation/calibration.md, on
the MIT push dataset).

The point estimate stays the posterior's mean: the bagged mean was further from
the true CoM on both the real pushes and their simulated twins.

Only the region changes. Each resampling keeps the posterior's choices: the
hypotheses it pruned stay pruned and its learned powers on the model
(``model_weight``) keep the weights they earned on all the pushes.
"""

from __future__ import annotations

import numpy as np

from ._grid import GridPosterior

__all__ = ["MAX_BAG_FLOATS", "MAX_KEPT_FLOATS", "RECORDED_BOOTSTRAP", "PushLikelihoods"]

#: Bayesian-bootstrap resamplings :func:`comcore.estimate_posterior` averages by default:
#: enough for the region to change little with the seed (docs/how-to/recordings.md;
#: benchmarks/timing/bench_bagging.py times them).
RECORDED_BOOTSTRAP = 200
#: Floats one block of resamplings may hold at once (resamplings x tempers x hypotheses).
MAX_BAG_FLOATS = 4_000_000
#: Most log-likelihoods kept for the resamplings (pushes x tempers x hypotheses, 400 MB): 40
#: pushes over a 15 cm object at 1 mm/px keep 16 million before any is pruned.
MAX_KEPT_FLOATS = 50_000_000


class PushLikelihoods:
    """Each evidence push's tempered log-likelihood over a posterior's live hypotheses.

    Built on the posterior before any push (its log prior is kept); :meth:`add`
    each push's ``Evidence.tempered`` (n_tempers, p, m, k) as it is multiplied
    in. Hypotheses the posterior prunes (a ``-inf`` log-likelihood) are dropped
    from every row, so memory is pushes x live hypotheses.
    """

    def __init__(self, post: GridPosterior, n_pushes: int):
        """Refuse (naming ``bootstrap``) to keep over :data:`MAX_KEPT_FLOATS` for ``n_pushes``."""
        kept = n_pushes * post.n_tempers * post.log_w.size
        if kept > MAX_KEPT_FLOATS:
            raise ValueError(
                f"bootstrap would keep {kept:,} log-likelihoods ({n_pushes} pushes over "
                f"{post.log_w.size:,} hypotheses, {8 * kept / 1e9:.1f} GB): pass bootstrap=0, "
                "fewer pushes or a coarser mask resolution"
            )
        self.shape = post.log_w.shape  # (p, m, k)
        self.live = np.arange(post.log_w.size)
        self.log_prior = post.log_w.reshape(-1).copy()
        self.rows: list[np.ndarray] = []

    def __len__(self) -> int:
        return len(self.rows)

    def add(self, tempered) -> None:
        """Keep one push's log-likelihood, shape (n_tempers, p, m, k)."""
        loglik = np.asarray(tempered, dtype=float)
        flat = loglik.reshape(loglik.shape[0], -1)[:, self.live]
        alive = np.isfinite(flat).all(axis=0)
        if not alive.all():
            self.live = self.live[alive]
            self.rows = [row[:, alive] for row in self.rows]
            flat = flat[:, alive]
        self.rows.append(flat)

    def bagged_marginal(self, temper_weights, draws: int, rng: np.random.Generator) -> np.ndarray:
        """The CoM-pixel marginal averaged over ``draws`` Bayesian-bootstrap resamplings, (p,).

        ``temper_weights`` (n_tempers,) mix each resampling's tempered posteriors
        (the posterior's own weights). With fewer than two pushes every
        resampling is the posterior itself.
        """
        stack = np.stack(self.rows)  # (n, T, h)
        n, n_tempers, h = stack.shape
        weights = rng.standard_exponential((draws, n))
        weights *= n / weights.sum(axis=1, keepdims=True)  # Dirichlet(1, ..., 1) x n
        log_prior = self.log_prior[self.live]
        temper_w = np.asarray(temper_weights, dtype=float)
        per_pixel = int(np.prod(self.shape[1:]))
        joint = np.zeros(h)
        block = max(1, MAX_BAG_FLOATS // max(n_tempers * h, 1))
        flat = stack.reshape(n, -1)
        for first in range(0, draws, block):
            w = weights[first : first + block]
            post = (w @ flat).reshape(len(w), n_tempers, h) + log_prior
            post -= post.max(axis=2, keepdims=True)
            np.exp(post, out=post)
            post /= post.sum(axis=2, keepdims=True)  # each resampling's tempered posteriors
            joint += temper_w @ post.sum(axis=0)
        marginal = np.bincount(self.live // per_pixel, weights=joint, minlength=self.shape[0])
        return marginal / marginal.sum()
