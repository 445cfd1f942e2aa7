"""The active estimator's posterior over recorded pushes: :func:`estimate_posterior`.

The same parts as :class:`comcore.ActiveSession` (:mod:`comcore.active._grid`,
:mod:`comcore.active._likelihood`), over pushes already made: no push is chosen and
nothing stops.

**The region.** With every push of a recording the posterior narrows to a few pixels,
while a motion model's error on a real object, shared by pushes made alike, does not
average away. So the credible region, its radius and the covariance are read from the
posterior averaged over ``bootstrap`` Bayesian-bootstrap resamplings of the pushes
(:mod:`comcore.active._posterior`), which widens where the pushes disagree; ``com`` is
the posterior's mean either way, and ``posterior.history`` holds the posterior's own
states. The status compares that region's equivalent-circle radius with
``target_radius``: ``"ok"`` means the same here as where a session stops.

**The senses.** Besides the likelihood's check that some hypothesis explains the
pushes, the observed senses of rotation are checked on their own
(:func:`comcore.active._stop.sense_check`): a recording whose senses no CoM explains,
or whose estimate most of them contradict, is ``"inconsistent"`` whatever the model.

**The units of theta.** ``theta_units="auto"`` reads radians and, with a motion model,
refuses a recording that every theta multiplied by pi/180 explains more than
:data:`comcore.active._posterior.DEGREES_NATS` nats better (:func:`scaled_gain`):
turns under 3 degrees are under pi everywhere, so the bound on theta cannot see
them. This costs a second posterior, without bagging. ``"rad"`` skips the check,
``"deg"`` converts. Records (``pushes``) are in radians and not checked.

**Frames.** Each push's frames (its pusher in ``mask``'s pixels, its view a motion
since the push began or a mask in ``mask``'s frame) are read into its record's path
and scored with its end pose (:mod:`comcore.active._path`); the record says which
frames were dropped and why. Records carry their paths already.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, NamedTuple

import numpy as np

from .._checks import check_count
from .._mask import Mask
from .._status import DEFAULT_TARGET_RADIUS, Status, region_reached
from .._types import Estimate, Motion, PushRecord
from .._validation import (
    check_actions,
    check_motions,
    check_one_object,
    check_per_push,
    check_physical,
    check_rng,
    check_turns,
)
from ..camera._pose_tracking import is_miss
from ..conventions import DEFAULT_PUSHER_RADIUS, rotation_sense
from ..geometry._disc_contacts import pusher_contacts, usable_pushes
from ..motion._predictor import register_few_shot_fit
from ..vt._voting import force_line_distances, push_force_lines
from ._grid import GridPosterior, prior_grid
from ._likelihood import (
    PushMemo,
    SenseTally,
    gyration_px,
    mu_grid,
    push_evidence,
    sense_flip_prob,
    tracking_noise,
)
from ._motion_term import KnownPushes
from ._options import DEFAULT_CREDIBLE, DEFAULT_MODEL
from ._options import RECORDED_SYSTEMATIC_ERROR as RECORDED_FLOOR
from ._overlap import pusher_overlap
from ._path import FramedPush, PushPath, check_frames, path_tracking, read_path
from ._records import PushLog
from ._session import session_setup
from ._stop import offline_status, sense_check

__all__ = [
    "DEGREES_NATS",
    "MAX_BAG_FLOATS",
    "MAX_KEPT_FLOATS",
    "RECORDED_BOOTSTRAP",
    "THETA_UNITS",
    "PushLikelihoods",
    "check_theta_units",
    "degrees_message",
    "estimate_posterior",
    "scaled_gain",
    "theta_degrees_nats",
    "theta_in_radians",
]

#: Bayesian-bootstrap resamplings :func:`comcore.estimate_posterior` averages by default:
#: enough for the region to change little with the seed (docs/how-to/recordings.md;
#: benchmarks/timing/bench_bagging.py times them).
RECORDED_BOOTSTRAP = 200
#: Floats one block of resamplings may hold at once (resamplings x tempers x hypotheses).
MAX_BAG_FLOATS = 4_000_000
#: Most log-likelihoods kept for the resamplings (pushes x tempers x hypotheses, 400 MB): 40
#: pushes over a 15 cm object at 1 mm/px keep 16 million before any is pruned.
MAX_KEPT_FLOATS = 50_000_000
#: Most Bayesian-bootstrap resamplings ``bootstrap`` may ask for (each costs a
#: multiply-add per push and live hypothesis; benchmarks/timing/bench_bagging.py times them).
MAX_BOOTSTRAP = 10_000


def estimate_posterior(
    mask: Mask,
    actions=None,
    motions=None,
    *,
    pushes=None,
    model=DEFAULT_MODEL,
    pusher_radius: float = DEFAULT_PUSHER_RADIUS,
    prior=None,
    credible: float = DEFAULT_CREDIBLE,
    likelihood=None,
    rotation_observed=None,
    residual_px=None,
    bootstrap: int = RECORDED_BOOTSTRAP,
    target_radius: float = DEFAULT_TARGET_RADIUS,
    rng=0,
    theta_units: str = "auto",
    frames=None,
) -> Estimate:
    """The active estimator's posterior over recorded pushes, without choosing any.

    The offline counterpart of :class:`comcore.ActiveSession` (the same prior,
    likelihood and result) over pushes made from the pose of ``mask``, the
    object reset before each, or over a session's records (``pushes=``). A push
    below the noise missed and carries no evidence. How the region, the senses,
    the units of theta and the frames are read: :mod:`comcore.active._posterior`.

    Parameters
    ----------
    mask : Mask
        The object before the pushes.
    actions, motions : array_like, shapes (n, 4) and (n, 3)
        The pushes in ``mask``'s pixels (each starts outside the object and
        hits it) and their observed motions ``(theta, tx, ty)`` about
        ``mask``'s centroid (radians, pixels).
    pushes : sequence of PushRecord, optional
        Instead of ``actions`` and ``motions``: an :class:`Estimate`'s records.
    model, pusher_radius, prior, credible, likelihood
        As for :class:`comcore.ActiveSession`; a ``systematic_error`` left None is
        :data:`comcore.active.RECORDED_SYSTEMATIC_ERROR`.
    rotation_observed, residual_px : sequence, shape (n,), optional
        With ``actions``, per push: False where the rotation is unknown; the
        registration's RMS outline residual (pixels; NaN or None: none).
    bootstrap : int, optional
        Bayesian-bootstrap resamplings averaged for the region (0: none).
    target_radius : float, optional
        The credible region's radius (metres) for ``"ok"``, as a
        :class:`comcore.StopRule`'s (default 6 mm); a wider region is ``"wide"``.
    rng : None, int or numpy.random.Generator, optional
        Seed of the resamplings (default 0).
    theta_units : {"auto", "rad", "deg"}, optional
        The unit of ``motions``' theta; ``"auto"``: radians, checked against degrees.
    frames : sequence, shape (n,), of sequences of PushFrame, optional
        With ``actions``, per push: its frames in ``mask``'s frame (as ``observe``'s).

    Returns
    -------
    Estimate
        As :func:`comcore.estimate_active`'s; ``used`` the pushes with evidence;
        ``status`` ``"ok"``, ``"wide"``, ``"inconsistent"`` or ``"no_evidence"``.

    Raises
    ------
    TypeError, ValueError
        On invalid arguments (each named); for theta that looks like degrees.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
    >>> motions = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)]
    >>> est = comcore.estimate_posterior(mask, actions, motions, model=None)
    >>> est.status, np.round(est.com, 1).tolist(), round(est.posterior.credible_radius_px, 1)
    ('wide', [11.1, 11.1], 9.0)
    >>> comcore.estimate_posterior(mask, actions, motions, model=None, target_radius=0.025).status
    'ok'
    """
    mask = check_one_object(mask)
    theta_units = check_theta_units(theta_units)
    if theta_units == "deg":
        if pushes is not None:
            raise ValueError("theta_units='deg' converts motions; pushes (records) are in radians")
        motions = None if motions is None else theta_in_radians(motions, "deg")
    bootstrap = _check_bootstrap(bootstrap)
    target_radius = check_physical(target_radius, "target_radius", "target_radius")
    rng = check_rng(rng)
    options = dict(model=model, pusher_radius=pusher_radius, prior=prior, credible=credible,
                   likelihood=likelihood)
    scoring, credible = session_setup(
        mask, model, pusher_radius, credible, likelihood, systematic_floor=RECORDED_FLOOR
    )
    given = _records(mask, actions, motions, pushes, rotation_observed, residual_px)
    acts = check_actions([record.action for _, record in given], "actions", allow_empty=False)
    con = pusher_contacts(mask, acts, scoring.pusher_radius)
    if frames is not None:
        given = _with_frames(mask, given, frames, theta_units, pushes, scoring, travel=con.travel)
    run = _Run(scoring, credible, prior, KnownPushes(acts) if scoring.models else None)
    log, post, kept, check, usable, skipped = _scored(mask, given, run, con, bag=bootstrap > 0)
    used = [i for (i, r), ok in zip(given, usable) if ok and r.outcome == "evidence"]
    skipped = tuple(s._replace(index=given[s.index][0]) for s in skipped)
    bagged = None  # one push is its own bag: the posterior's region
    if kept is not None and len(kept) > 1:
        bagged = kept.bagged_marginal(post.temper_weights, bootstrap, rng)
    est = log.estimate(  # its status set below, once its region's radius is known
        mask, post, used, Status.OK, marginal=bagged, skipped=skipped, senses=check,
        bootstrap=0 if bagged is None else bootstrap,
    )
    radius_px = est.posterior.credible_radius_px  # the region reported: the bagged one
    reached = region_reached(radius_px, target_radius, mask.resolution)
    est = dataclasses.replace(est, status=offline_status(log.state, check, reached=reached))
    if theta_units == "auto" and scoring.models and pushes is None:
        _refuse_degrees(mask, est, options, run)
    return est


class _Run(NamedTuple):
    """What :func:`estimate_posterior`'s posteriors share: its first and the units check's."""

    scoring: Any
    """The :class:`comcore.active._likelihood.Scoring` of its options."""
    credible: float
    """The credible mass of the region."""
    prior: Any
    """The prior as given (None: uniform over the object)."""
    known: KnownPushes | None
    """The model's predictions for every push, asked once (None without a model)."""


