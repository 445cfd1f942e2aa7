"""The active estimator: push, update a grid posterior, choose the next push, repeat."""

from __future__ import annotations

import math

import numpy as np

from ._conventions import ANGLE_EPS
from ._errors import PushFailedError
from ._geometry import contacts
from ._mask import Mask
from ._posterior import (
    GridPosterior,
    force_lines,
    line_distances,
    motion_log_likelihood,
    push_log_likelihood,
    sense_information,
)
from ._predictor import HypothesisPredictor
from ._sampling import sample_pushes
from ._types import Action, Estimate
from ._validation import (
    check_actions,
    check_mask,
    check_motions,
    check_mu,
    check_positive,
    check_probability,
)

__all__ = ["estimate_active"]

#: Friction range searched when ``mu`` is unknown (covers common pusher materials).
UNKNOWN_MU_RANGE = (0.0, 2.0)
#: Degrees of freedom of the Student-t motion likelihood (heavy tails).
STUDENT_DOF = 3.0
#: Hypotheses this many nats below the best are dropped before the model is asked
#: about them (their posterior is below 1e-11 of the best; saves model calls).
PRUNE_LOG = 25.0
#: Largest cone half-angle used for an unbounded friction range (radians).
MAX_ALPHA = math.pi / 2 - 1e-3


def _mu_grid(mu, n_mu: int) -> np.ndarray:
    """Friction values at the mid-points of ``n_mu`` equal bins of cone half-angle."""
    lo, hi = UNKNOWN_MU_RANGE if mu is None else check_mu(mu)
    a_lo, a_hi = math.atan(lo), min(math.atan(hi), MAX_ALPHA)
    if a_hi - a_lo < 1e-12:
        return np.array([lo])
    alphas = a_lo + (np.arange(n_mu) + 0.5) * (a_hi - a_lo) / n_mu
    return np.tan(alphas)


def _prior_grid(mask: Mask, prior) -> tuple[np.ndarray, np.ndarray]:
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
    rows, cols = np.nonzero(weights > 0)
    w = weights[rows, cols]
    return np.column_stack([cols, rows]).astype(float), w / w.sum()


def _pair(value, name: str) -> tuple[float, float]:
    try:
        a, r = (float(v) for v in value)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be an (absolute, relative) pair of numbers") from e
    if not (a > 0 and math.isfinite(a) and r >= 0 and math.isfinite(r)):
        raise ValueError(f"{name} must have absolute > 0 and relative >= 0, got ({a}, {r})")
    return a, r


def _model_predictions(model, mask, action, pixels, mus, alive) -> np.ndarray:
    """The model's motion of ``action`` per (pixel, mu) where ``alive``, shape (p, m, 3).

    Hypotheses that are not alive are left NaN (they are not evaluated).
    """
    out = np.full((len(pixels), len(mus), 3), np.nan)
    for j, mu_j in enumerate(mus):
        idx = np.flatnonzero(alive[:, j])
        if len(idx) == 0:
            continue
        pred = np.asarray(model.predict_hypotheses(mask, action[None, :], pixels[idx], float(mu_j)))
        if pred.shape != (len(idx), 1, 3) or not np.isfinite(pred).all():
            raise ValueError(
                f"model.predict_hypotheses must return finite motions of shape "
                f"({len(idx)}, 1, 3), got shape {pred.shape}"
            )
        out[idx, j] = pred[:, 0]
    return out


def _build(mask, post, level, candidates, used, motions, history, status) -> Estimate:
    region_idx, area = post.credible(level)
    rows, cols = post.pixels[:, 1].astype(int), post.pixels[:, 0].astype(int)
    region = np.zeros(mask.shape, dtype=bool)
    region[rows[region_idx], cols[region_idx]] = True
    image = np.zeros(mask.shape)
    np.add.at(image, (rows, cols), post.marginal)
    com = tuple(float(v) for v in post.mean())
    return Estimate(
        com=com,
        com_m=mask.to_metres(com),
        region=region,
        used=tuple(used),
        status=status,
        covariance=post.covariance(),
        extras={
            "motions": np.array(motions, dtype=float).reshape(-1, 3),
            "actions": candidates[list(used)].reshape(-1, 4),
            "posterior": image,
            "credible_radius_px": math.sqrt(area / math.pi),
            "mu_grid": post.mus.copy(),
            "mu_posterior": post.mu_marginal,
            "history": tuple(history),
        },
    )


