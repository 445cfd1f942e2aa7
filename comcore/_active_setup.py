"""Arguments, grids and the result of :func:`comcore.estimate_active` and the session."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ._conventions import ANGLE_EPS, pixel_centres
from ._mask import Mask
from ._predictor import HypothesisPredictor
from ._sampling import DEFAULT_TRAVEL_M
from ._types import Estimate
from ._validation import check_mu, check_positive, check_probability

__all__ = [
    "DEFAULT_MODEL",
    "DEFAULT_MODEL_SCALES",
    "DEFAULT_MODEL_WEIGHT",
    "DEFAULT_MOTION_NOISE",
    "DEFAULT_PUSHER_RADIUS",
    "DEFAULT_TARGET_RADIUS",
    "LINE_BLUR_M",
    "MAX_ALPHA",
    "NEAR_LINE_M",
    "SELECTIONS",
    "UNKNOWN_MU_RANGE",
    "ActiveOptions",
    "active_options",
    "build_estimate",
    "check_model_weight",
    "check_models",
    "mu_grid",
    "pair",
    "prior_grid",
]

#: Friction range searched when ``mu`` is unknown (covers common pusher materials).
UNKNOWN_MU_RANGE = (0.0, 2.0)
#: Largest cone half-angle used for an unbounded friction range (radians).
MAX_ALPHA = math.pi / 2 - 1e-3
#: Length (metres) over which the rotation's model error falls off with the
#: lever arm (fitted against the simulator for 3 cm pushes, docs/active.md).
NEAR_LINE_M = 0.0375
#: Ways to choose the next push.
SELECTIONS = ("sense", "model")
#: Blur (metres, a standard deviation) of the force line with an exact pusher:
#: the pusher's radius, the object turning during a 3 cm push, outlines and
#: normals. Fitted against the simulator as a logistic of scale 1.2 px at
#: 2.5 mm/px (docs/active.md); the pusher's own error adds in quadrature.
LINE_BLUR_M = 1.2 * 0.0025 * math.pi / math.sqrt(3.0)
#: Default tracking error of a measured motion: 0.5 deg and 0.5 mm (a camera's).
DEFAULT_MOTION_NOISE = (math.radians(0.5), 0.0005)
#: Radius (metres) of the pusher assumed when none is given: the simulators' default pusher.
DEFAULT_PUSHER_RADIUS = 0.004
#: Pushes with evidence before a region small enough may stop the session ``"ok"``: one
#: push's motion is explained by the model at some CoM whatever the model's error, so
#: the first push cannot check the model (docs/active.md: with the untempered model, the
#: runs that stopped after one push were 0.83 cm off on average, half outside the region).
DEFAULT_MIN_PUSHES = 2


class _DefaultModel:
    """The ``model`` argument's default: ``LimitSurfaceModel(pusher_radius=pusher_radius)``."""

    def __repr__(self) -> str:
        return "<default: comcore.LimitSurfaceModel(pusher_radius=pusher_radius)>"

    def __reduce__(self):
        return "DEFAULT_MODEL"


#: ``model``'s default (``model=None`` asks for the Voting Theorem alone).
DEFAULT_MODEL = _DefaultModel()
#: Power on the motion model's likelihood (tempered: a model errs alike on the pushes
#: of one object). Chosen on benchmark trials of seed 1 (docs/active.md).
DEFAULT_MODEL_WEIGHT = (0.25, 0.4, 0.6, 1.0)
#: Credible-region radius (metres) at which the estimator stops (seed 1, docs/active.md).
DEFAULT_TARGET_RADIUS = 0.006
#: Factors on the motion model's error scales (``theta_noise``, ``translation_error``)
#: weighed like the friction: one unknown factor for all pushes of a session.
DEFAULT_MODEL_SCALES = (1.0,)
#: Standard deviation of a logistic of unit scale (its scale is std * sqrt(3) / pi).
_LOGISTIC_STD = math.pi / math.sqrt(3.0)


