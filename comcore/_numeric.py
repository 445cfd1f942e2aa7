"""A lighter stand-in for ``scipy.special.logsumexp``, the same numbers.

A session's step calls ``logsumexp`` several times on its posterior grid (tempers x CoM
pixels x frictions x models), which grows with the square of the camera's resolution.
scipy's computes every result twice: once by the shifted sum, once directly for the
results that come out infinite. :func:`logsumexp` does the shifted sum's floating-point
operations in the same order, so it returns the same numbers bit for bit
(``tests/camera/test_numeric.py`` compares them), and hands what it does not cover
(non-finite results, other dtypes) to scipy.
"""

from __future__ import annotations

import numpy as np
from scipy import special

__all__ = ["logsumexp"]


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
