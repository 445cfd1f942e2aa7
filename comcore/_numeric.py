"""Lighter stand-ins for two scipy routines a session calls on every step, same numbers.

A session's step calls ``scipy.ndimage.map_coordinates`` (bilinear) a few hundred times on
small batches of points and ``scipy.special.logsumexp`` on its posterior grid; most of
their cost is argument handling and, for ``logsumexp``, a second pass over the whole array
that only its infinite results use. :func:`bilinear` and :func:`logsumexp` do the same
floating-point operations in the same order, so they return the same numbers bit for bit
(``tests/camera/test_numeric.py`` compares them), and hand what they do not cover (other
modes, non-finite input or results) to scipy.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage, special

__all__ = ["bilinear", "logsumexp"]


def bilinear(array: np.ndarray, coord0, coord1) -> np.ndarray:
    """``ndimage.map_coordinates(array, [coord0, coord1], order=1, mode="nearest")``.

    ``array`` 2-D float64; ``coord0``, ``coord1`` 1-D, one length (rows, columns).
    Beyond the edges the nearest row or column is read, with the weights of the
    unclamped coordinate, as scipy does.

    Examples
    --------
    >>> a = np.arange(12.0).reshape(3, 4)
    >>> bilinear(a, np.array([0.5, 2.0, -1.0]), np.array([0.5, 1.0, 9.0])).tolist()
    [2.5, 9.0, 3.0]
    """
    c0, c1 = np.asarray(coord0, dtype=float), np.asarray(coord1, dtype=float)
    if (
        array.ndim != 2
        or array.dtype != np.float64
        or not (np.isfinite(c0).all() and np.isfinite(c1).all())
    ):
        return ndimage.map_coordinates(array, np.vstack([c0, c1]), order=1, mode="nearest")
    h, w = array.shape
    f0, f1 = np.floor(c0), np.floor(c1)
    t0, t1 = c0 - f0, c1 - f1
    u0, u1 = 1.0 - t0, 1.0 - t1
    i0 = np.clip(f0, 0, h - 1).astype(np.intp)
    i1 = np.clip(f0 + 1, 0, h - 1).astype(np.intp)
    j0 = np.clip(f1, 0, w - 1).astype(np.intp)
    j1 = np.clip(f1 + 1, 0, w - 1).astype(np.intp)
    # scipy's sum: from 0.0, the corners with the last axis fastest, value * w0 * w1 each
    out = 0.0 + array[i0, j0] * u0 * u1
    out += array[i0, j1] * u0 * t1
    out += array[i1, j0] * t0 * u1
    out += array[i1, j1] * t0 * t1
    return out


def logsumexp(a, axis=None, b=None, keepdims: bool = False):
    """``scipy.special.logsumexp(a, axis, b, keepdims)`` for real float64 arrays.

    The largest term is taken out of the sum and added back through ``log1p``, as
    scipy does; where a result is not finite (all weights zero, an infinite or NaN
    term) scipy computes it instead.

    Examples
    --------
    >>> x = np.log([[1.0, 2.0], [3.0, 4.0]])
    >>> bool(logsumexp(x) == special.logsumexp(x))
    True
    >>> logsumexp(x, axis=1, b=[[1.0, 0.0], [1.0, 1.0]]).round(6).tolist()
    [0.0, 1.94591]
    """
    arr = np.asarray(a)
    weights = None if b is None else np.asarray(b)
    if arr.dtype != np.float64 or (weights is not None and weights.dtype != np.float64):
        return special.logsumexp(a, axis=axis, b=b, keepdims=keepdims)
    if weights is not None:
        arr, weights = np.broadcast_arrays(arr, weights)
    if arr.ndim == 0 or arr.size == 0:
        return special.logsumexp(a, axis=axis, b=b, keepdims=keepdims)
    axes = tuple(range(arr.ndim)) if axis is None else axis
    with np.errstate(divide="ignore", invalid="ignore"):
        if weights is not None:
            arr = np.where(weights == 0, -np.inf, arr)
        top = np.max(arr, axis=axes, keepdims=True)
        at_top = arr == top
        arr = np.where(at_top, -np.inf, arr)
        count = at_top.astype(np.float64) if weights is None else weights * at_top
        m = np.sum(count, axis=axes, keepdims=True, dtype=np.float64)
        terms = np.exp(arr - top) if weights is None else weights * np.exp(arr - top)
        s = np.sum(terms, axis=axes, keepdims=True, dtype=np.float64)
        s = np.where(s == 0, s, s / m)
        out = np.log1p(s) + np.log(m) + top
    if not (np.isfinite(out).all() and (m > 0).all() and (s >= -1).all()):
        return special.logsumexp(a, axis=axis, b=b, keepdims=keepdims)
    if not keepdims:
        out = np.squeeze(out, axis=axes)
    return out[()] if out.ndim == 0 else out
