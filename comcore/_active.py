"""The active estimator: push, update a grid posterior, choose the next push, repeat."""

from __future__ import annotations

import math

import numpy as np

from ._active_setup import (
    DEFAULT_MIN_PUSHES,
    DEFAULT_MODEL,
    DEFAULT_MODEL_SCALES,
    DEFAULT_MODEL_WEIGHT,
    DEFAULT_MOTION_NOISE,
    DEFAULT_PUSHER_RADIUS,
    DEFAULT_TARGET_RADIUS,
    active_options,
    build_estimate,
    prior_grid,
)
from ._conventions import ANGLE_EPS
from ._errors import PushFailedError
from ._mask import Mask
from ._planning import Candidates
from ._posterior import GridPosterior
from ._sampling import DEFAULT_TRAVEL_M
from ._session import ActiveSession
from ._session_log import SessionLog
from ._session_pose import is_miss
from ._session_update import gyration_px, push_evidence, tracking_noise
from ._types import Estimate, Motion
from ._validation import check_actions, check_mask, check_motions

__all__ = ["estimate_active", "estimate_posterior"]

#: Options of estimate_active that choose pushes or stop: estimate_posterior has none.
PLANNING_OPTIONS = frozenset(
    {
        "max_pushes",
        "min_pushes",
        "target_radius",
        "selection",
        "min_information",
        "n_candidates",
        "cone",
        "travel",
        "rng",
    }
)


