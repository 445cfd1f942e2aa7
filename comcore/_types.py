"""Immutable value types: Action, Motion, PushRecord, Estimate and what an estimator attaches."""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, NamedTuple

import numpy as np

from ._status import Status
from .conventions import rotation_sense

__all__ = [
    "OUTCOMES",
    "Action",
    "Estimate",
    "HeatmapDetails",
    "Motion",
    "PathPoint",
    "PosteriorDetails",
    "ProgressiveDetails",
    "PushFrame",
    "PushRecord",
    "SkippedPush",
]


def _finite_float(value, name: str, owner: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{owner}.{name} must be a real number, got {type(value).__name__}")
    out = float(value)
    if not math.isfinite(out):
        raise ValueError(f"{owner}.{name} must be finite, got {out}")
    return out


class _ActionFields(NamedTuple):
    sx: float
    """x (column) of the start of the pusher's leading point, pixels."""
    sy: float
    """y (row, down) of the start of the pusher's leading point, pixels."""
    ex: float
    """x (column) of the end of the pusher's leading point, pixels."""
    ey: float
    """y (row, down) of the end of the pusher's leading point, pixels."""


class _MotionFields(NamedTuple):
    theta: float
    """Rotation in radians, positive counter-clockwise on screen."""
    tx: float
    """Displacement of the mask's area centroid along x (columns), pixels."""
    ty: float
    """Displacement of the mask's area centroid along y (rows, down), pixels."""


class Action(_ActionFields):
    """A push: the straight path of the pusher's leading point in the image, in pixels.

    For a round pusher of radius ``r`` the leading point is the point of the
    disc farthest along the push: it is what touches a flat edge pushed along
    its normal. The disc's centre runs ``r`` behind it on the same line, from
    ``start - r * direction`` to ``end - r * direction``. A robot that moves
    the centre of its pusher must take that offset off both points, or every
    push goes one radius deeper than planned. comcore's samplers
    (:func:`comcore.sample_pushes`), motion model
    (:class:`comcore.LimitSurfaceModel`) and ``simulators`` all read an action
    so; docs/explanation/conventions.md has the conversion. For a point pusher (``r =
    0``) the two coincide.

    Validated on construction: every field must be a finite real number and the
    path must have non-zero length.

    Examples
    --------
    >>> a = Action(0, 10, 20, 10)
    >>> a.direction
    (1.0, 0.0)
    >>> a.length
    20.0

    The path of the centre of a 4 mm disc at 2.5 mm per pixel (1.6 px behind):

    >>> r = 0.004 / 0.0025
    >>> [round(v, 6) for v in (a.sx - r * a.direction[0], a.ex - r * a.direction[0])]
    [-1.6, 18.4]
    >>> Action(1, 1, 1, 1)
    Traceback (most recent call last):
    ...
    ValueError: Action must have non-zero length (start == end == (1.0, 1.0))
    """

    __slots__ = ()

    def __new__(cls, sx, sy, ex, ey):
        vals = [_finite_float(v, n, "Action") for v, n in zip((sx, sy, ex, ey), cls._fields)]
        if math.hypot(vals[2] - vals[0], vals[3] - vals[1]) <= 1e-9:
            raise ValueError(
                f"Action must have non-zero length (start == end == ({vals[0]}, {vals[1]}))"
            )
        return super().__new__(cls, *vals)

    @property
    def start(self) -> tuple[float, float]:
        """The start point ``(sx, sy)``."""
        return (self.sx, self.sy)

    @property
    def end(self) -> tuple[float, float]:
        """The end point ``(ex, ey)``."""
        return (self.ex, self.ey)

    @property
    def length(self) -> float:
        """Length of the path in pixels."""
        return math.hypot(self.ex - self.sx, self.ey - self.sy)

    @property
    def direction(self) -> tuple[float, float]:
        """Unit vector from start to end (pixel frame)."""
        n = self.length
        return ((self.ex - self.sx) / n, (self.ey - self.sy) / n)


class Motion(_MotionFields):
    """The object's answer to a push: a rotation and a translation.

    Examples
    --------
    >>> Motion(0.1, 2.0, -1.0).sense
    1
    >>> Motion(float("nan"), 0, 0)
    Traceback (most recent call last):
    ...
    ValueError: Motion.theta must be finite, got nan
    """

    __slots__ = ()

    def __new__(cls, theta, tx=0.0, ty=0.0):
        vals = [_finite_float(v, n, "Motion") for v, n in zip((theta, tx, ty), cls._fields)]
        return super().__new__(cls, *vals)

    @classmethod
    def identity(cls) -> Motion:
        """The motion that moves nothing, ``Motion(0.0, 0.0, 0.0)``: the first pose.

        Examples
        --------
        >>> Motion.identity()
        Motion(theta=0.0, tx=0.0, ty=0.0)
        >>> Motion.identity() is Motion.identity()
        True
        """
        return _IDENTITY

    @property
    def sense(self) -> int:
        """+1 counter-clockwise, -1 clockwise, 0 for no rotation (no dead band).

        :func:`comcore.conventions.rotation_sense` with ``tol=0``.
        """
        return int(rotation_sense(self.theta, tol=0.0))


_IDENTITY = Motion(0.0, 0.0, 0.0)


class PathPoint(NamedTuple):
    """One pose of the object during a push, as a session scored it (in a :class:`PushRecord`)."""

    travel: float
    """How far (pixels) the pusher had gone along the push as scored (``PushRecord.action``),
    from its start."""
    motion: Motion
    """The object's motion since the push began, in the first mask's frame, about its
    centroid (as ``PushRecord.motion`` is the whole push's)."""
    residual_px: float | None = None
    """The RMS outline residual (pixels) of the registration that measured it (None: a
    motion the caller's tracker gave)."""


class PushFrame(NamedTuple):
    """One camera frame taken during a push, with where the pusher was when it was taken.

    What :meth:`comcore.ActiveSession.observe` takes as ``frames``: the frames a
    camera saw while the object moved, in the order they were taken (the
    mask after the push is the observation itself, not one of them). A plain
    pair ``(pusher, view)`` does as well.

    Examples
    --------
    >>> import comcore
    >>> comcore.PushFrame((12.0, 30.5), comcore.Motion(0.02, 1.5, 0.0)).pusher
    (12.0, 30.5)
    """

    pusher: tuple[float, float]
    """Where the pusher's leading point was (the point whose path an :class:`Action`
    gives), in this frame's camera pixels, as the robot reports it."""
    view: Any
    """The camera's :class:`comcore.Mask` of the object then (registered by the
    session, as its observed masks are), or the object's :class:`Motion` since
    the push began (camera frame, about the object's centroid before the push,
    as ``observe(motion=...)``), for a caller with its own tracker."""
class SkippedPush(NamedTuple):
    """One push that could not be used, and why."""

    index: int
    """Position of the push in the input."""
    name: str
    """Its name, or ``""``."""
    reason: str
    """``"starts_inside"`` (the pusher's disc starts inside the outline, or the action's
    start falls on the mask), ``"misses"`` (the disc never comes within the contact
    tolerance of the outline, or misses the drawn mask), ``"short"`` (the pusher travels
    less than the window after first contact) or ``"no_object_pose"`` (the object's stream
    does not cover the window)."""
    detail: str
    """A sentence with the numbers."""


#: What a reported push did: it moved the object (``"evidence"``), it did not
#: (``"miss"``: below the tracking noise), or it could not be executed (``"failed"``).
OUTCOMES = ("evidence", "miss", "failed")


@dataclass(frozen=True)
class PushRecord:
    """One push an active estimator made or was told about: what was planned, done and seen.

    :class:`Estimate.pushes <Estimate>` holds one per push, in order; passing
    them back (``comcore.estimate_posterior(mask, pushes=est.pushes)``)
    replays the posterior that scored them. Every length is in pixels of the
    first mask; ``action`` and ``motion`` are in the object's frame (the first
    mask's), however the object moved.

    Attributes
    ----------
    action : Action
        The push as scored, in the first mask's frame: the path executed where
        the robot said where its pusher went (``executed``), else the one
        planned (``planned``).
    motion : Motion or None
        The object's motion in the first mask's frame, about its centroid
        (None for a failed push).
    outcome : {"evidence", "miss", "failed"}
        What the push did (:data:`OUTCOMES`).
    index : int or None
        The candidate it was (an index into the session's candidates), or its
        position among recorded pushes.
    planned : Action or None
        The push as planned, in the first mask's frame (None: as ``action``).
    camera_action : Action or None
        The push as handed to the robot, in the camera frame at ``pose_before``
        (None offline).
    camera_motion : Motion or None
        The motion as the camera saw it, about the object's centroid at the time.
    pose_before : Motion
        The object's pose before the push, relative to the first mask.
    rotation_observed : bool
        False where the camera could not tell the rotation (a symmetric outline
        read ambiguously): neither its sense nor its size is scored.
    residual_px : float or None
        The RMS outline residual of the registration that measured the motion
        (None: not measured from masks).
    symmetry : int
        Order of the outline's rotational symmetry the registration saw (1: none).
    log_evidence : float or None
        The log-probability the posterior before the push gave its motion (its
        evidence, nats); None for a miss or a failed push.
    path : tuple of PathPoint
        The object's poses during the push that were scored (from the frames
        given to ``observe(..., frames=...)``; empty without frames).
    dropped_frames : tuple of (int, str)
        The frames given that were not scored: their index among those given
        and why (:mod:`comcore.active._path`).
    """

    action: Action
    motion: Motion | None
    outcome: str
    index: int | None = None
    planned: Action | None = None
    camera_action: Action | None = None
    camera_motion: Motion | None = None
    pose_before: Motion = _IDENTITY
    rotation_observed: bool = True
    residual_px: float | None = None
    symmetry: int = 1
    log_evidence: float | None = None
    path: tuple = ()
    dropped_frames: tuple = ()

    def __post_init__(self):
        if self.outcome not in OUTCOMES:
            raise ValueError(f"PushRecord.outcome must be one of {OUTCOMES}, got {self.outcome!r}")
        set_ = object.__setattr__
        set_(self, "action", Action(*self.action))
        for name, kind in (("planned", Action), ("camera_action", Action),
                           ("motion", Motion), ("camera_motion", Motion)):
            value = getattr(self, name)
            if value is not None:
                set_(self, name, kind(*value))
        if self.motion is None and self.outcome != "failed":
            raise ValueError(
                f"PushRecord.motion is needed for a push with outcome {self.outcome!r}"
            )
        set_(self, "pose_before", Motion(*self.pose_before))
        if self.residual_px is not None:
            residual = _finite_float(self.residual_px, "residual_px", "PushRecord")
            if residual < 0:
                raise ValueError(f"PushRecord.residual_px must be >= 0 or None, got {residual}")
            set_(self, "residual_px", residual)
        set_(self, "rotation_observed", bool(self.rotation_observed))
        set_(self, "path", _path_points(self.path))
        set_(self, "dropped_frames", tuple((int(i), str(why)) for i, why in self.dropped_frames))


def _path_point(travel, motion, residual_px=None) -> PathPoint:
    travel = _finite_float(travel, "path travel", "PushRecord")
    if residual_px is not None:
        residual_px = _finite_float(residual_px, "path residual_px", "PushRecord")
    return PathPoint(travel, Motion(*motion), residual_px)


def _path_points(path) -> tuple:
    """``PushRecord.path`` as PathPoints, their travel finite and non-decreasing."""
    try:
        points = tuple(_path_point(*p) for p in path)
    except (TypeError, ValueError) as e:
        raise type(e)(f"PushRecord.path must be (travel, motion) pairs: {e}") from e
    travel = [p.travel for p in points]
    if any(b < a for a, b in itertools.pairwise(travel)):
        raise ValueError(f"PushRecord.path's travel must not decrease, got {travel}")
    return points


def readonly(values, dtype=None) -> np.ndarray:
    """A read-only copy of ``values``, for the arrays a frozen record holds.

    The caller's array is never changed (the copy is made first), and the
    record's own cannot be changed after it is built.

    Parameters
    ----------
    values : array_like
    dtype : numpy dtype, optional
        Of the copy (default: as ``numpy.array`` infers it).

    Examples
    --------
    >>> import numpy as np
    >>> from comcore.checks import readonly
    >>> given = np.zeros(3)
    >>> held = readonly(given, float)
    >>> held.flags.writeable, given.flags.writeable
    (False, True)
    """
    out = np.array(values, dtype=dtype, copy=True)
    out.setflags(write=False)
    return out


def _check_pair(value, name: str) -> tuple[float, float]:
    """``value`` as two finite floats ``(x, y)``, or a named error."""
    try:
        pair = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        pair = ()
    if len(pair) != 2 or not all(map(math.isfinite, pair)):
        raise ValueError(f"{name} must be two finite numbers (x, y), got {value!r}")
    return pair  # type: ignore[return-value]


def _check_covariance(value) -> np.ndarray:
    """``value`` as a finite symmetric 2 x 2 array, variances >= 0, or a named error."""
    try:
        cov = np.array(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise ValueError(f"Estimate.covariance must be a 2 x 2 array of numbers; {e}") from e
    if cov.shape != (2, 2):
        raise ValueError(f"Estimate.covariance must have shape (2, 2), got {cov.shape}")
    if not np.isfinite(cov).all():
        raise ValueError(f"Estimate.covariance must be finite, got {cov.tolist()}")
    if not np.isclose(cov[0, 1], cov[1, 0], rtol=1e-9, atol=1e-12) or (np.diag(cov) < 0).any():
        raise ValueError(
            "Estimate.covariance must be symmetric with variances >= 0 on its diagonal, got "
            f"{cov.tolist()}"
        )
    return cov


def _check_region(region) -> np.ndarray:
    """``region`` as a 2-D boolean array, or a named error."""
    try:
        arr = np.asarray(region)
    except (TypeError, ValueError) as e:  # ragged nested sequences
        raise ValueError(f"Estimate.region must be a 2-D image of shape (H, W): {e}") from e
    if arr.dtype != bool and not np.issubdtype(arr.dtype, np.number):
        raise TypeError(f"Estimate.region must be an image of booleans, got dtype {arr.dtype}")
    if arr.ndim != 2 or 0 in arr.shape:
        raise ValueError(
            f"Estimate.region must be a 2-D image of shape (H, W) (the mask's), got shape "
            f"{arr.shape}"
        )
    if arr.dtype != bool:
        odd = arr[(arr != 0) & (arr != 1)]  # NaN is neither
        if odd.size:
            raise ValueError(
                "Estimate.region must hold booleans (or the numbers 0 and 1), got "
                f"{odd.size} other value(s), e.g. {odd.flat[0]}"
            )
    return arr.astype(bool)


@dataclass(frozen=True)
class HeatmapDetails:
    """What Alg. 1 (:func:`comcore.estimate_heatmap`) computed: :attr:`Estimate.heatmap`.

    Attributes
    ----------
    image : numpy.ndarray of float, shape (H, W)
        The heat map ``S``: each pixel's distance-weighted rotation (read-only).
    segmented : numpy.ndarray of bool, shape (H, W)
        The object's pixels below the threshold, before the connected-component
        step (read-only).
    """

    image: np.ndarray
    segmented: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "image", readonly(np.asarray(self.image, float)))
        object.__setattr__(self, "segmented", readonly(np.asarray(self.segmented, bool)))


@dataclass(frozen=True)
class ProgressiveDetails:
    """How Alg. 2 (:func:`comcore.estimate_progressive`) cut: :attr:`Estimate.progressive`.

    Attributes
    ----------
    region_sizes : tuple of int
        The region's size in pixels after each applied cut, the object's first.
    contradicted : tuple of int
        The pushes whose sense no pixel of the region explains (skipped ones
        first, in the order met); when any, the status is ``"inconsistent"``
        and the estimate rests on the others.
    """

    region_sizes: tuple[int, ...] = ()
    contradicted: tuple[int, ...] = ()

    def __post_init__(self):
        object.__setattr__(self, "region_sizes", tuple(int(v) for v in self.region_sizes))
        object.__setattr__(self, "contradicted", tuple(int(v) for v in self.contradicted))


@dataclass(frozen=True)
class PosteriorDetails:
    """The posterior behind an active estimate: :attr:`Estimate.posterior`.

    Set by :func:`comcore.estimate_posterior`, :func:`comcore.estimate_active`,
    :meth:`comcore.ActiveSession.estimate` and :meth:`comcore.GoalSession.estimate`.
    Arrays are read-only; lengths are in pixels of the first mask.

    Attributes
    ----------
    image : numpy.ndarray of float, shape (H, W)
        The posterior probability of each pixel being the CoM (sums to 1).
    region_image : numpy.ndarray of float, shape (H, W)
        What the credible region was read from: ``image``, blurred by the
        likelihood's systematic error or bagged where the estimator did so
        (:func:`comcore.credible_level` reads it).
    credible_radius_px : float
        Equivalent-circle radius ``sqrt(area / pi)`` of the credible region.
    mu_grid : numpy.ndarray, shape (m,)
        The contact friction values marginalised over.
    mu_posterior : numpy.ndarray, shape (m,)
        Their posterior.
    model_posterior : numpy.ndarray, shape (k,)
        The posterior over the predictor's motion models.
    scale_posterior : numpy.ndarray
        The posterior over ``Likelihood.model_scales``.
    model_weight_posterior : numpy.ndarray
        The posterior over the powers of ``Likelihood.model_weight``.
    log_evidence : float
        Log marginal likelihood of the motions (nats).
    excess_nats : float
        The best hypothesis' excess surprise (above ``10 + 6 sqrt(n)``: the
        status is ``"inconsistent"``).
    history : tuple of SessionState
        The state of every posterior, the prior first
        (:class:`comcore.active.SessionState`: mean, entropy, credible radius,
        evidence, counts).
    senses : SenseCheck or None
        :func:`comcore.estimate_posterior`'s check of the observed senses
        (:class:`comcore.active.SenseCheck`); None for the sessions.
    bootstrap : int
        Resamplings the region was bagged over (0: the posterior's own region).
    pose : Motion or None
        The object's pose when a session made the estimate, relative to the
        first mask; None for :func:`comcore.estimate_posterior`.
    """

    image: np.ndarray
    region_image: np.ndarray
    credible_radius_px: float
    mu_grid: np.ndarray
    mu_posterior: np.ndarray
    model_posterior: np.ndarray
    scale_posterior: np.ndarray
    model_weight_posterior: np.ndarray
    log_evidence: float
    excess_nats: float
    history: tuple = ()
    senses: Any = None
    bootstrap: int = 0
    pose: Motion | None = None

    def __post_init__(self):
        set_ = object.__setattr__
        for name in ("image", "region_image", "mu_grid", "mu_posterior", "model_posterior",
                     "scale_posterior", "model_weight_posterior"):
            set_(self, name, readonly(np.asarray(getattr(self, name), float)))
        for name in ("credible_radius_px", "log_evidence", "excess_nats"):
            set_(self, name, float(getattr(self, name)))
        set_(self, "history", tuple(self.history))
        set_(self, "bootstrap", int(self.bootstrap))
        if self.pose is not None:
            set_(self, "pose", Motion(*self.pose))


@dataclass(frozen=True)
class Estimate:
    """The result of every estimator.

    An estimator that cannot do its job (no usable action, contradictory
    observations, a zero budget) still returns an ``Estimate``: ``ok`` is then
    ``False``, ``status`` says why, and ``com`` holds the documented fallback
    (usually the mask's area centroid). It never returns NaN.

    Attributes
    ----------
    com : tuple of float
        Estimated CoM ``(x, y)`` in pixels.
    com_m : tuple of float
        The same in metres in the mask frame (``resolution * (x, y)``).
    region : numpy.ndarray of bool, shape (H, W)
        The CoM region the estimate is the mean of (read-only): a 2-D image
        of the mask's shape, booleans (or the numbers 0 and 1).
    used : tuple of int
        Indices of the actions the estimator used, in the order it used them.
    status : Status
        ``Status.OK`` (``"ok"``: the data were consistent and the region
        reached the target radius) or why not (``"wide"``: consistent, the
        region wider); :class:`comcore.Status` says what each
        member means. A string is taken if it is a member's.
    covariance : numpy.ndarray, shape (2, 2), or None
        Covariance of the CoM in pixels squared, where the estimator has one.
    extras : Mapping[str, Any]
        Free-form information a caller attached (``comcore bench`` notes the
        robot's pose there), read-only; nothing in comcore reads it.
    pushes : tuple of PushRecord
        The active estimators' pushes, in order (misses and failed pushes
        included); empty for the others.
    skipped : tuple of SkippedPush
        The pushes an estimator could not use, and why (Alg. 2 and
        :func:`comcore.estimate_posterior` with a round pusher).
    heatmap : HeatmapDetails or None
        Alg. 1's heat map (:func:`comcore.estimate_heatmap`).
    progressive : ProgressiveDetails or None
        Alg. 2's cuts (:func:`comcore.estimate_progressive`).
    posterior : PosteriorDetails or None
        The posterior of the active estimators and :func:`comcore.estimate_posterior`.

    Examples
    --------
    >>> import numpy as np
    >>> e = Estimate(com=(1.0, 2.0), com_m=(0.01, 0.02), region=np.ones((3, 3), bool))
    >>> e.ok, e.region.flags.writeable
    (True, False)
    >>> Estimate(com=(1.0, 2.0), com_m=(0.01, 0.02), region=np.ones(4, bool))
    Traceback (most recent call last):
    ...
    ValueError: Estimate.region must be a 2-D image of shape (H, W) (the mask's), got shape (4,)
    """

    com: tuple[float, float]
    com_m: tuple[float, float]
    region: np.ndarray
    used: tuple[int, ...] = ()
    status: Status = Status.OK
    covariance: np.ndarray | None = None
    extras: Mapping[str, Any] = field(default_factory=dict)
    pushes: tuple = ()
    skipped: tuple = ()
    heatmap: HeatmapDetails | None = None
    progressive: ProgressiveDetails | None = None
    posterior: PosteriorDetails | None = None

    def __post_init__(self):
        object.__setattr__(self, "com", _check_pair(self.com, "Estimate.com"))
        object.__setattr__(self, "com_m", _check_pair(self.com_m, "Estimate.com_m"))
        object.__setattr__(self, "region", readonly(_check_region(self.region)))
        object.__setattr__(self, "used", tuple(int(i) for i in self.used))
        object.__setattr__(self, "status", Status.check(self.status, "Estimate.status"))
        if self.covariance is not None:
            object.__setattr__(self, "covariance", readonly(_check_covariance(self.covariance)))
        extras = {}
        for key, value in dict(self.extras).items():
            extras[key] = readonly(value) if isinstance(value, np.ndarray) else value
        object.__setattr__(self, "extras", MappingProxyType(extras))
        pushes = tuple(self.pushes)
        if not all(isinstance(p, PushRecord) for p in pushes):
            raise TypeError("Estimate.pushes must hold comcore.PushRecord values")
        object.__setattr__(self, "pushes", pushes)
        skipped = tuple(self.skipped)
        if not all(isinstance(p, SkippedPush) for p in skipped):
            raise TypeError("Estimate.skipped must hold comcore.SkippedPush values")
        object.__setattr__(self, "skipped", skipped)
        for name, kind in (("heatmap", HeatmapDetails), ("progressive", ProgressiveDetails),
                           ("posterior", PosteriorDetails)):
            value = getattr(self, name)
            if value is not None and not isinstance(value, kind):
                raise TypeError(
                    f"Estimate.{name} must be a {kind.__name__} or None, got {type(value).__name__}"
                )

    @property
    def ok(self) -> bool:
        """``True`` when the estimator worked as intended (``status == "ok"``)."""
        return self.status is Status.OK

    def error_px(self, true_com) -> float:
        """Euclidean distance in pixels from ``com`` to ``true_com`` ``(x, y)``."""
        t = np.asarray(true_com, dtype=float)
        return float(np.hypot(self.com[0] - t[0], self.com[1] - t[1]))

    def region_holds(self, point) -> bool:
        """Whether the pixel under ``point`` ``(x, y)`` lies in ``region``.

        The pixel is the one whose centre is nearest (x = column, y = row);
        a point outside the image is not held.

        >>> import numpy as np
        >>> region = np.zeros((4, 5), bool)
        >>> region[1, 3] = True
        >>> e = Estimate(com=(3.0, 1.0), com_m=(0.0, 0.0), region=region)
        >>> e.region_holds((3.2, 0.8)), e.region_holds((1.0, 3.0)), e.region_holds((-7, 1))
        (True, False, False)
        """
        col, row = (round(float(v)) for v in np.asarray(point, dtype=float).reshape(2))
        h, w = self.region.shape
        return bool(0 <= row < h and 0 <= col < w and self.region[row, col])