class _Posterior(NamedTuple):
    """The posterior over recorded pushes, before its region and status are read."""

    log: PushLog
    """The records and states."""
    post: Any
    """The :class:`comcore.active._grid.GridPosterior` after the pushes."""
    kept: PushLikelihoods | None
    """Each push's likelihood for the bagging (None: no bagging)."""
    senses: Any
    """The senses' check (:func:`comcore.active._stop.sense_check`)."""
    usable: np.ndarray
    """Per push: whether it starts outside the object and hits it."""
    skipped: tuple
    """The pushes that do not (their index among the pushes given)."""


def _scored(mask, given, run: _Run, con, *, bag: bool) -> _Posterior:
    """The posterior over the records ``given`` (``(position, record)`` pairs).

    ``con`` are the pushes' contacts; ``bag``: keep each push's likelihood for the
    bagging.
    """
    scoring = run.scoring
    acts = np.array([record.action for _, record in given], dtype=float)
    pixels, prior_weights = prior_grid(mask, run.prior)
    usable, skipped = usable_pushes(con, "actions")  # the rest kept, these reported
    lines = push_force_lines(con, acts, scoring.mus)
    post = scoring.posterior(pixels, prior_weights)
    log = PushLog(post, run.credible, scoring.systematic_px)
    kept = PushLikelihoods(post, int(sum(usable))) if bag else None
    senses = SenseTally(post.log_w.shape[:2])
    gyration = gyration_px(mask)
    for i, (_, record) in enumerate(given):
        if not usable[i]:
            continue
        if record.outcome == "miss":
            log.add(record, post)
            continue
        tracking = tracking_noise(scoring.tracking, record.residual_px, gyration)
        path = _scored_path(record, acts[i], float(con.travel[i]), scoring, mask)
        loglik, excess = push_evidence(
            post, scoring, mask, acts[i], lines[i], record.motion,
            rotation_observed=record.rotation_observed, tracking=tracking, path=path,
            memo=PushMemo(known=run.known),
        )
        log.add(record, post, loglik, excess, pusher_overlap(mask, scoring, record, gyration))
        if kept is not None:
            kept.add(loglik.tempered)
        _count_sense(senses, scoring, post.pixels, lines[i], record, tracking)
    check = sense_check(senses, _nearest_pixel(post.pixels, post.mean()))
    return _Posterior(log, post, kept, check, usable, skipped)