def estimate_active(
    mask: Mask,
    push,
    candidates=None,
    max_pushes: int = 5,
    *,
    model=DEFAULT_MODEL,
    pusher_radius: float = DEFAULT_PUSHER_RADIUS,
    min_pushes: int = DEFAULT_MIN_PUSHES,
    mu=None,
    target_radius: float = DEFAULT_TARGET_RADIUS,
    credible: float = 0.9,
    flip_prob: float = 0.05,
    rng=None,
    cone: float = 0.0,
    n_candidates: int = 200,
    travel: float = DEFAULT_TRAVEL_M,
    n_mu: int = 6,
    theta_tol: float = ANGLE_EPS,
    theta_noise=(0.01, 0.13),
    translation_error=(0.001, 0.056),
    pusher_error: float = 0.001,
    motion_noise=DEFAULT_MOTION_NOISE,
    translation_noise=None,
    selection: str = "sense",
    model_weight: float = DEFAULT_MODEL_WEIGHT,
    model_scales=DEFAULT_MODEL_SCALES,
    prior=None,
    min_information: float = 1e-3,
) -> Estimate:
    """Find the CoM by pushing the real object, choosing each push from what was seen.

    A posterior over (CoM pixel, contact friction) starts from ``prior``
    (uniform over the object) and a uniform grid of friction cone angles:
    friction is one unknown shared by all pushes, marginalised, never assumed.
    Each push's observed motion multiplies in a likelihood:

    * **Voting Theorem.** The sense of rotation tells the side of the push's
      force line (the push direction clipped to the friction cone) the CoM
      lies on: soft (a logistic edge whose standard deviation is
      ``hypot(pusher_error, 5.4 mm)``, the 5.4 mm fitted against the
      simulator with an exact pusher), and wrong with probability
      ``flip_prob`` (noise, slip), or more when the observed rotation is
      within the tracking noise ``motion_noise[0]`` of zero.
    * **Motion model** (``model``, a :class:`comcore.HypothesisPredictor`;
      by default :class:`comcore.LimitSurfaceModel` for a round pusher of
      ``pusher_radius`` metres; ``model=None``: the Voting Theorem alone):
      the rotation and translation it predicts for each (CoM, mu) hypothesis,
      scored with heavy-tailed Student-t residuals, the pusher's offset
      (``pusher_error``) marginalised at three Gauss-Hermite nodes, the whole
      term raised to a power (``model_weight``, learned per session). The rotation's scale is
      ``theta_noise[0] + theta_noise[1] / (1 + (lever / 3.75 cm)^2)`` (rad):
      a push whose line passes near the CoM balances on an unstable
      equilibrium and turns the object unpredictably; the translation's is
      ``translation_error[0] + translation_error[1] * |t|`` (metres), on the
      displacement of the hypothesis' CoM (the centroid's displacement also
      carries the rotation's error times its distance to the CoM). The
      defaults were fitted to the ellipsoid model's errors against the
      simulator (docs/active.md). The tracking error ``motion_noise`` adds to
      both in quadrature. All scales are in metres and radians: the same
      object gives the same posterior in metres at any camera resolution.

    Choosing the next push (``selection``):

    * ``"sense"`` (the default): the candidate with the
      highest expected information about the CoM from its observed sense,
      ``I(com; sense) = H(sense) - E[H(sense | com)]``, friction marginalised
      per hypothesis, computed exactly over the whole grid. It favours force
      lines that cut the posterior's mass in halves; the paper's equality
      score is the special case of a flat posterior, a known force line and
      no noise.
    * ``"model"``: the candidate whose motion is
      expected to tell the most apart among 64 CoMs drawn from the posterior
      (``I = E_i[log p(y_i | i) - log E_j p(y_i | j)]``, ``y_i`` the motion CoM
      ``i`` predicts at the most probable friction), using the same error
      scales as the update. Against the simulator it chose worse pushes than
      the sense (0.46 cm mean error against 0.28 cm after 5 pushes): it steers
      towards pushes whose predicted motions differ most, which is where the
      model is least right. It is slower too (the model is asked about every
      candidate).

    Pushes already made are not repeated. The loop stops when the
    equivalent-circle radius ``sqrt(area / pi)`` of the ``credible``
    highest-posterior region is at most ``target_radius`` after at least
    ``min_pushes`` pushes with evidence (status ``"ok"``), when ``max_pushes``
    pushes are spent (``"budget"``), when no candidate is
    left (``"exhausted"``) or when none is expected to teach more than
    ``min_information`` bits (``"uninformative"``). Whatever the reason, the
    status is ``"inconsistent"`` instead when no (CoM, friction, model)
    hypothesis explains the observed motions well (see
    :attr:`comcore.ActiveSession.consistent`): a robot, model or tracker that
    does not behave as the likelihood says.

    Parameters
    ----------
    mask : Mask
        The object as seen before the first push. Every action is given in this
        frame: ``push`` must execute it on the object in this pose (reset the
        object, or map the action through the motions observed so far).
    push : callable
        ``push(action: Action) -> Motion`` (or three numbers ``(theta, tx, ty)``):
        the robot or simulator. A robot that sees where its pusher really went
        returns ``(motion, executed)``, ``executed`` the path as executed
        (an :class:`Action` or four numbers, pixels of ``mask``): the push is
        then scored as executed (:meth:`comcore.ActiveSession.observe`'s
        ``executed``; set ``pusher_error`` to how well you know that path).
    candidates : array_like, shape (n, 4), optional
        Pushes to choose from; each must start outside the object and hit it.
        Default: ``comcore.sample_pushes(mask, n_candidates, cone=cone, rng=rng)``
        (a round pusher needs candidates that start clear of the object).
    max_pushes : int, optional
        Budget of real pushes (>= 0; default 5).
    min_pushes : int, optional
        Pushes with evidence before a small region may stop the run ``"ok"``
        (default 2; 0 lets a tight ``prior`` stop it before any push). One
        push cannot check the model: its motion is explained at some CoM
        however wrong the model is. Untempered (``model_weight=1``), the robot
        loop's runs that stopped after one push were 0.83 cm off on average.
    model : HypothesisPredictor, sequence of them, or None, optional
        Motion model for the likelihood of the whole motion. Default:
        ``comcore.LimitSurfaceModel(pusher_radius=pusher_radius)``. ``None``:
        the Voting Theorem alone (the sense of each rotation). Several models
        (say, different pressure assumptions) are weighed against each other
        like the friction: a uniform prior, marginalised.
    pusher_radius : float, optional
        Radius (metres) of the round pusher, for the default model (default
        4 mm, comcore's simulators' pusher): set it from your robot.
    mu : None, float or (lo, hi), optional
        Contact friction: unknown (default, marginalised over ``[0, 2]``), known,
        or a range (marginalised over it).
    target_radius : float, optional
        Stop when the credible region's equivalent-circle radius is at most
        this, in **metres** (default 6 mm). A region can be no smaller than a
        pixel (radius ``0.56 * resolution``). The defaults of ``max_pushes``
        (5), ``target_radius`` and ``model_weight`` were chosen on benchmark
        trials of seed 1 under the realism conditions (docs/active.md); the
        figures there are measured on other trials (seed 0).
    credible : float, optional
        Mass of the credible region, in (0, 1).
    flip_prob : float, optional
        Probability that an observed sense is wrong, in (0, 0.5).
    rng : None, int or numpy.random.Generator, optional
        Seeds the default candidates (the only random choice).
    cone : float, optional
        Half-angle (radians) of the default candidates' directions about the
        inward normal. The default 0 pushes along the normal: the contact
        sticks for any friction, so the force line is the push line (against
        the simulator: 0.32 cm after 4 pushes, against 0.37 cm with 0.3 rad).
    n_candidates : int, optional
        Number of default candidates.
    travel : float, optional
        How far (metres, default 3 cm) the default candidates push past first
        contact: set it from your workspace. Longer pushes turn the object
        more and tell more per push, and the model's errors grow with them
        (docs/active.md, "Longer pushes").
    n_mu : int, optional
        Number of friction values the unknown friction is marginalised over.
    theta_tol : float, optional
        Rotations with ``|theta| <= theta_tol`` (radians) carry no sense.
    theta_noise : (float, float), optional
        Rotation error scale of the model (rad): everywhere, and extra near
        the force line.
    translation_error : (float, float), optional
        Error scale of the model's CoM displacement: absolute (metres, default
        1 mm) and relative to the displacement.
    pusher_error : float, optional
        Standard deviation (metres) of the pusher's position across its path
        (default 1 mm): how far the executed push line may lie from the
        planned one.
    motion_noise : (float, float), optional
        Standard deviations of the measured motion's error, rotation (rad)
        and translation (metres); default 0.5 deg and 0.5 mm, a camera
        tracker's. Where :class:`comcore.ActiveSession` registers masks itself,
        the registration's residual is added.
    translation_noise : (float, float), optional
        Deprecated: ``translation_error`` in pixels (absolute, relative).
        Passing it warns (``DeprecationWarning``) and overrides
        ``translation_error``.
    model_weight : float or sequence of float, optional
        Power in (0, 1] on the model's likelihood. A model errs alike on the
        pushes of one object (its pressure is wrong the same way for every
        push), so treating its errors as independent overstates what several
        pushes tell: untempered, the 90 % region held the CoM in 62-72 % of
        benchmark trials with another engine or a pusher 3 mm off its path.
        A number fixes the power. A sequence (default ``(0.25, 0.4, 0.6,
        1.0)``) keeps one posterior per power and reports their mixture, each
        weighted by how well its posterior predicted every push before that
        push was seen (the untempered likelihood's posterior predictive: a
        power too high for the model's errors predicts the next push badly);
        ``extras["model_weight_posterior"]`` holds the weights. Chosen on
        seed-1 benchmark trials (docs/active.md): it held the CoM in 90-98 %
        where a fixed 0.6 held it in 80-98 %.
    model_scales : sequence of float, optional
        Factors on the model's error scales (``theta_noise``,
        ``translation_error``), one unknown factor shared by all pushes and
        marginalised like the friction (default ``(1.0,)``: the scales as
        given). ``extras["scale_posterior"]`` holds its posterior.
    selection : {"sense", "model"}, optional
        How to choose pushes (see above).
    prior : array_like, shape (H, W), optional
        Non-negative prior weights of the CoM over the image (default uniform
        over the object; pass e.g. the convex hull if the CoM may lie off it).
    min_information : float, optional
        Stop when no push is expected to teach more bits than this.

    Returns
    -------
    Estimate
        ``com`` is the posterior mean (it minimises the expected squared error;
        the MAP of a pixel grid is quantised and ill-defined on the flat
        plateaus the Voting Theorem leaves). ``covariance`` is the posterior
        covariance (px^2), ``region`` the credible region and ``used`` the
        indices into ``candidates`` in execution order. ``extras``:
        ``"motions"`` (k, 3) and ``"actions"`` (k, 4) executed, in order;
        ``"posterior"`` (H, W) CoM posterior; ``"credible_radius_px"``;
        ``"mu_grid"`` and ``"mu_posterior"``; ``"model_posterior"`` (one weight
        per model); ``"model_weight_posterior"`` (one weight per power of
        ``model_weight``); ``"log_evidence"`` and ``"excess_nats"`` (see
        :func:`comcore.estimate_posterior`); ``"outcomes"`` (``"evidence"`` or
        ``"miss"`` per push: a push that moved the object by less than 1 mm
        and 0.01 rad carries no evidence); ``"rotation_observed"`` and
        ``"residual_px"`` per push (what :func:`comcore.estimate_posterior`
        needs to replay them); ``"history"``: one dict per
        state (prior first) with the posterior mean ``"com"``,
        ``"entropy_bits"``, ``"credible_radius_px"``, ``"expected_gain_bits"``
        of the push chosen next (``None`` if none), ``"log_evidence"`` and
        ``"excess_nats"`` so far.

    Raises
    ------
    PushFailedError
        If ``push`` raises or returns an invalid or non-finite motion or an
        invalid executed path; its
        ``index`` says which push, ``partial`` holds the estimate so far.
    TypeError, ValueError
        On invalid arguments (each named).

    Examples
    --------
    A toy robot whose object turns 0.1 rad in the Voting Theorem's sense and
    does not move (no physics: the Voting Theorem alone, ``model=None``):

    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 8))
    >>> true_com = np.array([17.0, 20.0])
    >>> def push(action):
    ...     c = comcore.contacts(mask, action)
    ...     s = comcore.vt.rotation_sense(true_com, c.point[0], c.normal[0], action.direction, 0.3)
    ...     return comcore.Motion(0.1 * s, 0.0, 0.0)
    >>> est = comcore.estimate_active(mask, push, max_pushes=8, model=None, rng=0)
    >>> est.status, len(est.used), round(est.error_px(true_com), 1)
    ('budget', 8, 1.2)
    >>> comcore.estimate_active(mask, push, max_pushes=0, model=None).com  # the prior
    (22.5, 22.5)
    """
    mask = check_mask(mask)
    if not callable(push):
        raise TypeError(
            f"push must be callable as push(action) -> Motion, got {type(push).__name__}"
        )
    session = ActiveSession(
        mask,
        candidates=candidates,
        max_pushes=max_pushes,
        min_pushes=min_pushes,
        model=model,
        pusher_radius=pusher_radius,
        mu=mu,
        target_radius=target_radius,
        credible=credible,
        flip_prob=flip_prob,
        rng=rng,
        cone=cone,
        n_candidates=n_candidates,
        travel=travel,
        n_mu=n_mu,
        theta_tol=theta_tol,
        theta_noise=theta_noise,
        translation_error=translation_error,
        pusher_error=pusher_error,
        motion_noise=motion_noise,
        translation_noise=translation_noise,
        selection=selection,
        model_weight=model_weight,
        model_scales=model_scales,
        prior=prior,
        min_information=min_information,
    )
    while not session.done:
        action = session.next_push()
        try:
            motion, executed = _push_result(push(action))
        except Exception as e:
            raise _push_failed(session, action, e) from e
        try:
            session.observe(motion=motion, executed=executed)
        except (TypeError, ValueError) as e:  # a bad executed path; the session is unchanged
            if executed is None:
                raise
            raise _push_failed(session, action, e) from e
        session.reset_pose()  # push() executes every action on the object in mask's pose
    return session.estimate()


