"""What an active session has seen: its pushes, its states and the evidence, as typed records.

:class:`PushLog` keeps one :class:`comcore.PushRecord` per reported push and one
:class:`SessionState` per posterior (the prior first), and sums each
hypothesis' excess surprise: how much more the pushes surprise it than its own
motions would (:func:`comcore.active._likelihood.push_evidence`). The best
hypothesis' sum says whether any (CoM, friction, model) explains the data
(:attr:`SessionState.consistent`). :meth:`PushLog.estimate` turns the log and
the posterior into the :class:`comcore.Estimate` the user gets.
"""

from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import numpy as np

from .._mask import Mask
from .._status import SessionError, Status
from .._types import Action, Estimate, Motion, PosteriorDetails, PushRecord
from ._grid import GridPosterior
from ._likelihood import consistency_threshold

__all__ = ["PushLog", "PushLoop", "SessionState", "credible_level"]


class SessionState(NamedTuple):
    """The posterior after a push (or the prior): one entry of an estimate's ``history``."""

    com: tuple[float, float]
    """Posterior mean of the CoM, pixels of the first mask."""
    entropy_bits: float
    """Entropy of the CoM-pixel posterior."""
    credible_radius_px: float
    """Equivalent-circle radius of the credible region, pixels."""
    log_evidence: float
    """Log marginal likelihood of the motions so far (nats)."""
    excess_nats: float
    """The best hypothesis' excess surprise so far (0 before any evidence)."""
    n_pushes: int = 0
    """Pushes made so far (misses included, failed pushes not)."""
    n_evidence: int = 0
    """Pushes so far that carried evidence."""
    expected_gain_bits: float | None = None
    """Expected information (bits) of the push chosen next (None: none chosen)."""
    contradiction: str | None = None
    """Why the pushes so far contradict themselves whatever the CoM (the first push whose
    pusher ends inside the object as its motion moved it, and how deep:
    :mod:`comcore.active._overlap`), or None."""

    @property
    def consistent(self) -> bool:
        """False on a :attr:`contradiction` or an excess above ``10 + 6 sqrt(n)`` nats."""
        if self.contradiction is not None:
            return False
        n = self.n_evidence
        return n == 0 or self.excess_nats <= consistency_threshold(n)


class PushLog:
    """Records, states and evidence of a session or an offline posterior (internal, mutable)."""

    def __init__(self, post: GridPosterior, credible: float, blur_px: float = 0.0):
        self.credible = credible
        self.blur_px = blur_px  # Likelihood.systematic_error, pixels
        self.records: list[PushRecord] = []
        self.history: list[SessionState] = []
        self.excess = np.zeros(post.log_w.shape)
        self.log_evidence = 0.0
        self.contradiction: str | None = None  # SessionState.contradiction
        self._state(post)

    def _state(self, post: GridPosterior) -> None:
        _, area = post.credible(self.credible, self.blur_px)
        self.history.append(
            SessionState(
                com=tuple(float(v) for v in post.mean()),
                entropy_bits=post.entropy_bits(),
                credible_radius_px=math.sqrt(area / math.pi),
                log_evidence=self.log_evidence,
                excess_nats=self.excess_nats,
                n_pushes=len(self.executed),
                n_evidence=self.n_evidence,
                contradiction=self.contradiction,
            )
        )

    def add(
        self, record: PushRecord, post: GridPosterior, loglik=None, excess=None, overlap=None
    ) -> None:
        """Add a push's record; with evidence, multiply its likelihood into ``post``.

        ``overlap``: the push's :class:`comcore.active._overlap.PusherOverlap` (None: none),
        kept as the log's contradiction if it is the first.
        """
        if overlap is not None and self.contradiction is None:
            self.contradiction = overlap.message(len(self.records))
        if loglik is not None:
            evidence = post.update(loglik.tempered, loglik.full)
            record = dataclasses.replace(record, log_evidence=evidence)
            self.excess = self.excess + excess
            self.log_evidence += evidence
        self.records.append(record)
        self._state(post)

    def set_gain(self, gain: float | None) -> None:
        """Note the expected gain of the push chosen next in the latest state."""
        self.history[-1] = self.history[-1]._replace(expected_gain_bits=gain)

    @property
    def state(self) -> SessionState:
        """The latest state."""
        return self.history[-1]

    @property
    def executed(self) -> list[PushRecord]:
        """Records of the pushes that were executed (evidence or miss)."""
        return [r for r in self.records if r.outcome != "failed"]

    @property
    def n_evidence(self) -> int:
        """Number of pushes that carried evidence."""
        return sum(r.outcome == "evidence" for r in self.records)

    @property
    def excess_nats(self) -> float:
        """The best hypothesis' summed excess surprise (nats; 0 before any evidence)."""
        return float(self.excess.min()) if self.n_evidence else 0.0

    def estimate(
        self, mask: Mask, post: GridPosterior, used, status, marginal=None, skipped=(), **details
    ) -> Estimate:
        """The :class:`Estimate` of the posterior: mean, covariance, credible region, records.

        The region is read from :meth:`GridPosterior.region_weights`: the
        posterior's marginal, or ``marginal`` (p,) where given (a bagged
        posterior's, :mod:`comcore.active._posterior`; the covariance is then its spread
        about the posterior's mean), blurred by the systematic error.
        ``details`` (``senses``, ``bootstrap``, ``pose``) go to the estimate's
        :class:`comcore.active.PosteriorDetails` with the posterior's own.
        """
        weights = post.region_weights(self.blur_px, marginal)
        region_idx, area = post.credible(self.credible, marginal=weights)
        rows, cols = post.pixels[:, 1].astype(int), post.pixels[:, 0].astype(int)
        region = np.zeros(mask.shape, dtype=bool)
        region[rows[region_idx], cols[region_idx]] = True
        image, region_image = np.zeros(mask.shape), np.zeros(mask.shape)
        np.add.at(image, (rows, cols), post.marginal)
        np.add.at(region_image, (rows, cols), weights)
        com = tuple(float(v) for v in post.mean())
        return Estimate(
            com=com,
            com_m=mask.to_metres(com),
            region=region,
            used=tuple(used),
            status=status,
            covariance=post.covariance(marginal),
            pushes=tuple(self.records),
            skipped=skipped,
            posterior=PosteriorDetails(
                image=image,
                region_image=region_image,
                credible_radius_px=math.sqrt(area / math.pi),
                mu_grid=post.mus.copy(),
                mu_posterior=post.mu_marginal,
                model_posterior=post.model_marginal,
                scale_posterior=post.scale_marginal,
                model_weight_posterior=post.temper_weights,
                log_evidence=self.log_evidence,
                excess_nats=self.excess_nats,
                history=tuple(self.history),
                **details,
            ),
        )