def estimate_active(
    mask: Mask,
    push,
    candidates=None,
    max_pushes: int = 6,
    *,
    model=None,
    mu=None,
    target_radius: float = 0.003,
    credible: float = 0.9,
    flip_prob: float = 0.05,
    rng=None,
    cone: float = 0.3,
    n_candidates: int = 200,
    n_mu: int = 6,
    theta_tol: float = ANGLE_EPS,
    theta_noise=(0.02, 0.15),
    translation_noise=(1.0, 0.1),
    prior=None,
    min_information: float = 1e-3,
) -> Estimate:
    """Find the CoM by pushing the real object, choosing each push from what was seen.

    A posterior over (CoM pixel, contact friction) starts from ``prior``
    (uniform over the object) and a uniform grid of friction cone angles. Each
    push's observed motion multiplies in a likelihood:

    * **Voting Theorem.** The sense of rotation tells the side of the push's
      force line the CoM lies on (the push direction clipped to the friction
      cone, see :mod:`comcore._posterior`), with probability ``1 - flip_prob``;
      with ``flip_prob`` the observed sense is wrong (noise, slip).
    * **Motion model** (optional ``model``, a :class:`comcore.HypothesisPredictor`):
      the rotation and translation it predicts for each (CoM, mu) hypothesis,
      scored with heavy-tailed Student-t residuals whose scales are
      ``absolute + relative * |prediction|`` (``theta_noise``,
      ``translation_noise``), robust to the model's mismatch with the robot.

    The next push is the candidate with the highest expected information gain
    about the CoM from its observed sense, ``I(com; sense) = H(sense) -
    E[H(sense | com)]``, friction marginalised per hypothesis. It is computed
    exactly over the grid (no sampling), is what the Voting Theorem can
    guarantee, and it favours force lines through the middle of the current
    posterior: exactly the pushes whose rotation magnitude is most sensitive
    to the CoM (the rotation is steepest in the lever arm at zero lever arm),
    so the same choice serves the model's likelihood. The paper's equality
    score is the special case of a flat posterior, a known force line and no
    noise. Pushes already made are not repeated.

    The loop stops when the equivalent-circle radius ``sqrt(area / pi)`` of
    the ``credible`` highest-posterior region is at most ``target_radius``
    (status ``"ok"``), when ``max_pushes`` pushes are spent (``"budget"``),
    when no candidate is left (``"exhausted"``) or when no candidate is
    expected to teach more than ``min_information`` bits (``"uninformative"``).

    Parameters
    ----------
    mask : Mask
        The object as seen before the first push. Every action is given in this
        frame: ``push`` must execute it on the object in this pose (reset the
        object, or map the action through the motions observed so far).
    push : callable
        ``push(action: Action) -> Motion`` (or three numbers ``(theta, tx, ty)``):
        the robot or simulator.
    candidates : array_like, shape (n, 4), optional
        Pushes to choose from; each must start outside the object and hit it.
        Default: ``comcore.sample_pushes(mask, n_candidates, cone=cone, rng=rng)``.
    max_pushes : int, optional
        Budget of real pushes (>= 0).
    model : HypothesisPredictor, optional
        Motion model for the rotation magnitude and translation likelihood.
    mu : None, float or (lo, hi), optional
        Contact friction: unknown (default, marginalised over ``[0, 2]``), known,
        or a range (marginalised over it).
    target_radius : float, optional
        Stop when the credible region's equivalent-circle radius is at most
        this, in **metres** (default 3 mm). A region can be no smaller than a
        pixel (radius ``0.56 * resolution``).
    credible : float, optional
        Mass of the credible region, in (0, 1).
    flip_prob : float, optional
        Probability that an observed sense is wrong, in (0, 0.5).
    rng : None, int or numpy.random.Generator, optional
        Seeds the default candidates (the only random choice).
    cone : float, optional
        Half-angle (radians) of the default candidates' directions about the
        inward normal.
    n_candidates : int, optional
        Number of default candidates.
    n_mu : int, optional
        Number of friction values the unknown friction is marginalised over.
    theta_tol : float, optional
        Rotations with ``|theta| <= theta_tol`` (radians) carry no sense.
    theta_noise : (float, float), optional
        Model likelihood scale of the rotation: absolute (rad) and relative.
    translation_noise : (float, float), optional
        Model likelihood scale of the translation: absolute (px) and relative.
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
        ``"mu_grid"`` and ``"mu_posterior"``; ``"history"``: one dict per
        state (prior first) with ``"entropy_bits"``, ``"credible_radius_px"``
        and ``"expected_gain_bits"`` of the push chosen next (``None`` if none).

    Raises
    ------
    PushFailedError
        If ``push`` raises or returns an invalid or non-finite motion; its
        ``index`` says which push, ``partial`` holds the estimate so far.
    TypeError, ValueError
        On invalid arguments (each named).

    Examples
    --------
    A toy robot whose object turns 0.1 rad in the Voting Theorem's sense:

    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 8))
    >>> true_com = np.array([17.0, 20.0])
    >>> def push(action):
    ...     c = comcore.contacts(mask, action)
    ...     s = comcore.vt.rotation_sense(true_com, c.point[0], c.normal[0], action.direction, 0.3)
    ...     return comcore.Motion(0.1 * s, 0.0, 0.0)
    >>> est = comcore.estimate_active(mask, push, max_pushes=8, rng=0)
    >>> est.status, len(est.used), round(est.error_px(true_com), 1)
    ('budget', 8, 1.9)
    >>> comcore.estimate_active(mask, push, max_pushes=0).com  # the prior: the centroid
    (22.5, 22.5)
    """
    mask = check_mask(mask)
    if not callable(push):
        raise TypeError(
            f"push must be callable as push(action) -> Motion, got {type(push).__name__}"
        )
    if isinstance(max_pushes, bool) or not isinstance(max_pushes, (int, np.integer)):
        raise TypeError(f"max_pushes must be an int, got {type(max_pushes).__name__}")
    if max_pushes < 0:
        raise ValueError(f"max_pushes must be >= 0, got {max_pushes}")
    if model is not None and not isinstance(model, HypothesisPredictor):
        raise TypeError(
            "model must implement comcore.HypothesisPredictor (a predict_hypotheses(mask, "
            f"actions, coms, mu) method), got {type(model).__name__}"
        )
    target_px = check_positive(target_radius, "target_radius") / mask.resolution
    credible = check_probability(credible, "credible", open_low=True, open_high=True)
    flip_prob = check_probability(flip_prob, "flip_prob", open_low=True)
    if flip_prob >= 0.5:
        raise ValueError(f"flip_prob must be in (0, 0.5), got {flip_prob}")
    theta_tol = check_positive(theta_tol, "theta_tol", allow_zero=True)
    min_information = check_positive(min_information, "min_information", allow_zero=True)
    theta_noise = _pair(theta_noise, "theta_noise")
    translation_noise = _pair(translation_noise, "translation_noise")
    for value, name in ((n_mu, "n_mu"), (n_candidates, "n_candidates")):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
            raise ValueError(f"{name} must be a positive int, got {value!r}")
    mus = _mu_grid(mu, int(n_mu))
    pixels, prior_w = _prior_grid(mask, prior)
    rng = np.random.default_rng(rng)
    if candidates is None:
        cands = sample_pushes(mask, int(n_candidates), cone=cone, rng=rng)
    else:
        cands = check_actions(candidates, "candidates", allow_empty=False)
    con = contacts(mask, cands)
    con.require_hits("candidates")
    direction = cands[:, 2:] - cands[:, :2]
    direction = direction / np.hypot(direction[:, 0], direction[:, 1])[:, None]
    lines = force_lines(con.point, con.normal, direction, np.arctan(mus))

    post = GridPosterior(pixels, prior_w, mus)
    used: list[int] = []
    motions: list[tuple[float, float, float]] = []
    history: list[dict] = []
    available = np.ones(len(cands), dtype=bool)
    while True:
        _, area = post.credible(credible)
        radius = math.sqrt(area / math.pi)
        history.append(
            {
                "entropy_bits": post.entropy_bits(),
                "credible_radius_px": radius,
                "expected_gain_bits": None,
            }
        )
        if radius <= target_px:
            status = "ok"
            break
        if len(used) >= max_pushes:
            status = "budget"
            break
        if not available.any():
            status = "exhausted"
            break
        idx = np.flatnonzero(available)
        gains = sense_information(post.pixels, post.weights, lines[idx], flip_prob)
        best = int(np.argmax(gains))
        if gains[best] <= min_information:
            status = "uninformative"
            break
        chosen = int(idx[best])
        history[-1]["expected_gain_bits"] = float(gains[best])
        action = Action(*cands[chosen])
        n_done = len(used)
        try:
            observed = check_motions(push(action), n=1, name="push result")[0]
        except Exception as e:
            partial = _build(mask, post, credible, cands, used, motions, history, "push_failed")
            raise PushFailedError(
                f"push {n_done} (candidates[{chosen}] = {tuple(action)}) failed: "
                f"{type(e).__name__}: {e}",
                index=n_done,
                action=action,
                partial=partial,
            ) from e
        distances = line_distances(post.pixels, lines[chosen])
        model_term = flipped_term = None
        if model is not None:
            alive = post.log_w > post.log_w.max() - PRUNE_LOG
            predicted = _model_predictions(model, mask, cands[chosen], post.pixels, mus, alive)
            args = (theta_noise, translation_noise, STUDENT_DOF)
            flipped = observed * np.array([-1.0, 1.0, 1.0])
            model_term = np.where(alive, motion_log_likelihood(observed, predicted, *args), -np.inf)
            flipped_term = np.where(
                alive, motion_log_likelihood(flipped, predicted, *args), -np.inf
            )
        post.update(
            push_log_likelihood(distances, observed, flip_prob, theta_tol, model_term, flipped_term)
        )
        used.append(chosen)
        motions.append(tuple(float(v) for v in observed))
        available[chosen] = False
    return _build(mask, post, credible, cands, used, motions, history, status)