def _check_bootstrap(bootstrap) -> int:
    """``bootstrap`` as a count of at most :data:`MAX_BOOTSTRAP` resamplings."""
    bootstrap = check_count(bootstrap, "bootstrap")
    if bootstrap > MAX_BOOTSTRAP:
        raise ValueError(f"bootstrap must be at most {MAX_BOOTSTRAP} resamplings, got {bootstrap}")
    return bootstrap


def _scored_path(record, action, contact_travel: float, scoring, mask):
    """The :class:`PushPath` of a record that carries one (None for its end pose alone)."""
    if not record.path:
        return None
    tracking = path_tracking(record.path, scoring.tracking, mask)
    return PushPath.of(action, record.path, contact_travel, tracking)


def _refuse_degrees(mask, est, options: dict, run: _Run) -> None:
    """A ValueError when every theta times pi/180 explains the pushes much better.

    The second posterior reads the model's predictions the first asked for (``run``).
    """
    gain = scaled_gain(mask, est, options, run)
    if gain > DEGREES_NATS:
        raise ValueError(
            f"motions[:, 0]: {degrees_message(gain)}; "
            "theta_units='deg' converts them, 'rad' skips this check"
        )


def theta_degrees_nats(
    mask, actions, motions, *, model=DEFAULT_MODEL, pusher_radius: float = DEFAULT_PUSHER_RADIUS
) -> float:
    """How much better (nats) every theta multiplied by pi/180 explains the pushes.

    The log evidence of :func:`comcore.estimate_posterior`'s posterior under
    ``model`` (default: the limit-surface model with ``pusher_radius``
    metres) over the pushes with every theta times pi/180, minus that over
    the pushes as given (:func:`scaled_gain`). Above :data:`DEGREES_NATS`
    the theta column is in degrees. Two posteriors without bagging: about
    2 s each for 40 pushes.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
    >>> motions = [(1.344, 12.931, -12.832), (-1.344, -12.832, 12.931),
    ...            (-1.08, 7.821, 9.148), (1.08, 9.148, 7.821)]  # radians
    >>> theta_degrees_nats(mask, actions, motions) < 0
    True
    """
    options = {"model": model, "pusher_radius": pusher_radius}
    given = estimate_posterior(mask, actions, motions, bootstrap=0, theta_units="rad", **options)
    return scaled_gain(mask, given, options)