def credible_level(estimate: Estimate, point) -> float:
    """The smallest credible level whose region holds ``point``: how surprising the truth is.

    The mass of the pixels more probable than the pixel under ``point``
    ``(x, y)`` (the highest-posterior-density rank) in what the credible
    region was read from (``posterior.region_image``: the posterior,
    blurred by a systematic error or bagged where the estimator did so, so
    that a point inside the 90 % region is below 0.9). For an honest
    posterior it is uniform on [0, 1] over many runs: the share of runs below
    0.9 is the coverage of the 90 % region, and its quantiles say how over- or
    under-confident the posterior is at every level. 1.0 for a point outside
    the image.

    Parameters
    ----------
    estimate : Estimate
        An active estimator's (its ``posterior`` holds the posterior).
    point : array_like, shape (2,)

    Raises
    ------
    ValueError
        If the estimate carries no posterior.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> actions = [(0, 13, 30, 13), (13, 0, 13, 30)]
    >>> est = comcore.estimate_posterior(mask, actions, [(0.2, 3, 0), (-0.2, 0, 3)], model=None)
    >>> comcore.credible_level(est, (8.0, 8.0)) < 0.5 < comcore.credible_level(est, (20.0, 20.0))
    True
    """
    if estimate.posterior is None:
        raise ValueError("estimate must carry a posterior (an active estimator's Estimate)")
    post = estimate.posterior.region_image
    col, row = (round(float(v)) for v in np.asarray(point, dtype=float).reshape(2))
    h, w = post.shape
    if not (0 <= row < h and 0 <= col < w):
        return 1.0
    return float(post[post > post[row, col]].sum())


class PushLoop:
    """The steps a session's push loop shares: ``next_push``, ``done``, ``status``, ``pose``.

    Shared by :class:`comcore.ActiveSession` and :class:`comcore.GoalSession`, which set
    ``_final`` (the stop's :class:`comcore.Status`, ``None`` while running),
    ``_handed_out`` (a push handed out and not yet observed), ``_pose`` and ``_log``
    (a :class:`PushLog`), and say which push they planned (``_planned_push``).
    """

    _final: Status | None
    _handed_out: bool
    _pose: Motion
    _log: PushLog

    @property
    def done(self) -> bool:
        """True once the session has stopped (see :attr:`status`)."""
        return self._final is not None

    @property
    def status(self) -> Status:
        """What the session waits for (a push asked, an observation), or why it stopped."""
        if self._final is not None:
            return self._final
        return Status.WAITING_OBSERVATION if self._handed_out else Status.WAITING_PUSH

    @property
    def pose(self) -> Motion:
        """The object's pose now, relative to the first mask (about its centroid)."""
        return self._pose

    @property
    def pushes(self) -> tuple[PushRecord, ...]:
        """Every push reported so far (misses and failed pushes included), in order."""
        return tuple(self._log.records)

    def next_push(self) -> Action:
        """The next push, camera pixels, on the object where it is now.

        Calling it again before ``observe`` returns the same push.

        Raises
        ------
        SessionError
            If the session is done.
        """
        if self.done:
            raise SessionError(f"the session is done (status {self._final!r}): no push to offer")
        self._handed_out = True
        return self._planned_push()

    def _planned_push(self) -> Action:
        """The push the session planned, in the camera frame now."""
        raise NotImplementedError

    def _check_waiting(self) -> None:
        """Refuse an observation when no push handed out waits for one."""
        if self.done or not self._handed_out:
            what = f"the session is done (status {self._final!r})" if self.done else "no push"
            raise SessionError(f"observe() called but {what} is waiting: call next_push() first")
