"""Low-level checks of numbers and point arrays, for the modules below the validators.

:mod:`comcore.conventions` and :class:`comcore.Mask` validate their points with these;
:mod:`comcore._validation` (which imports both of them) builds the per-type validators
on them and re-exports them. This module imports nothing of comcore.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "check_count",
    "check_finite",
    "check_number",
    "check_pair",
    "check_point",
    "check_points",
    "refuse_complex",
]


def refuse_complex(value, name: str) -> None:
    """A TypeError naming ``name`` if ``value`` holds complex numbers.

    numpy's ``asarray(value, dtype=float)`` keeps only their real part, with a
    warning the caller may never see; a complex coordinate is always a mistake.
    Anything numpy cannot read as one array passes, for the conversion to refuse.

    Examples
    --------
    >>> refuse_complex([1.0, 2.0], "actions")
    >>> refuse_complex([1.0, 2.0 + 1j], "actions")
    Traceback (most recent call last):
    ...
    TypeError: actions must hold real numbers, got complex ones (numpy would keep only their real part)
    """  # noqa: E501
    try:
        complex_ = np.iscomplexobj(value)
    except (TypeError, ValueError):
        return
    if complex_:
        raise TypeError(
            f"{name} must hold real numbers, got complex ones (numpy would keep only their "
            "real part)"
        )


def is_ragged(error: Exception) -> bool:
    """Whether numpy refused to build an array because nested lists differ in length."""
    return isinstance(error, ValueError) and "inhomogeneous" in str(error)


def _as_float_rows(value, width: int, name: str, row_type) -> np.ndarray:
    refuse_complex(value, name)
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
            if is_ragged(e):
                raise TypeError(
                    f"{name} must be array_like of real numbers with shape (n, {width}), got "
                    "ragged rows (nested lists of different lengths)"
                ) from e
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
    if isinstance(value, (str, bytes)) or value is None:
        raise TypeError(f"{name} must be a point (x, y) of 2 numbers, got {type(value).__name__}")
    try:
        shape = np.shape(value)
    except ValueError:  # ragged nested lists
        shape = None
    if shape != (2,):
        raise ValueError(f"{name} must be a single point of shape (2,), got shape {shape}")
    arr = _as_float_rows(value, 2, name, tuple())  # type: ignore[arg-type]
    return arr[0]


def check_number(value, name: str, *, integer: bool = False, allow_inf: bool = False) -> float:
    """``value`` as a float if it is a real number (an integer with ``integer``), not NaN.

    A bool, a string or an array is a TypeError naming ``name``; NaN (and
    infinity unless ``allow_inf``) a ValueError.

    >>> check_number(3, "n_iterations", integer=True)
    3.0
    >>> check_number(2.5, "n_iterations", integer=True)
    Traceback (most recent call last):
    ...
    TypeError: n_iterations must be an integer, got float
    """
    kinds = (int, np.integer) if integer else (int, float, np.integer, np.floating)
    if isinstance(value, bool) or not isinstance(value, kinds):
        kind = "an integer" if integer else "a number"
        raise TypeError(f"{name} must be {kind}, got {type(value).__name__}")
    value = float(value)
    if math.isnan(value) or (math.isinf(value) and not allow_inf):
        raise ValueError(f"{name} must be finite, got {value}")
    return value


def check_count(value, name: str, minimum: int = 0) -> int:
    """Validate an int (not a bool) of at least ``minimum``.

    A wrong type is a TypeError, a wrong value a ValueError, for every count.

    Examples
    --------
    >>> check_count(3, "max_pushes")
    3
    >>> check_count(0, "n_mu", 1)
    Traceback (most recent call last):
    ...
    ValueError: n_mu must be >= 1, got 0
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def check_pair(value, name: str, allow_zero: bool = False) -> tuple[float, float]:
    """Validate an ``(absolute > 0, other >= 0)`` pair of numbers (both >= 0 with allow_zero).

    Examples
    --------
    >>> check_pair((0.01, 0.13), "theta_noise")
    (0.01, 0.13)
    >>> check_pair((0.0, 0.1), "theta_noise")
    Traceback (most recent call last):
    ...
    ValueError: theta_noise must be a pair with absolute > 0 and other >= 0, got (0.0, 0.1)
    """
    try:
        a, r = (float(v) for v in value)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be a pair of numbers (absolute, other)") from e
    low_ok = a >= 0 if allow_zero else a > 0
    if not (low_ok and math.isfinite(a) and r >= 0 and math.isfinite(r)):
        want = "both >= 0" if allow_zero else "absolute > 0 and other >= 0"
        raise ValueError(f"{name} must be a pair with {want}, got ({a}, {r})")
    return a, r