def scaled_gain(mask, given, options: dict, run: _Run | None = None) -> float:
    """Log evidence with every theta of ``given``'s pushes times pi/180, minus ``given``'s.

    ``given`` is :func:`comcore.estimate_posterior`'s estimate of the pushes as
    given; its records are scored again (``pushes=``, with ``options``: the
    same model, prior and likelihood) with theta converted. Each push keeps
    its outcome: one that carried evidence as given still does, so that
    both evidences score the same pushes (a push whose converted turn is below
    the noise would otherwise drop out and count as explained). With ``run``
    (``given``'s scoring and the model's predictions it asked for) the model is
    not asked again.
    """
    scaled = [
        dataclasses.replace(r, motion=Motion(r.motion[0] * math.pi / 180, *r.motion[1:]))
        for r in given.pushes
    ]
    if run is None:
        other = estimate_posterior(mask, pushes=scaled, bootstrap=0, theta_units="rad", **options)
        return float(other.posterior.log_evidence - given.posterior.log_evidence)
    records = [(i, r) for i, r in enumerate(scaled) if r.outcome != "failed"]
    acts = check_actions([r.action for _, r in records], "actions", allow_empty=False)
    con = pusher_contacts(mask, acts, run.scoring.pusher_radius)
    log = _scored(mask, records, run, con, bag=False).log
    return float(log.log_evidence - given.posterior.log_evidence)


