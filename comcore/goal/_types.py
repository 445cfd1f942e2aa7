"""What a goal is, and the CoM hypotheses a push is planned over.

:class:`Goal` is the pose a user wants the object in (position, orientation,
either optional, with tolerances in metres and radians). :class:`CoMHypotheses`
is a small weighted set of (CoM, friction) hypotheses drawn from a posterior:
what :func:`comcore.goal.translation_push` and :class:`comcore.GoalSession` predict
each candidate push over, instead of one point estimate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .._checks import check_finite
from .._mask import Mask
from .._types import Estimate
from ..active._grid import GridPosterior
from ..active._likelihood import Likelihood, mu_grid
from ..conventions import check_plausible

__all__ = [
    "PLANNING_PARTICLES",
    "CoMHypotheses",
    "Goal",
    "MetricPose",
    "estimate_frictions",
    "hypotheses_from",
]

#: How many (CoM, friction) particles a push is planned over (a systematic draw).
PLANNING_PARTICLES = 32
#: The most particles ``GoalSession(n_particles=...)`` takes: each is a motion-model call
#: per candidate push, so 10,000 already costs minutes a push; more asked numpy for terabytes.
MAX_PLANNING_PARTICLES = 10_000


def _pair(value, name: str) -> tuple[float, float] | None:
    if value is None:
        return None
    try:
        items = tuple(value)
    except TypeError:
        raise TypeError(f"{name} must be a pair (x, y) of numbers, got {value!r}") from None
    if len(items) != 2:
        raise ValueError(f"{name} must be a pair (x, y), got {len(items)} numbers")
    return tuple(check_finite(v, f"{name}[{i}]") for i, v in enumerate(items))


@dataclass(frozen=True)
class Goal:
    """The pose to push an object to, in the first mask's camera frame.

    **The frame is the camera's pixel frame, relative to the first mask**: x
    to the right (columns), **+y down the screen** (rows), not a robot's or a
    table's y-up world frame; ``orientation`` counter-clockwise as seen on
    screen. ``displacement=(0, 0.1)`` moves the object 10 cm *down* the image;
    a robot whose world y points up the screen passes ``(dx, -dy)``
    (docs/explanation/conventions.md).

    The pose has the form of :attr:`comcore.ActiveSession.pose`: the object's
    rotation ``theta`` since the first mask and where the first mask's area
    centroid (the material point under it) has gone. Give the position as a
    ``position`` (where that point should be) or a ``displacement`` (how far it
    should move), not both; either, and the ``orientation``, may be left out
    (None: free). At least one of them must be given.

    Parameters
    ----------
    position : (float, float), optional
        Where the first mask's centroid should end, in ``units`` of the first
        mask's frame (metres are ``resolution * (x, y)``, as
        :meth:`comcore.Mask.to_metres`).
    displacement : (float, float), optional
        How far it should move, in ``units`` (x right, +y down the screen).
    orientation : float, optional
        The rotation (radians, counter-clockwise on screen) relative to the
        first mask; 0 holds the first orientation. Within ``[-2 pi, 2 pi]``.
    units : {"m", "px"}, optional
        Units of ``position`` and ``displacement`` (default metres).
    position_tolerance : float, optional
        Metres (default 0.01): the goal is reached when the point is this close.
    orientation_tolerance : float, optional
        Radians (default 3 degrees).
    max_turn : float, optional
        Radians: how far the object may turn on the way beyond the band from
        its orientation at the session's start to the goal's (just the start
        where the orientation is free). The planner does not make a push
        predicted (mean over the posterior's particles) to leave the band by
        more, nor, once the object is past it, further than it is; the
        camera may still see it turn more, as the motion model errs. None
        (default): unbounded. Within ``(0, 2 pi]``.

    Raises
    ------
    TypeError, ValueError
        On a missing or invalid field (named), e.g. an orientation in degrees.

    Examples
    --------
    >>> import math, comcore
    >>> goal = comcore.Goal(displacement=(0.2, 0.0), orientation=0.0,
    ...                     orientation_tolerance=math.radians(2))
    >>> goal.displacement, goal.units
    ((0.2, 0.0), 'm')
    >>> comcore.Goal(orientation=90.0)
    Traceback (most recent call last):
    ...
    ValueError: Goal.orientation 90 rad is more than a full turn: radians are expected (did you mean math.radians(90.0) = 1.571?)
    """  # noqa: E501

    position: tuple[float, float] | None = None
    displacement: tuple[float, float] | None = None
    orientation: float | None = None
    units: str = "m"
    position_tolerance: float = 0.01
    orientation_tolerance: float = math.radians(3.0)
    max_turn: float | None = None

    def __post_init__(self):
        set_ = object.__setattr__
        if self.units not in ("m", "px"):
            raise ValueError(f"Goal.units must be 'm' or 'px', got {self.units!r}")
        set_(self, "position", _pair(self.position, "Goal.position"))
        set_(self, "displacement", _pair(self.displacement, "Goal.displacement"))
        if self.position is not None and self.displacement is not None:
            raise ValueError("Goal takes a position or a displacement, not both")
        if self.orientation is not None:
            theta = check_finite(self.orientation, "Goal.orientation")
            if abs(theta) > 2 * math.pi:
                raise ValueError(
                    f"Goal.orientation {theta:g} rad is more than a full turn: radians are "
                    f"expected (did you mean math.radians({theta}) = {math.radians(theta):.4g}?)"
                )
            set_(self, "orientation", theta)
        if self.position is None and self.displacement is None and self.orientation is None:
            raise ValueError("Goal needs a position, a displacement or an orientation")
        tol = check_finite(self.position_tolerance, "Goal.position_tolerance")
        if tol <= 0:
            raise ValueError(f"Goal.position_tolerance must be > 0 metres, got {tol}")
        set_(self, "position_tolerance", check_plausible(tol, "position_tolerance", "push_length"))
        angle = check_finite(self.orientation_tolerance, "Goal.orientation_tolerance")
        if not 0 < angle <= math.pi:
            raise ValueError(
                f"Goal.orientation_tolerance must be in (0, pi] radians, got {angle:g}"
                + (" (degrees?)" if angle > math.pi else "")
            )
        set_(self, "orientation_tolerance", angle)
        if self.max_turn is not None:
            bound = check_finite(self.max_turn, "Goal.max_turn")
            if not 0 < bound <= 2 * math.pi:
                raise ValueError(
                    f"Goal.max_turn must be in (0, 2 pi] radians, got {bound:g}"
                    + (f" (degrees? math.radians({bound:g}) = {math.radians(bound):.4g})"
                       if bound > 2 * math.pi else "")
                )
            set_(self, "max_turn", bound)

    def turn_band(self, start: float) -> tuple[float, float]:
        """The orientations (radians, low and high) the object may pass without turning on the way.

        From ``start`` (the orientation at the session's start) to the goal's
        orientation (just ``start`` where it is free); :attr:`max_turn` bounds
        how far outside it a push may take the object.
        """
        end = start if self.orientation is None else self.orientation
        return (min(start, end), max(start, end))

    @property
    def has_position(self) -> bool:
        """Whether the goal sets where the object goes."""
        return self.position is not None or self.displacement is not None

    def target_px(self, first: Mask) -> tuple[float, float] | None:
        """The pose's ``(tx, ty)`` the goal asks for, pixels of ``first`` (None: free)."""
        scale = 1.0 if self.units == "px" else 1.0 / first.resolution
        if self.displacement is not None:
            return (self.displacement[0] * scale, self.displacement[1] * scale)
        if self.position is not None:
            cx, cy = first.centroid
            return (self.position[0] * scale - cx, self.position[1] * scale - cy)
        return None


class MetricPose(NamedTuple):
    """A pose with its translation in metres (:attr:`comcore.GoalSession.pose_m`).

    The form of :attr:`comcore.GoalSession.pose` (a :class:`comcore.Motion`,
    pixels) in the units of a :class:`Goal`: the first mask's frame, x right
    and +y down the screen.
    """

    theta: float
    """The turn since the first mask, radians, counter-clockwise on screen."""
    tx: float
    """How far the first mask's area centroid has moved along x (right), metres."""
    ty: float
    """How far it has moved along y (down the screen), metres."""


class CoMHypotheses(NamedTuple):
    """Weighted (CoM, friction) hypotheses, the CoMs in pixels of the first mask.

    A posterior :func:`comcore.goal.translation_push` and :class:`comcore.GoalSession`
    accept as it is (e.g. a known CoM and friction:
    ``CoMHypotheses(np.array([[x, y]]), np.array([mu]), np.array([1.0]))``).
    """

    coms: np.ndarray
    """Shape (n, 2)."""
    mus: np.ndarray
    """Shape (n,): each hypothesis' contact friction."""
    weights: np.ndarray
    """Shape (n,), summing to 1."""


def _systematic(weights: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Deterministic systematic draw: distinct indices and their weights (counts / n)."""
    cum = np.cumsum(weights)
    picks = np.searchsorted(cum, (np.arange(n) + 0.5) / n * cum[-1])
    index, counts = np.unique(np.minimum(picks, len(cum) - 1), return_counts=True)
    return index, counts / n


def _default_mus() -> np.ndarray:
    lik = Likelihood()
    return mu_grid(lik.mu, lik.n_mu)


def hypotheses_from(posterior, mask: Mask, n: int = PLANNING_PARTICLES, mus=None) -> CoMHypotheses:
    """``n`` particles of a posterior over the CoM (and the friction where it has one).

    Accepted: a :class:`comcore.Estimate` of an active estimator (its
    ``posterior``'s ``image``, ``mu_grid`` and ``mu_posterior``; an estimate
    without a posterior is its ``com`` alone), a
    :class:`CoMHypotheses`, the session's grid posterior, an array of CoMs
    ``(k, 2)`` (equal weights) or a pair ``(coms (k, 2), weights (k,))``.
    Frictions unknown to the posterior are ``mus`` (default: the
    :class:`comcore.Likelihood` grid), each CoM crossed with each.
    """
    if isinstance(posterior, CoMHypotheses):
        return _checked(posterior, mask)
    if isinstance(posterior, GridPosterior):
        joint = posterior.sense_weights  # (p, m)
        index, w = _systematic(joint.ravel(), n)
        p, m = np.unravel_index(index, joint.shape)
        return CoMHypotheses(posterior.pixels[p], posterior.mus[m], w)
    if isinstance(posterior, Estimate):
        image = None if posterior.posterior is None else posterior.posterior.image
        if image is None:
            coms, cw = np.array([posterior.com], float), np.ones(1)
        else:
            image = np.asarray(image, float)
            if image.shape != mask.shape:
                raise ValueError(
                    f"posterior's image has shape {image.shape}, the mask {mask.shape}: an "
                    "estimate of another mask?"
                )
            rows, cols = np.nonzero(image > 0)
            pixel_w = image[rows, cols]
            index, cw = _systematic(pixel_w / pixel_w.sum(), n)
            coms = np.column_stack([cols[index], rows[index]]).astype(float)
        frictions = estimate_frictions(posterior)
        if frictions is not None and mus is None:
            return _crossed(coms, cw, *frictions, n)
        return _crossed(coms, cw, _friction(mus), None, n)
    return _from_points(posterior, mask, n, _friction(mus))


def estimate_frictions(estimate: Estimate) -> tuple[np.ndarray, np.ndarray] | None:
    """An estimate's friction values and their posterior (summing to 1), or None if it has none."""
    if estimate.posterior is None:
        return None
    grid, weights = estimate.posterior.mu_grid, estimate.posterior.mu_posterior
    grid, weights = np.asarray(grid, float).ravel(), np.asarray(weights, float).ravel()
    if grid.shape != weights.shape or not (np.isfinite(weights).all() and (weights >= 0).all()):
        raise ValueError(
            "the estimate's posterior.mu_posterior must be non-negative weights, one per "
            f"posterior.mu_grid value ({len(grid)}), got {weights.tolist()}"
        )
    if weights.sum() <= 0:
        raise ValueError("the estimate's posterior.mu_posterior must not be all zero")
    return grid, weights / weights.sum()


def _checked(hyps: CoMHypotheses, mask: Mask) -> CoMHypotheses:
    base = _from_points((hyps.coms, hyps.weights), mask, len(hyps.coms), np.array([0.0]))
    mus = np.asarray(hyps.mus, dtype=float)
    if mus.shape != (len(base.coms),) or not np.isfinite(mus).all() or (mus < 0).any():
        raise ValueError(f"CoMHypotheses.mus must be {len(base.coms)} friction values >= 0")
    weights = np.asarray(hyps.weights, dtype=float)
    return CoMHypotheses(np.asarray(hyps.coms, float), mus, weights / weights.sum())


def _friction(mus) -> np.ndarray:
    if mus is None:
        return _default_mus()
    out = np.atleast_1d(np.asarray(mus, float))
    if out.ndim != 1 or not np.isfinite(out).all() or (out < 0).any():
        raise ValueError(f"mus must be friction values >= 0, got {mus!r}")
    return out


def _crossed(coms, cw, grid, mu_w, n) -> CoMHypotheses:
    mu_w = np.full(len(grid), 1.0 / len(grid)) if mu_w is None else mu_w
    joint = (cw[:, None] * mu_w[None, :]).ravel()
    index, w = _systematic(joint / joint.sum(), max(n, 1))
    c, m = np.unravel_index(index, (len(coms), len(grid)))
    return CoMHypotheses(np.asarray(coms, float)[c], grid[m], w)


def _from_points(posterior, mask: Mask, n: int, grid) -> CoMHypotheses:
    weights = None
    if isinstance(posterior, tuple) and len(posterior) == 2:
        posterior, weights = posterior
    try:
        coms = np.asarray(posterior, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(
            "posterior must be a comcore.Estimate, an array of CoMs (k, 2) in pixels or a pair "
            f"(coms, weights), got {type(posterior).__name__}"
        ) from None
    coms = coms.reshape(-1, 2) if coms.shape == (2,) else coms
    if coms.ndim != 2 or coms.shape[1] != 2 or len(coms) == 0 or not np.isfinite(coms).all():
        raise ValueError(f"posterior's CoMs must be finite, shape (k, 2) pixels, got {coms.shape}")
    if weights is None:
        weights = np.full(len(coms), 1.0 / len(coms))
    weights = np.asarray(weights, dtype=float)
    if weights.shape != (len(coms),) or not np.isfinite(weights).all() or (weights < 0).any():
        raise ValueError(f"posterior's weights must be {len(coms)} finite numbers >= 0")
    if weights.sum() <= 0:
        raise ValueError("posterior's weights must not all be zero")
    h, w = mask.shape
    if ((coms < -0.5) | (coms > np.array([w, h]) - 0.5)).any():
        raise ValueError(
            f"posterior's CoMs must lie in the mask's image ({w} x {h} px): pixels, not metres?"
        )
    return _crossed(coms, weights / weights.sum(), grid, None, n)
