"""Low-level checks of numbers and point arrays, for the modules below the validators.

:mod:`comcore._conventions` and :class:`comcore.Mask` validate their points with these;
:mod:`comcore._validation` (which imports both of them) builds the per-type validators
on them and re-exports them. This module imports nothing of comcore.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["check_finite", "check_point", "check_points"]


def _as_float_rows(value, width: int, name: str, row_type) -> np.ndarray:
    if isinstance(value, row_type):
        arr = np.asarray([tuple(value)], dtype=float)
    else:
        if isinstance(value, (str, bytes)) or value is None:
            raise TypeError(
                f"{name} must be array_like of shape (n, {width}), got {type(value).__name__}"
            )
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError) as e:
            raise TypeError(
                f"{name} must be array_like of real numbers with shape (n, {width}); {e}"
            ) from e
        if arr.ndim == 1 and arr.shape[0] == width:
            arr = arr[None, :]
        if arr.ndim == 1 and arr.shape[0] == 0:
            arr = arr.reshape(0, width)
    if arr.ndim != 2 or arr.shape[1] != width:
        raise ValueError(f"{name} must have shape (n, {width}), got {arr.shape}")
    if not np.isfinite(arr).all():
        bad = np.flatnonzero(~np.isfinite(arr).all(axis=1))
        raise ValueError(f"{name} must be finite, got NaN or inf in row(s) {bad[:5].tolist()}")
    arr = arr.copy()
    arr.setflags(write=False)
    return arr


def _real_number(value, name: str, expected: str = "a number") -> float:
    """``value`` as a float if it is a real number (not a bool), else a TypeError."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be {expected}, got {type(value).__name__}")
    return float(value)


def check_points(points, name: str = "points") -> np.ndarray:
    """Validate pixel points into a read-only float array of shape (n, 2)."""
    return _as_float_rows(points, 2, name, tuple())  # type: ignore[arg-type]


def check_finite(value, name: str) -> float:
    """Validate a finite real number of any sign (an angle, an offset).

    Examples
    --------
    >>> check_finite(-0.5, "theta")
    -0.5
    >>> check_finite(float("nan"), "theta")
    Traceback (most recent call last):
    ...
    ValueError: theta must be a finite number, got nan
    """
    v = _real_number(value, name)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be a finite number, got {v}")
    return v


def check_point(value, name: str = "point") -> np.ndarray:
    """Validate one finite pixel point or 2-vector into a read-only array of shape (2,).

    Examples
    --------
    >>> check_point((3, 4), "center").tolist()
    [3.0, 4.0]
    >>> check_point([[3, 4], [5, 6]], "center")
    Traceback (most recent call last):
    ...
    ValueError: center must be a single point of shape (2,), got shape (2, 2)
    """
    arr = _as_float_rows(value, 2, name, tuple())  # type: ignore[arg-type]
    if np.ndim(value) != 1 or arr.shape[0] != 1:
        raise ValueError(
            f"{name} must be a single point of shape (2,), got shape {np.shape(value)}"
        )
    return arr[0]