def _count_sense(tally: SenseTally, scoring, pixels, lines, record, tracking) -> None:
    """Count the push's observed sense against every hypothesis (:class:`SenseTally`)."""
    theta = float(record.motion[0])
    if not record.rotation_observed:
        return
    sense = int(rotation_sense(theta, scoring.theta_tol))
    if sense == 0:
        return
    flip = sense_flip_prob(scoring.flip_prob, theta, tracking[0], True)
    distances = force_line_distances(pixels, lines)  # (p, m)
    tally.add(distances, sense, flip, scoring.line_scale_px)


def _with_frames(mask, given, frames, theta_units, pushes, scoring, *, travel) -> list:
    """``given`` with each push's frames read into its record's path (:func:`read_path`).

    ``travel`` (n,): each push's travel (pixels) to first contact.
    """
    if pushes is not None:
        raise TypeError("frames go with actions and motions; records (pushes) carry their paths")
    if isinstance(frames, (str, bytes, Mask)) or not hasattr(frames, "__len__"):
        raise TypeError(
            f"frames must be a sequence of one frame sequence per push, got {type(frames).__name__}"
        )
    if len(frames) != len(given):
        raise ValueError(f"frames must hold one entry per push ({len(given)}), got {len(frames)}")
    out = []
    for (i, record), push_frames, contact_travel in zip(given, frames, travel):
        if push_frames is None or len(push_frames) == 0 or record.outcome != "evidence":
            out.append((i, record))
            continue
        try:
            checked = check_frames(push_frames)
        except (TypeError, ValueError) as e:
            raise type(e)(f"frames[{i}]: {e}") from e
        if theta_units == "deg":
            checked = [
                f if isinstance(f.view, Mask) else f._replace(view=_turn_in_radians(f.view))
                for f in checked
            ]
        push = FramedPush(
            mask,
            Motion.identity(),
            record.action,
            end_pose=record.motion,
            contact_travel=float(contact_travel),
            tracking=scoring.tracking,
            pusher_px=scoring.pusher_px,
        )
        try:
            path = read_path(push, checked)
        except ValueError as e:
            raise ValueError(f"frames[{i}]: {e}") from e
        out.append((i, dataclasses.replace(record, path=path.points, dropped_frames=path.dropped)))
    return out


def _turn_in_radians(motion: Motion) -> Motion:
    return Motion(math.radians(motion.theta), motion.tx, motion.ty)


def _nearest_pixel(pixels, point) -> int:
    """Index of the grid pixel nearest ``point``."""
    return int(np.argmin(np.sum((pixels - np.asarray(point)) ** 2, axis=1)))


def _records(mask, actions, motions, pushes, rotation_observed, residual_px) -> list:
    """``(position, record)`` of the pushes to score: given, or made from the arrays.

    Failed records are skipped (their positions too); a push made from the
    arrays is a miss when its motion is below the noise.
    """
    if pushes is not None:
        if actions is not None or motions is not None:
            raise TypeError("estimate_posterior takes actions and motions, or pushes, not both")
        if rotation_observed is not None or residual_px is not None:
            raise TypeError("pushes carry rotation_observed and residual_px: do not pass them too")
        if isinstance(pushes, PushRecord) or not all(isinstance(p, PushRecord) for p in pushes):
            raise TypeError(
                "pushes must be a sequence of comcore.PushRecord (an Estimate's pushes)"
            )
        records = [(i, p) for i, p in enumerate(pushes) if p.outcome != "failed"]
        if not records:
            raise ValueError("pushes must hold at least one executed push (none failed)")
        return records
    if actions is None or motions is None:
        raise TypeError("estimate_posterior needs actions and motions (or pushes=...)")
    acts = check_actions(actions, "actions", allow_empty=False)
    moves = check_turns(check_motions(motions, n=len(acts), name="motions"))
    observed = check_per_push(rotation_observed, len(acts), "rotation_observed", True)
    residuals = check_per_push(residual_px, len(acts), "residual_px", float("nan"))
    return [
        (i, PushRecord(
            action=acts[i],
            motion=moves[i],
            outcome="miss" if is_miss(moves[i], mask.resolution) else "evidence",
            index=i,
            rotation_observed=observed[i],
            residual_px=None if math.isnan(residuals[i]) else residuals[i],
        ))
        for i in range(len(acts))
    ]




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