def _push_failed(session: ActiveSession, action, error: Exception) -> PushFailedError:
    """The error for a push that raised or returned something invalid, with the estimate so far."""
    n_done = len(session.actions)
    return PushFailedError(
        f"push {n_done} (candidates[{session._pending}] = {tuple(action)}) failed: "
        f"{type(error).__name__}: {error}",
        index=n_done,
        action=action,
        partial=session._estimate("push_failed"),
    )


def _push_result(result):
    """``(motion, executed or None)`` from what ``push`` returned (validated)."""
    if not isinstance(result, Motion) and isinstance(result, (tuple, list)) and len(result) == 2:
        motion, executed = result
        return check_motions(motion, n=1, name="push result's motion")[0], executed
    return check_motions(result, n=1, name="push result")[0], None


def estimate_posterior(
    mask: Mask,
    actions,
    motions,
    *,
    model=None,
    prior=None,
    rotation_observed=None,
    residual_px=None,
    **options,
) -> Estimate:
    """The active estimator's posterior over recorded pushes, without choosing any.

    The offline counterpart of :func:`comcore.estimate_active` and
    :class:`comcore.ActiveSession`: the same prior, likelihood (Voting Theorem
    force lines, optional motion model, friction marginalised) and result,
    over pushes in ``mask``'s frame: made from the pose of ``mask`` (the
    object reset before each), or a session's pushes as its Estimate holds
    them (``extras["actions"]``, ``["motions"]``, ``["rotation_observed"]``
    and ``["residual_px"]``, in the first mask's frame however the object
    moved): with the session's model and options that replays its posterior.
    A push whose motion is below the noise (it turned by less than 0.01 rad
    and moved by less than 1 mm: it missed) carries no evidence.

    Parameters
    ----------
    mask : Mask
        The object before the pushes.
    actions : array_like, shape (n, 4)
        The pushes in ``mask``'s pixels; each must start outside the object
        and hit it.
    motions : array_like, shape (n, 3)
        Their observed motions ``(theta, tx, ty)`` (radians, pixels), about
        ``mask``'s centroid.
    model : HypothesisPredictor or sequence of them, optional
        Motion model for the likelihood of the whole motion. Default None:
        the Voting Theorem alone (pass ``comcore.LimitSurfaceModel(
        pusher_radius=...)`` for :func:`comcore.estimate_active`'s default).
    prior : array_like, shape (H, W), optional
        Prior weights of the CoM (default uniform over the object).
    rotation_observed : sequence of bool, shape (n,), optional
        False for a push whose rotation is unknown (a symmetric outline's
        registration could not tell it: neither its sense nor its size is
        scored). Default: every rotation observed.
    residual_px : sequence of float, shape (n,), optional
        Per push, the RMS outline residual (pixels) of the registration that
        measured its motion, NaN where none did; it widens that motion's
        tracking error as in :class:`comcore.ActiveSession`. Default: none.
    **options
        The likelihood's options of :func:`comcore.estimate_active` (``mu``,
        ``credible``, ``flip_prob``, ``theta_tol``, ``n_mu``, the noise
        scales, ``model_weight``); those that choose pushes or stop are refused.

    Returns
    -------
    Estimate
        ``com`` the posterior mean, ``region`` the credible region, ``used``
        the pushes that carried evidence. ``extras`` as
        :func:`comcore.estimate_active`'s (``"posterior"``,
        ``"credible_radius_px"``, ``"history"``, ...) plus ``"outcomes"``
        (``"evidence"`` / ``"miss"`` per push), ``"log_evidence"`` (the log
        marginal likelihood of the motions: the log-probability the posterior
        before each push gave its motion under the untempered likelihood,
        summed) and ``"excess_nats"`` (how much
        more they surprise the best hypothesis than its own motions would, see
        :attr:`comcore.ActiveSession.excess_nats`). ``status`` is ``"ok"``,
        ``"inconsistent"`` when no hypothesis explains the pushes well
        (``excess_nats`` above ``10 + 6 sqrt(n)``), or ``"no_evidence"`` when
        no push carried any.

    Raises
    ------
    TypeError, ValueError
        On invalid arguments (each named).

    Examples
    --------
    Four pushes across a plate and the senses they turned it in: the CoM is
    between rows 8 and 13 and columns 8 and 13 (each sense may be wrong with
    probability ``flip_prob``, so the 90 % region still reaches outside):

    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
    >>> motions = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)]
    >>> est = comcore.estimate_posterior(mask, actions, motions)
    >>> est.status, np.round(est.com, 1).tolist(), round(est.extras["credible_radius_px"], 1)
    ('ok', [11.1, 11.1], 7.7)
    """
    mask = check_mask(mask)
    refused = sorted(PLANNING_OPTIONS & set(options))
    if refused:
        raise TypeError(f"estimate_posterior chooses no pushes: option(s) {refused} do not apply")
    acts = check_actions(actions, "actions", allow_empty=False)
    moves = check_motions(motions, n=len(acts), name="motions")
    observed = _per_push(rotation_observed, len(acts), "rotation_observed", True)
    residuals = _per_push(residual_px, len(acts), "residual_px", math.nan)
    opts = active_options(mask, model=model, **options)
    gyration = gyration_px(mask)
    pixels, prior_w = prior_grid(mask, prior)
    pushes = Candidates(mask, acts, opts, rng=None, name="actions")
    post = GridPosterior(
        pixels, prior_w, opts.mus, max(len(opts.models), 1), opts.n_scales, opts.n_tempers
    )
    log = SessionLog(post, opts.credible)
    for i, motion in enumerate(moves):
        record = {
            "index": i,
            "object_action": acts[i],
            "object_motion": tuple(motion),
            "ambiguous": not observed[i],
            "residual_px": residuals[i],
        }
        if is_miss(motion, mask.resolution):
            log.add({**record, "outcome": "miss"}, post)
            continue
        loglik, excess = push_evidence(
            post, opts, mask, acts[i], pushes.lines[i], motion,
            rotation_observed=bool(observed[i]),
            tracking=tracking_noise(opts.tracking, residuals[i], gyration),
        )  # fmt: skip
        log.add({**record, "outcome": "evidence"}, post, loglik, excess)
    used = [r["index"] for r in log.records if r["outcome"] == "evidence"]
    extras = log.extras()
    del extras["failed"]
    if not used:
        status = "no_evidence"
    elif not log.consistent:
        status = "inconsistent"
    else:
        status = "ok"
    return build_estimate(mask, post, opts.credible, used, log.history, status, extras)


def _per_push(values, n: int, name: str, default):
    """One value per push (bools for ``rotation_observed``, residuals otherwise), validated."""
    if values is None:
        return [default] * n
    if isinstance(values, (str, bytes)) or np.ndim(values) != 1 or len(values) != n:
        raise ValueError(f"{name} must hold one value per push ({n}), got {values!r}")
    if isinstance(default, bool):
        if not all(isinstance(v, (bool, np.bool_)) for v in values):
            raise TypeError(f"{name} must hold bools, got {values!r}")
        return [bool(v) for v in values]
    try:
        out = [float(v) for v in values]
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must hold numbers (NaN: not measured), got {values!r}") from e
    if any(v < 0 or math.isinf(v) for v in out):
        raise ValueError(f"{name} must be >= 0 and finite or NaN (pixels), got {values!r}")
    return out
