"""Mason's Voting Theorem: the sense of rotation and the CoM region it implies.

Three rays leave the contact point: the two edges of the friction cone,
``R_L`` and ``R_R`` (the inward normal turned by +/- ``atan(mu)``), and the
push direction ``R_P``. Each votes the sense of the moment its line has about
the CoM; the majority wins (Mason 1986). When the CoM lies outside the
friction cone both edges agree and decide; inside it they disagree and the
push direction decides.

Choices (the paper is silent on them):

* A vote is 0 when the CoM lies within ``band`` pixels of the ray's line, and
  the sense is the sign of the sum of the three votes: a tie (0) means pure
  translation. With ``band = 0`` this is exactly Mason's majority.
* The region for an observed sense keeps every pixel for which that sense, or
  a tie, is possible for SOME ``mu`` in the given range. Pixels on a deciding
  line (within ``band``) are therefore kept on both sides; the true CoM is
  never excluded by discretisation.
* ``mu = None`` means unknown: any ``mu >= 0``, i.e. cone half-angles in
  ``[0, pi/2]`` (the closed end is the limit ``mu -> inf``).
"""

from __future__ import annotations

import math

import numpy as np

from .._mask import Mask
from .._validation import (
    check_actions,
    check_mask,
    check_mu,
    check_physical,
    check_point,
    check_points,
    check_positive,
)
from ..conventions import (
    ANGLE_EPS,
    DEFAULT_PUSHER_RADIUS,
    _ccw_cross,
    ccw_cross,
    rotate_vectors,
    rotation_sense,
)
from ..geometry._disc_contacts import pusher_contacts

__all__ = [
    "LINE_SCALE_PX",
    "UNEXPLAINED_STDS",
    "SenseTally",
    "consistent",
    "force_line_distances",
    "force_lines",
    "predicted_sense",
    "push_force_lines",
    "region",
    "side_probability",
]