#: The units ``theta_units`` takes: ``auto`` (radians, checked against degrees), ``rad``
#: (radians, not checked), ``deg`` (degrees, converted).
THETA_UNITS = ("auto", "rad", "deg")
#: A recording whose log evidence under the motion model rises by more than this (nats) with
#: every theta multiplied by pi/180 is in degrees (calibrated by
#: benchmarks/calibration/theta_units.py on seed 1; its false alarms and detections on seed 0
#: are in docs/how-to/recordings.md).
DEGREES_NATS = 10.0


def check_theta_units(theta_units) -> str:
    """``theta_units`` if it is one of :data:`THETA_UNITS`, else a ValueError.

    Examples
    --------
    >>> check_theta_units("deg")
    'deg'
    >>> check_theta_units("degrees")
    Traceback (most recent call last):
    ...
    ValueError: theta_units must be one of ('auto', 'rad', 'deg'), got 'degrees'
    """
    if not isinstance(theta_units, str) or theta_units not in THETA_UNITS:
        raise ValueError(f"theta_units must be one of {THETA_UNITS}, got {theta_units!r}")
    return theta_units


def theta_in_radians(motions, theta_units: str) -> np.ndarray:
    """``motions`` (n, 3) with theta in radians: multiplied by pi/180 for ``"deg"``.

    Examples
    --------
    >>> theta_in_radians([[90.0, 1.0, 2.0]], "deg").round(4).tolist()
    [[1.5708, 1.0, 2.0]]
    """
    motions = np.array(motions, dtype=float)
    if check_theta_units(theta_units) == "deg" and motions.ndim == 2 and motions.shape[1:] == (3,):
        motions[:, 0] *= math.pi / 180
    return motions


def degrees_message(gain: float, column: str = "the column") -> str:
    """What to say of pushes that every theta times pi/180 explains ``gain`` nats better.

    The data and the motion model disagree, and either may be at fault: theta
    recorded in degrees, or a model whose theta has the wrong sign or unit. The
    message names both.

    Examples
    --------
    >>> degrees_message(42.0)
    'the motion model and the data disagree, as if theta were in degrees: if it is, multiply the column by pi/180; if not, the theta of the model is wrong: check its sign and unit against a push whose turn you know (every theta times pi/180 explains the pushes 42 nats better than as given)'
    """  # noqa: E501
    return (
        "the motion model and the data disagree, as if theta were in degrees: if it is, "
        f"multiply {column} by pi/180; if not, the theta of the model is wrong: check its "
        "sign and unit against a push whose turn you know (every theta times pi/180 explains "
        f"the pushes {gain:.0f} nats better than as given)"
    )


def fit_to_priors(model, mask: Mask, actions, motions) -> tuple[tuple[float, float], float]:
    """The CoM and friction a model's few-shot ``predict`` uses (:class:`comcore.Predictor`).

    The posterior mean CoM and the most probable friction under ``model`` given the prior
    pushes (``estimate_posterior``, no bootstrap, theta in radians); without prior pushes,
    the mask's area centroid and the middle of the default friction range.
    """
    if len(actions) == 0:
        return mask.centroid, float(mu_grid(None, 1)[0])
    est = estimate_posterior(
        mask, actions, motions, model=model, bootstrap=0, theta_units="rad"
    )
    details = est.posterior
    return est.com, float(details.mu_grid[np.argmax(details.mu_posterior)])


register_few_shot_fit(fit_to_priors)
