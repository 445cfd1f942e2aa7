"""One validator per input kind. Each returns the cleaned value or raises.

Every public function calls these first, so that bad input fails at the
entrance with a message that names the argument, the expected form and what
arrived.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy import ndimage

from ._checks import (  # the low-level checks, re-exported
    _as_float_rows,
    _real_number,
    check_count,
    check_finite,
    check_number,
    check_pair,
    check_point,
    check_points,
    refuse_complex,
)
from ._mask import Mask
from ._types import Action, Motion
from .conventions import LENGTH_EPS, check_plausible

__all__ = [
    "check_actions",
    "check_count",
    "check_finite",
    "check_mask",
    "check_motions",
    "check_mu",
    "check_number",
    "check_one_object",
    "check_pair",
    "check_point",
    "check_points",
    "check_priors",
    "check_probability",
    "check_rng",
]


def check_mask(mask, name: str = "mask") -> Mask:
    """Return ``mask`` if it is a :class:`comcore.Mask`, else raise TypeError."""
    if not isinstance(mask, Mask):
        hint = (
            " (wrap an image with comcore.Mask(image, resolution))"
            if isinstance(mask, np.ndarray)
            else ""
        )
        raise TypeError(f"{name} must be a comcore.Mask, got {type(mask).__name__}{hint}")
    return mask


#: A mask's holes (background enclosed by the object) may cover at most this share of the
#: filled object's area. Segmentation noise leaves holes of a few pixels, which move the
#: area centroid by under this share of the object's size; larger holes (a ring, a frame, a
#: checkerboard) may hold the CoM itself, which the estimators, whose regions are sets of
#: mask pixels, cannot return.
MAX_HOLE_SHARE = 0.01
#: An object must be at least this many pixels across somewhere (a solid
#: ``MIN_WIDTH_PX`` x ``MIN_WIDTH_PX`` block of object pixels): a line one or two pixels
#: wide, a 2 x 2 speck or a checkerboard has no inside, no outline normal to push along
#: (smoothed over ``comcore._mask.NORMAL_SMOOTHING_PX`` = 2 px) and no region to cut.
MIN_WIDTH_PX = 3
#: How many of a mask's separate parts an error lists by area.
_PARTS_LISTED = 4


def check_one_object(mask, name: str = "mask") -> Mask:
    """``mask`` if it shows one solid object, else a ValueError that says what it shows.

    The estimators (:func:`comcore.estimate_heatmap`, :func:`comcore.estimate_progressive`,
    :func:`comcore.estimate_posterior`, :class:`comcore.ActiveSession`) call it first. Each
    case is refused, not flagged with a status: no estimate over such a mask's pixels is
    right, and the fix is the caller's (which object, which threshold). Refused are

    * several 8-connected parts (two objects, or speckle beside one);
    * holes (4-connected background not reaching the image's border) over
      :data:`MAX_HOLE_SHARE` of the filled area; smaller holes are segmentation noise and
      pass as they are;
    * an object nowhere :data:`MIN_WIDTH_PX` pixels across.

    Examples
    --------
    >>> img = np.zeros((30, 40), bool)
    >>> img[5:15, 5:17] = img[5:25, 25:35] = True
    >>> check_one_object(Mask(img))
    Traceback (most recent call last):
    ...
    ValueError: mask has 2 separate parts (areas 200 and 120 px): pass one object's mask, e.g. comcore.Mask(comcore.geometry.largest_component(mask.data), mask.resolution)
    >>> ring = np.pad(np.ones((20, 20), bool), 2)
    >>> ring[7:17, 7:17] = False
    >>> check_one_object(Mask(ring))
    Traceback (most recent call last):
    ...
    ValueError: mask has holes of 100 px, 25 % of the object's 400 px (at most 1 % allowed): the CoM may lie in a hole, where no estimate over the mask's pixels can put it; if the object is solid there, fill them (scipy.ndimage.binary_fill_holes(mask.data))
    >>> check_one_object(Mask(np.eye(8, dtype=bool)))
    Traceback (most recent call last):
    ...
    ValueError: mask is nowhere 3 pixels across (8 px in all, no 3 x 3 block of object pixels): a line or a speck cannot be pushed along its outline; use a finer resolution or check the segmentation
    """  # noqa: E501
    mask = check_mask(mask, name)
    rows, cols = np.nonzero(mask.data)
    box = np.pad(mask.data[rows.min() : rows.max() + 1, cols.min() : cols.max() + 1], 1)
    labels, n_parts = ndimage.label(box, structure=np.ones((3, 3), bool))
    if n_parts > 1:
        areas = [str(a) for a in np.sort(np.bincount(labels.ravel())[1:])[::-1]]
        shown = " and ".join(areas) if n_parts == 2 else ", ".join(areas[:_PARTS_LISTED])
        more = f" and {n_parts - _PARTS_LISTED} more" if n_parts > _PARTS_LISTED else ""
        raise ValueError(
            f"{name} has {n_parts} separate parts (areas {shown} px{more}): pass one "
            "object's mask, e.g. "
            "comcore.Mask(comcore.geometry.largest_component(mask.data), mask.resolution)"
        )
    area = int(rows.size)
    filled = int(ndimage.binary_fill_holes(box).sum())
    if filled - area > MAX_HOLE_SHARE * filled:
        raise ValueError(
            f"{name} has holes of {filled - area} px, {100 * (filled - area) / filled:.3g} % "
            f"of the object's {filled} px (at most {100 * MAX_HOLE_SHARE:g} % allowed): the "
            "CoM may lie in a hole, where no estimate over the mask's pixels can put it; if "
            "the object is solid there, fill them (scipy.ndimage.binary_fill_holes(mask.data))"
        )
    block = np.ones((MIN_WIDTH_PX, MIN_WIDTH_PX), bool)
    if not ndimage.binary_erosion(box, structure=block).any():
        raise ValueError(
            f"{name} is nowhere {MIN_WIDTH_PX} pixels across ({area} px in all, no "
            f"{MIN_WIDTH_PX} x {MIN_WIDTH_PX} block of object pixels): a line or a speck "
            "cannot be pushed along its outline; use a finer resolution or check the "
            "segmentation"
        )
    return mask


def check_actions(actions, name: str = "actions", allow_empty: bool = True) -> np.ndarray:
    """Validate actions into a read-only float array of shape (n, 4).

    Accepts an :class:`Action`, a sequence of them, or array_like of shape
    (4,) or (n, 4) holding ``(sx, sy, ex, ey)`` rows in pixels.

    Examples
    --------
    >>> check_actions([(0, 0, 1, 0), (0, 0, 0, 2)]).shape
    (2, 4)
    >>> check_actions([[0, 0, 1]])
    Traceback (most recent call last):
    ...
    ValueError: actions must have shape (n, 4), got (1, 3)
    """
    arr = _as_float_rows(actions, 4, name, Action)
    if not allow_empty and arr.shape[0] == 0:
        raise ValueError(f"{name} must hold at least one action, got none")
    length = np.hypot(arr[:, 2] - arr[:, 0], arr[:, 3] - arr[:, 1])
    if (length <= LENGTH_EPS).any():
        bad = np.flatnonzero(length <= LENGTH_EPS)
        raise ValueError(
            f"{name} must have non-zero length; zero-length action(s) at index {bad[:5].tolist()}"
        )
    return arr


def check_motions(motions, n: int | None = None, name: str = "motions") -> np.ndarray:
    """Validate motions into a read-only float array of shape (n, 3).

    Accepts a :class:`Motion`, a sequence of them, or array_like of shape (3,)
    or (n, 3) holding ``(theta, tx, ty)`` rows. When ``n`` is given the number
    of rows must equal it.

    Examples
    --------
    >>> check_motions([(0.1, 0, 0)], n=2)
    Traceback (most recent call last):
    ...
    ValueError: motions must have one row per action: expected 2, got 1
    """
    arr = _as_float_rows(motions, 3, name, Motion)
    if n is not None and arr.shape[0] != n:
        raise ValueError(f"{name} must have one row per action: expected {n}, got {arr.shape[0]}")
    return arr


def check_priors(priors, name: str = "priors") -> tuple[np.ndarray, np.ndarray]:
    """Validate prior pushes: a sequence of ``(Action, Motion)`` pairs.

    Returns
    -------
    actions : numpy.ndarray, shape (k, 4)
    motions : numpy.ndarray, shape (k, 3)

    Examples
    --------
    >>> a, m = check_priors([(Action(0, 5, 9, 5), Motion(0.1, 1, 0))])
    >>> a.shape, m.shape
    ((1, 4), (1, 3))
    >>> check_priors([(1, 2)])
    Traceback (most recent call last):
    ...
    ValueError: priors[0] must be an (Action, Motion) pair of 4 and 3 numbers
    """
    if priors is None:
        priors = ()
    if not isinstance(priors, Sequence) or isinstance(priors, (str, bytes)):
        raise TypeError(
            f"{name} must be a sequence of (Action, Motion) pairs, got {type(priors).__name__}"
        )
    acts, mots = [], []
    for i, pair in enumerate(priors):
        try:
            a, m = pair
            refuse_complex(a, f"{name}[{i}]")
            refuse_complex(m, f"{name}[{i}]")
            a = np.asarray(tuple(a) if isinstance(a, tuple) else a, dtype=float).reshape(-1)
            m = np.asarray(tuple(m) if isinstance(m, tuple) else m, dtype=float).reshape(-1)
        except (TypeError, ValueError) as e:
            raise ValueError(
                f"{name}[{i}] must be an (Action, Motion) pair of 4 and 3 numbers"
            ) from e
        if a.shape != (4,) or m.shape != (3,):
            raise ValueError(f"{name}[{i}] must be an (Action, Motion) pair of 4 and 3 numbers")
        acts.append(a)
        mots.append(m)
    actions = check_actions(np.array(acts).reshape(-1, 4), name=f"{name} actions")
    motions = check_motions(np.array(mots).reshape(-1, 3), n=len(actions), name=f"{name} motions")
    return actions, motions


def check_mu(mu, name: str = "mu") -> tuple[float, float]:
    """Validate a friction coefficient spec into a closed range ``(lo, hi)``.

    ``None`` means unknown (any ``mu >= 0``: ``(0, inf)``); a number means
    exactly that value; a pair means a range.

    Examples
    --------
    >>> check_mu(None), check_mu(0.3), check_mu((0.1, 0.5))
    ((0.0, inf), (0.3, 0.3), (0.1, 0.5))
    >>> check_mu(-1)
    Traceback (most recent call last):
    ...
    ValueError: mu must be >= 0, got -1.0
    """
    if mu is None:
        return (0.0, math.inf)
    if isinstance(mu, bool):
        raise TypeError(f"{name} must be None, a number or a (lo, hi) pair, got bool")
    if isinstance(mu, (int, float, np.integer, np.floating)):
        lo = hi = float(mu)
    else:
        try:
            lo, hi = (float(v) for v in mu)
        except (TypeError, ValueError) as e:
            raise TypeError(f"{name} must be None, a number or a (lo, hi) pair, got {mu!r}") from e
    if math.isnan(lo) or math.isnan(hi):
        raise ValueError(f"{name} must not be NaN")
    if lo < 0 or hi < 0:
        raise ValueError(f"{name} must be >= 0, got {min(lo, hi)}")
    if lo > hi:
        raise ValueError(f"{name} range must have lo <= hi, got ({lo}, {hi})")
    if math.isinf(lo):
        raise ValueError(f"{name} lower bound must be finite, got {lo}")
    return (lo, hi)


def check_probability(
    value, name: str, *, open_low: bool = False, open_high: bool = False
) -> float:
    """Validate a number in [0, 1] (ends optionally open).

    Examples
    --------
    >>> check_probability(0.25, "flip")
    0.25
    >>> check_probability(1.0, "flip", open_high=True)
    Traceback (most recent call last):
    ...
    ValueError: flip must be in [0, 1), got 1.0
    """
    v = _real_number(value, name, "a number in [0, 1]")
    low_ok = v > 0 if open_low else v >= 0
    high_ok = v < 1 if open_high else v <= 1
    if not (math.isfinite(v) and low_ok and high_ok):
        lo = "(" if open_low else "["
        hi = ")" if open_high else "]"
        raise ValueError(f"{name} must be in {lo}0, 1{hi}, got {v}")
    return v


def check_positive(value, name: str, *, allow_zero: bool = False) -> float:
    """Validate a finite positive (or non-negative) number.

    Examples
    --------
    >>> check_positive(0.004, "pusher_radius")
    0.004
    >>> check_positive(0, "pusher_radius")
    Traceback (most recent call last):
    ...
    ValueError: pusher_radius must be a finite number > 0, got 0.0
    """
    v = _real_number(value, name)
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        want = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must be a finite number {want}, got {v}")
    return v


def check_turns(motions: np.ndarray, name: str = "motions") -> np.ndarray:
    """``motions`` (n, 3) if no push turned the object by more than pi, else a ValueError.

    One push cannot turn an object by more than half a turn: a larger theta is
    in degrees, not radians.

    Examples
    --------
    >>> check_turns(np.array([[0.2, 3.0, 0.0], [25.0, 1.0, 1.0]]))
    Traceback (most recent call last):
    ...
    ValueError: motions[1] turns the object by 25 rad, more than pi: theta must be in radians (did you mean degrees, 0.436 rad?)
    """  # noqa: E501
    big = np.flatnonzero(np.abs(motions[:, 0]) > math.pi)
    if len(big):
        i = int(big[0])
        theta = float(motions[i, 0])
        raise ValueError(
            f"{name}[{i}] turns the object by {theta:g} rad, more than pi: theta must be in "
            f"radians (did you mean degrees, {math.radians(theta):.3g} rad?)"
        )
    return motions


def check_physical(value, name: str, kind: str, *, allow_zero: bool = False) -> float:
    """Validate a length (metres) or angle (radians) a user sets: positive and believable.

    ``kind`` names its range in :data:`comcore.conventions.PLAUSIBLE`; outside it the
    ValueError guesses the unit it was typed in.

    Examples
    --------
    >>> check_physical(0.004, "pusher_radius", "pusher_radius")
    0.004
    >>> check_physical(4, "pusher_radius", "pusher_radius")
    Traceback (most recent call last):
    ...
    ValueError: pusher_radius 4 m is implausible (expected at most 0.05 m): did you mean millimetres, 0.004?
    """  # noqa: E501
    return check_plausible(check_positive(value, name, allow_zero=allow_zero), name, kind)


def check_rng(rng, name: str = "rng") -> np.random.Generator:
    """A :class:`numpy.random.Generator` from ``None``, a seed or a generator.

    ``None`` gives a fresh generator (OS entropy), a non-negative int (or a
    sequence of them, or a :class:`numpy.random.SeedSequence`) a seeded one; a
    Generator is returned as it is (the caller's stream is shared, not copied).

    Examples
    --------
    >>> check_rng(0).random() == check_rng(0).random()
    True
    >>> check_rng(-1)
    Traceback (most recent call last):
    ...
    ValueError: rng must be None, a non-negative int seed or a numpy Generator, got -1
    >>> check_rng("a")
    Traceback (most recent call last):
    ...
    TypeError: rng must be None, a non-negative int seed or a numpy Generator, got str
    """
    if rng is None or isinstance(rng, (np.random.Generator, np.random.SeedSequence)):
        return np.random.default_rng(rng)
    want = "None, a non-negative int seed or a numpy Generator"
    if isinstance(rng, (bool, np.bool_)) or isinstance(rng, (str, bytes, float, np.floating)):
        raise TypeError(f"{name} must be {want}, got {type(rng).__name__}")
    if isinstance(rng, (int, np.integer)):
        if rng < 0:
            raise ValueError(f"{name} must be {want}, got {rng}")
        return np.random.default_rng(int(rng))
    if isinstance(rng, np.random.BitGenerator):
        return np.random.default_rng(rng)
    try:
        if not isinstance(rng, (list, tuple, np.ndarray)) or len(rng) == 0:
            raise TypeError  # a dict, a set, an empty sequence: no seed anybody meant
        seeds = [int(s) for s in rng if not isinstance(s, (bool, float, str))]
        if len(seeds) != len(rng) or any(s < 0 for s in seeds):
            raise ValueError
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be {want}, got {type(rng).__name__}") from None
    return np.random.default_rng(seeds)


def check_powers(value, name: str) -> tuple[float, ...]:
    """Validate one power in (0, 1] or a sequence of distinct ones, as a tuple.

    Examples
    --------
    >>> check_powers(0.6, "model_weight"), check_powers([0.5, 1], "model_weight")
    ((0.6,), (0.5, 1.0))
    """
    want = f"{name} must be a number or a sequence of numbers, got {value!r}"
    if isinstance(value, (str, bytes)):
        raise TypeError(want)
    if np.ndim(value) == 0:
        return (check_probability(value, name, open_low=True),)
    try:
        values = tuple(value)
    except TypeError as e:
        raise TypeError(want) from e
    if not values:
        raise ValueError(f"{name} must not be an empty sequence")
    out = tuple(check_probability(v, name, open_low=True) for v in values)
    if len(set(out)) != len(out):
        raise ValueError(f"{name}'s powers must be distinct, got {value!r}")
    return out


def check_per_push(values, n: int, name: str, default):
    """One value per push, validated: bools when ``default`` is a bool, else numbers >= 0.

    ``None`` gives ``default`` for every push; a number may be NaN (not measured).
    """
    if values is None:
        return [default] * n
    if isinstance(values, (str, bytes)) or np.ndim(values) != 1 or len(values) != n:
        raise ValueError(f"{name} must hold one value per push ({n}), got {values!r}")
    if isinstance(default, bool):
        if not all(isinstance(v, (bool, np.bool_)) for v in values):
            raise TypeError(f"{name} must hold bools, got {values!r}")
        return [bool(v) for v in values]
    try:
        out = [math.nan if v is None else float(v) for v in values]
    except (TypeError, ValueError) as e:
        raise TypeError(
            f"{name} must hold numbers (NaN or None: not measured), got {values!r}"
        ) from e
    if any(v < 0 or math.isinf(v) for v in out):
        raise ValueError(f"{name} must be >= 0 and finite or NaN (pixels), got {values!r}")
    return out