def _unit(v, name: str) -> np.ndarray:
    """One non-zero finite 2-vector, normalised; shape (2,)."""
    try:
        v = np.asarray(v, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be a 2-vector of real numbers; {e}") from e
    if v.shape != (2,):
        raise ValueError(f"{name} must be a single 2-vector, shape (2,), got shape {v.shape}")
    if not np.isfinite(v).all():
        raise ValueError(f"{name} must be finite")
    norm = float(np.hypot(v[0], v[1]))
    if norm <= 1e-12:
        raise ValueError(f"{name} must be a non-zero vector")
    return v / norm


def _moments(r, normal, push_dir, alpha):
    """Moments (signed distances) of the three rays' lines about CoMs at ``contact - r``.

    ``r``: (m, 2); ``alpha``: scalar or (m, k) cone half-angles. Returns the
    left edge, right edge and push moments, broadcast to a common shape.
    """
    across = _ccw_cross(r, normal)  # |r| sin(phi), phi = angle from r to the normal
    along = r @ normal  # |r| cos(phi)
    alpha = np.asarray(alpha, dtype=float)
    push = _ccw_cross(r, push_dir)
    if alpha.ndim == 2:
        across, along, push = across[:, None], along[:, None], push[:, None]
    cos_a, sin_a = np.cos(alpha), np.sin(alpha)
    left = across * cos_a + along * sin_a  # |r| sin(phi + alpha)
    right = across * cos_a - along * sin_a  # |r| sin(phi - alpha)
    return np.broadcast_arrays(left, right, push)


def _vote(moment, band: float) -> np.ndarray:
    """+1 / -1 by the sign of a moment; 0 (abstain) within ``band`` (int8)."""
    return (moment > band).view(np.int8) - (moment < -band).view(np.int8)


def _majority(left, right, push, band: float) -> np.ndarray:
    """Sign of the sum of the three votes; a ray within ``band`` of the CoM abstains."""
    return np.sign(_vote(left, band) + _vote(right, band) + _vote(push, band)).astype(int)


def predicted_sense(com, contact, normal, push_dir, mu, band: float = 0.0) -> np.ndarray:
    """Sense of rotation predicted by the Voting Theorem for CoM candidates.

    Parameters
    ----------
    com : array_like, shape (m, 2) or (2,)
        CoM candidates ``(x, y)`` in pixels.
    contact : array_like, shape (2,)
        Contact point in pixels.
    normal : array_like, shape (2,)
        Inward normal of the object at the contact (normalised here).
    push_dir : array_like, shape (2,)
        Direction of the pusher's motion (normalised here).
    mu : float
        Coefficient of friction at the contact (>= 0; ``inf`` allowed).
    band : float, optional
        A ray whose line passes within ``band`` pixels of the CoM abstains.

    Returns
    -------
    numpy.ndarray of int, shape (m,) or ()
        +1 counter-clockwise, -1 clockwise, 0 pure translation.

    Raises
    ------
    ValueError
        If ``contact``, ``normal`` or ``push_dir`` is not a single finite
        2-vector of shape (2,) (one push at a time: a stack of normals is
        refused, not broadcast), a direction is zero, ``mu`` is a range, or
        ``band`` is negative or not finite.

    Examples
    --------
    Pushing right (+x) along the normal of a left edge at row 5: a CoM above
    the push line (row 3) turns the object counter-clockwise on screen.

    >>> predicted_sense([[5, 3], [5, 7], [5, 5]], (0, 5), (1, 0), (1, 0), mu=0.3).tolist()
    [1, -1, 0]
    """
    com_arr = np.asarray(com, dtype=float)
    single = com_arr.shape == (2,)
    pts = check_points(com_arr, "com")
    c = check_point(contact, "contact")
    n = _unit(normal, "normal")
    v = _unit(push_dir, "push_dir")
    mu = _single_mu(mu)
    band = check_positive(band, "band", allow_zero=True)
    left, right, push = _moments(c - pts, n, v, np.arctan(mu))
    out = _majority(left, right, push, band)
    return out[0] if single else out


def _single_mu(mu) -> float:
    """One friction coefficient >= 0, ``inf`` included (a cone half-angle of pi/2)."""
    is_number = isinstance(mu, (int, float, np.integer, np.floating)) and not isinstance(mu, bool)
    if is_number and float(mu) == np.inf:
        return np.inf
    if mu is None:
        raise ValueError("mu must be a single value for predicted_sense, got None (unknown)")
    lo, hi = check_mu(mu)
    if lo != hi:
        raise ValueError(f"mu must be a single value for predicted_sense, got range ({lo}, {hi})")
    return lo


def consistent(
    points, contact, normal, push_dir, sense, mu=None, *, band: float = 0.5
) -> np.ndarray:
    """Which CoM candidates can produce ``sense`` (or a tie) for some ``mu`` in range.

    The (strict) vote changes with the cone half-angle ``alpha = atan(mu)``
    only where a cone edge's line crosses the candidate, so evaluating at the
    range's ends, at that crossing and between them covers every ``mu``
    exactly. The ``band`` margin is checked at the same five angles.

    Parameters
    ----------
    points : array_like, shape (m, 2)
        CoM candidates in pixels.
    contact, normal, push_dir : array_like, shape (2,)
    sense : int
        Observed sense: +1, -1 or 0.
    mu : None, float or (lo, hi), optional
        Contact friction: unknown (default), known, or a range.
    band : float, optional
        Pixels within ``band`` of a deciding line are kept (default 0.5 px).

    Returns
    -------
    numpy.ndarray of bool, shape (m,)
    """
    pts = check_points(points, "points")
    c = check_point(contact, "contact")
    n = _unit(normal, "normal")
    v = _unit(push_dir, "push_dir")
    if sense not in (-1, 0, 1):
        raise ValueError(f"sense must be -1, 0 or +1, got {sense!r}")
    lo, hi = check_mu(mu)
    band = check_positive(band, "band", allow_zero=True)
    a_lo, a_hi = float(np.arctan(lo)), float(np.arctan(hi))
    return _consistent(c - pts, n, v, sense, a_lo, a_hi, band=band)


def _consistent(r, normal, push_dir, sense, a_lo, a_hi, *, band) -> np.ndarray:
    """Unvalidated core of :func:`consistent`; ``r = contact - candidates``, (m, 2).

    Over cone half-angles ``alpha`` in [0, pi/2] exactly one cone edge's line
    crosses a candidate, at ``alpha* = atan(|across| / |along|)`` (the
    candidate's offset across and along the normal); the strict vote is
    constant on either side of it. Evaluating at the range's ends, at
    ``alpha*`` and halfway between them therefore covers every ``mu`` in range
    for the strict vote. The ``band`` allowance (a ray within ``band`` abstains)
    is evaluated at the same five angles, so it can miss a pixel whose edges
    pass within ``band`` only between them: a pixel the strict vote allows is
    never lost, only some of the extra margin.

    ``alpha*`` and the midpoints enter through their cosines and sines, from
    the offsets and the half-angle formulas: per-pixel trigonometry cost more
    than everything else here together. At ``alpha*`` the deciding edge's
    moment is then exactly 0, as it is mathematically.
    """
    senses = np.array([sense])
    return _consistent_many(r[None], normal[None], push_dir[None], senses, a_lo, a_hi, band=band)[0]


def _consistent_many(r, normal, push_dir, sense, a_lo, a_hi, *, band) -> np.ndarray:
    """:func:`_consistent` for k pushes at once, bit for bit; (k, m) bool.

    ``r`` is (k, m, 2), ``normal`` and ``push_dir`` (k, 2), ``sense`` (k,) ints.
    """
    n, d = normal[:, None, :], push_dir[:, None, :]
    across = -(r[..., 0] * n[..., 1] - r[..., 1] * n[..., 0])  # _ccw_cross(r, normal)
    along = np.matmul(r, normal[:, :, None])[..., 0]  # r @ normal, as _moments computes it
    push = -(r[..., 0] * d[..., 1] - r[..., 1] * d[..., 0])  # _ccw_cross(r, push_dir)
    c_lo, s_lo, c_hi, s_hi = np.cos(a_lo), np.sin(a_lo), np.cos(a_hi), np.sin(a_hi)
    hyp = np.hypot(across, along)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos_c, sin_c = np.abs(along) / hyp, np.abs(across) / hyp  # alpha* unclipped
    below = ~(cos_c <= c_lo)  # alpha* < a_lo, or the contact itself (0 / 0)
    above = cos_c < c_hi  # alpha* > a_hi
    cos_c[below], sin_c[below] = c_lo, s_lo
    cos_c[above], sin_c[above] = c_hi, s_hi
    push_strict, push_tolerant = _vote(push, 0.0), _vote(push, band)
    s = np.asarray(sense, dtype=int)[:, None]
    ok = np.zeros(across.shape, dtype=bool)
    for cos_a, sin_a in (
        (c_lo, s_lo),
        _half_sum(c_lo, s_lo, cos_c, sin_c),
        (cos_c, sin_c),
        _half_sum(cos_c, sin_c, c_hi, s_hi),
        (c_hi, s_hi),
    ):
        a, b = across * cos_a, along * sin_a
        left, right = a + b, a - b  # |r| sin(phi + alpha), |r| sin(phi - alpha)
        strict = _vote(left, 0.0) + _vote(right, 0.0) + push_strict
        tolerant = _vote(left, band) + _vote(right, band) + push_tolerant
        # the sign of a sum of votes is `sense` (or a tie) without taking the sign
        ok |= np.where(
            s == 0, (strict == 0) | (tolerant == 0), (s * strict > 0) | (s * tolerant >= 0)
        )
    return ok


def _half_sum(cos_x, sin_x, cos_y, sin_y):
    """Cosine and sine of ``(x + y) / 2`` for angles in [0, pi/2] (both >= 0)."""
    cos_sum = np.clip(cos_x * cos_y - sin_x * sin_y, -1.0, 1.0)
    return np.sqrt(0.5 * (1.0 + cos_sum)), np.sqrt(0.5 * (1.0 - cos_sum))


def _thetas(theta, single: bool) -> np.ndarray:
    """Rotations from floats, Motions or (n, 3) motion arrays, as a flat array."""
    try:
        th = np.asarray(theta, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"theta must be a number, a Motion or an array of them; {e}") from e
    if th.ndim == 2 and th.shape[1] == 3:
        th = th[:, 0]
    elif single and th.shape == (3,):
        th = th[:1]
    return th.reshape(-1)


def region(
    mask: Mask,
    action,
    theta,
    mu=None,
    band: float = 0.5,
    theta_tol: float = ANGLE_EPS,
    *,
    pusher_radius: float = DEFAULT_PUSHER_RADIUS,
):
    """The CoM positions on the mask consistent with an observed rotation.

    Parameters
    ----------
    mask : Mask
    action : Action or array_like, shape (4,) or (n, 4)
        The push(es). Each must start outside the object and hit it.
    theta : float, Motion, or array_like, shape (n,) or (n, 3)
        Observed rotation(s) in radians (only the sign is used); a Motion or a
        motions array is accepted.
    mu : None, float or (lo, hi), optional
        Contact friction: unknown (default, any ``mu >= 0``), known, or a
        range. With a range or None the region is the union over ``mu``, so it
        always contains the true CoM when the true ``mu`` is in range.
    band : float, optional
        Pixels within ``band`` of a deciding line are kept on both sides
        (the paper's ``d_t``, default 0.5 px); finite and >= 0.
    theta_tol : float, optional
        ``|theta| <= theta_tol`` counts as no rotation (sense 0); finite and
        >= 0.
    pusher_radius : float, optional
        Radius (metres) of a round pusher: the contact is where its disc first
        touches the object (:func:`comcore.geometry.disc_contacts`); default
        :data:`comcore.conventions.DEFAULT_PUSHER_RADIUS` (4 mm); 0: a point on the
        leading line.

    Returns
    -------
    numpy.ndarray of bool, shape (H, W) for one action, (n, H, W) for a batch

    Raises
    ------
    ValueError
        If an action misses the object or starts inside it, the numbers of
        actions and rotations differ, or ``band`` or ``theta_tol`` is negative
        or not finite.

    Examples
    --------
    A push along the normal: the region is the half of the object on the side
    the rotation says, plus the pixels on the push line.

    >>> import numpy as np
    >>> from comcore import Mask, Action
    >>> m = Mask(np.pad(np.ones((5, 5), bool), 1))
    >>> r = region(m, Action(-2, 3, 2, 3), theta=0.1)
    >>> r[1:6, 1:6].astype(int)
    array([[1, 1, 1, 1, 1],
           [1, 1, 1, 1, 1],
           [1, 1, 1, 1, 1],
           [0, 0, 0, 0, 0],
           [0, 0, 0, 0, 0]])
    """
    mask = check_mask(mask)
    acts = check_actions(action, "action", allow_empty=False)
    single = np.ndim(action) == 1
    th = _thetas(theta, single)
    if th.shape[0] != acts.shape[0]:
        raise ValueError(
            f"theta must have one value per action: expected {acts.shape[0]}, got {th.shape[0]}"
        )
    if not np.isfinite(th).all():
        raise ValueError("theta must be finite")
    band = check_positive(band, "band", allow_zero=True)
    theta_tol = check_positive(theta_tol, "theta_tol", allow_zero=True)
    senses = rotation_sense(th, theta_tol)
    pusher_radius = check_physical(
        pusher_radius, "pusher_radius", "pusher_radius", allow_zero=True
    )
    con = pusher_contacts(mask, acts, pusher_radius)
    con.require_hits("action")
    out = np.zeros((acts.shape[0], *mask.shape), dtype=bool)
    rows, cols = mask.pixels[:, 1].astype(int), mask.pixels[:, 0].astype(int)
    direction = acts[:, 2:] - acts[:, :2]
    a_lo, a_hi = (float(np.arctan(v)) for v in check_mu(mu))
    unit = direction / np.hypot(direction[:, 0], direction[:, 1])[:, None]
    for i in range(acts.shape[0]):
        r = con.point[i] - mask.pixels
        ok = _consistent(r, con.normal[i], unit[i], int(senses[i]), a_lo, a_hi, band=band)
        out[i, rows[ok], cols[ok]] = True
    return out[0] if single else out


#: Standard deviation of a logistic of unit scale (its scale is std * sqrt(3) / pi).
_LOGISTIC_STD = math.pi / math.sqrt(3.0)
#: A hypothesis leaves a push's observed sense unexplained when it lies more than this many
#: standard deviations of the force line's blur on the wrong side of the line (the logistic
#: edge then gives the observed sense 2.6 % before ``flip_prob``).
UNEXPLAINED_STDS = 2.0


class SenseTally:
    """How many pushes' observed senses each (CoM, friction) hypothesis leaves unexplained.

    The Voting Theorem's check of recorded pushes, with or without a motion
    model: a push is unexplained by a hypothesis that lies more than
    :data:`UNEXPLAINED_STDS` standard deviations of the force line's blur on
    the wrong side of its force line. Under the hypothesis that made the
    pushes, push ``i`` is unexplained with probability at most
    ``allowed[i]``: its sense's flip probability (``flip_prob``, more for a
    rotation within the tracking noise of zero: :func:`sense_flip_prob`)
    plus the edge's 2.6 %. The stop rule compares the fewest unexplained
    pushes with those probabilities (:func:`comcore.active._stop.sense_check`).

    Examples
    --------
    Two pushes whose senses put the CoM on opposite sides of one line: every
    hypothesis leaves one of them unexplained.

    >>> tally = SenseTally((3, 1))
    >>> distances = np.array([[-9.0], [0.0], [9.0]])  # three CoMs, one friction value
    >>> tally.add(distances, +1, 0.05, 1.0)
    >>> tally.add(distances, -1, 0.05, 1.0)
    >>> tally.counts[:, 0].tolist(), tally.fewest, len(tally.allowed)
    ([1, 0, 1], 0, 2)
    """

    def __init__(self, shape: tuple[int, int]):
        self.counts = np.zeros(shape, dtype=np.int64)
        self.allowed: list[float] = []

    def add(self, distances, sense: int, flip_prob: float, scale: float) -> None:
        """Count one push of observed ``sense`` (0: none, not counted) at ``distances`` (p, m).

        ``flip_prob`` is the probability its sense is wrong, ``scale`` the
        force line's logistic scale (pixels).
        """
        if sense == 0:
            return
        margin = UNEXPLAINED_STDS * _LOGISTIC_STD * scale
        self.counts += np.asarray(sense * distances < -margin)
        edge = 1.0 / (1.0 + math.exp(UNEXPLAINED_STDS * _LOGISTIC_STD))
        self.allowed.append(flip_prob + (1.0 - 2.0 * flip_prob) * edge)

    @property
    def fewest(self) -> int:
        """The fewest pushes any hypothesis leaves unexplained (0 before any)."""
        return int(self.counts.min()) if self.counts.size else 0

    def at_pixel(self, index: int) -> int:
        """The fewest pushes a CoM at grid pixel ``index`` leaves unexplained, any friction."""
        return int(self.counts[index].min())


#: Scale (pixels) of the soft edge of a force line at the default 2.5 mm/px and
#: an exact pusher (the estimators derive it from metres: ``LINE_BLUR_M`` and
#: ``pusher_error`` in :mod:`comcore.active._likelihood`). The Voting Theorem's sense
#: is taken to be wrong for a CoM at distance d from the line with probability
#: ``1 / (1 + exp(|d| / scale))`` (plus ``flip_prob``): pixel outlines, the
#: smoothed normal, the pusher's radius and the object turning during the push
#: blur the line (how often the sense is wrong at each distance, measured against
#: the simulator: docs/explanation/likelihood.md, "The line is soft").
LINE_SCALE_PX = 1.2


def push_force_lines(con, actions, mus) -> np.ndarray:
    """Force lines (n, m, 3) of pushes that hit, from their contacts, for each friction value."""
    actions = np.asarray(actions, dtype=float)
    direction = actions[:, 2:] - actions[:, :2]
    direction = direction / np.hypot(direction[:, 0], direction[:, 1])[:, None]
    return force_lines(con.point, con.normal, direction, np.arctan(mus))


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
    >>> force_line_distances(np.array([[5.0, 3.0], [5.0, 7.0]]), lines)[:, 0, 0].tolist()
    [2.0, -2.0]
    """
    beta = np.arctan2(ccw_cross(normal, direction), np.einsum("ij,ij->i", normal, direction))
    delta = np.clip(beta[:, None], -alphas[None, :], alphas[None, :])  # (n, m)
    n_b = np.broadcast_to(normal[:, None, :], (*delta.shape, 2))
    force = rotate_vectors(n_b, delta)  # (n, m, 2)
    a, b = force[..., 1], -force[..., 0]
    k = -(a * contact[:, None, 0] + b * contact[:, None, 1])
    return np.stack([a, b, k], axis=-1)


def force_line_distances(points, lines) -> np.ndarray:
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