@dataclass(frozen=True)
class ActiveOptions:
    """The validated options of the active estimator (internal).

    Lengths are in pixels of the first mask (``target_px``, ``near_px``);
    see :func:`comcore.estimate_active` for what each option means.
    """

    models: tuple
    max_pushes: int
    min_pushes: int
    target_px: float
    credible: float
    flip_prob: float
    cone: float
    n_candidates: int
    travel_m: float
    mus: np.ndarray
    theta_tol: float
    theta_noise: tuple[float, float]
    translation_noise: tuple[float, float]
    selection: str
    model_weights: tuple
    min_information: float
    near_px: float
    line_scale_px: float
    tracking: tuple[float, float]
    pusher_px: float = 0.0
    model_scales: tuple = (1.0,)

    @property
    def n_tempers(self) -> int:
        """Powers on the model's likelihood weighed per session (1 without a model)."""
        return len(self.model_weights) if self.models else 1

    @property
    def n_scales(self) -> int:
        """Model-error scale factors marginalised (1 without a model)."""
        return len(self.model_scales) if self.models else 1


def _count(value, name: str, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def active_options(
    mask: Mask,
    *,
    model=DEFAULT_MODEL,
    pusher_radius: float = DEFAULT_PUSHER_RADIUS,
    max_pushes: int = 5,
    min_pushes: int = DEFAULT_MIN_PUSHES,
    mu=None,
    target_radius: float = DEFAULT_TARGET_RADIUS,
    credible: float = 0.9,
    flip_prob: float = 0.05,
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
    min_information: float = 1e-3,
) -> ActiveOptions:
    """Validate the active estimator's options (each error names its argument).

    The noise scales are physical (metres, radians) and become pixels of
    ``mask`` here: the force line's logistic edge has the standard deviation
    ``hypot(pusher_error, LINE_BLUR_M)``; ``translation_noise`` (pixels) is
    the deprecated form of ``translation_error`` (metres).
    """
    max_pushes = _count(max_pushes, "max_pushes", 0)
    min_pushes = _count(min_pushes, "min_pushes", 0)
    pusher_radius = check_positive(pusher_radius, "pusher_radius", allow_zero=True)
    models = check_models(model, pusher_radius)
    target_px = check_positive(target_radius, "target_radius") / mask.resolution
    credible = check_probability(credible, "credible", open_low=True, open_high=True)
    flip_prob = check_probability(flip_prob, "flip_prob", open_low=True)
    if flip_prob >= 0.5:
        raise ValueError(f"flip_prob must be in (0, 0.5), got {flip_prob}")
    theta_tol = check_positive(theta_tol, "theta_tol", allow_zero=True)
    min_information = check_positive(min_information, "min_information", allow_zero=True)
    theta_noise = pair(theta_noise, "theta_noise")
    if selection not in SELECTIONS:
        raise ValueError(f"selection must be one of {SELECTIONS}, got {selection!r}")
    if selection == "model" and not models:
        raise ValueError("selection='model' needs a model")
    model_weights = check_model_weight(model_weight)
    if translation_noise is not None:
        translation_noise = pair(translation_noise, "translation_noise")
        warnings.warn(
            "translation_noise (pixels) is deprecated: pass translation_error=(metres, relative)",
            DeprecationWarning,
            stacklevel=3,
        )
    else:
        t_abs, t_rel = pair(translation_error, "translation_error")
        translation_noise = (t_abs / mask.resolution, t_rel)
    pusher_error = check_positive(pusher_error, "pusher_error", allow_zero=True)
    travel_m = check_positive(travel, "travel")
    try:
        scales = tuple(float(v) for v in model_scales)
    except (TypeError, ValueError) as e:
        raise TypeError(f"model_scales must be a sequence of numbers, got {model_scales!r}") from e
    if not scales or not all(math.isfinite(v) and v > 0 for v in scales):
        raise ValueError(f"model_scales must be positive finite factors, got {model_scales!r}")
    track_theta, track_m = pair(motion_noise, "motion_noise", allow_zero=True)
    line_std_m = math.hypot(pusher_error, LINE_BLUR_M)
    for value, name in ((n_mu, "n_mu"), (n_candidates, "n_candidates")):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
            raise ValueError(f"{name} must be a positive int, got {value!r}")
    return ActiveOptions(
        models=models,
        max_pushes=max_pushes,
        min_pushes=min_pushes,
        target_px=target_px,
        credible=credible,
        flip_prob=flip_prob,
        cone=cone,
        n_candidates=int(n_candidates),
        travel_m=travel_m,
        mus=mu_grid(mu, int(n_mu)),
        theta_tol=theta_tol,
        theta_noise=theta_noise,
        translation_noise=translation_noise,
        selection=selection,
        model_weights=model_weights,
        min_information=min_information,
        near_px=NEAR_LINE_M / mask.resolution,
        line_scale_px=line_std_m / _LOGISTIC_STD / mask.resolution,
        tracking=(track_theta, track_m / mask.resolution),
        pusher_px=pusher_error / mask.resolution,
        model_scales=scales,
    )


def check_model_weight(model_weight) -> tuple[float, ...]:
    """``model_weight`` as a tuple of powers in (0, 1]: one fixed power, or the learned set."""
    if isinstance(model_weight, str):
        raise TypeError(
            f"model_weight must be a number or a sequence of numbers, got {model_weight!r}"
        )
    if np.ndim(model_weight) == 0:
        return (check_probability(model_weight, "model_weight", open_low=True),)
    try:
        values = tuple(model_weight)
    except TypeError as e:
        raise TypeError(
            f"model_weight must be a number or a sequence of numbers, got {model_weight!r}"
        ) from e
    if not values:
        raise ValueError("model_weight must not be an empty sequence")
    out = tuple(check_probability(v, "model_weight", open_low=True) for v in values)
    if len(set(out)) != len(out):
        raise ValueError(f"model_weight's powers must be distinct, got {model_weight!r}")
    return out


def mu_grid(mu, n_mu: int) -> np.ndarray:
    """Friction values at the mid-points of ``n_mu`` equal bins of cone half-angle."""
    lo, hi = UNKNOWN_MU_RANGE if mu is None else check_mu(mu)
    a_lo, a_hi = math.atan(lo), min(math.atan(hi), MAX_ALPHA)
    if a_hi - a_lo < 1e-12:
        return np.array([lo])
    alphas = a_lo + (np.arange(n_mu) + 0.5) * (a_hi - a_lo) / n_mu
    return np.tan(alphas)


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


def pair(value, name: str, allow_zero: bool = False) -> tuple[float, float]:
    """Validate an ``(absolute > 0, other >= 0)`` pair of numbers (both >= 0 with allow_zero)."""
    try:
        a, r = (float(v) for v in value)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be a pair of numbers (absolute, other)") from e
    low_ok = a >= 0 if allow_zero else a > 0
    if not (low_ok and math.isfinite(a) and r >= 0 and math.isfinite(r)):
        want = "both >= 0" if allow_zero else "absolute > 0 and other >= 0"
        raise ValueError(f"{name} must be a pair with {want}, got ({a}, {r})")
    return a, r


def check_models(model, pusher_radius: float = DEFAULT_PUSHER_RADIUS) -> tuple:
    """``model`` as a tuple of HypothesisPredictors (empty for None).

    :data:`DEFAULT_MODEL` becomes ``LimitSurfaceModel(pusher_radius=pusher_radius)``.
    """
    if model is DEFAULT_MODEL:
        from ._limit_surface_model import LimitSurfaceModel

        return (LimitSurfaceModel(pusher_radius=pusher_radius),)
    if model is None:
        return ()
    models = tuple(model) if isinstance(model, (list, tuple)) else (model,)
    for m in models:
        if not isinstance(m, HypothesisPredictor):
            raise TypeError(
                "model must implement comcore.HypothesisPredictor (a predict_hypotheses(mask, "
                f"actions, coms, mu) method) or be a sequence of them, got {type(m).__name__}"
            )
    if not models:
        raise ValueError("model must not be an empty sequence")
    return models


def build_estimate(mask, post, level, used, history, status, extras) -> Estimate:
    """The :class:`Estimate` of a posterior: mean, covariance, credible region, extras.

    ``extras`` (the executed actions and motions, ...) are added to the
    posterior's own: ``"posterior"``, ``"credible_radius_px"``, ``"mu_grid"``,
    ``"mu_posterior"``, ``"model_posterior"``, ``"scale_posterior"`` (one
    weight per ``model_scales`` factor) and ``"history"``.
    """
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
            **extras,
            "posterior": image,
            "credible_radius_px": math.sqrt(area / math.pi),
            "mu_grid": post.mus.copy(),
            "mu_posterior": post.mu_marginal,
            "model_posterior": post.model_marginal,
            "scale_posterior": post.scale_marginal,
            "model_weight_posterior": post.temper_weights,
            "history": tuple(dict(h) for h in history),
        },
    )
