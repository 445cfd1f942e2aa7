"""comcore.active._grid.logsumexp: scipy's numbers, bit for bit."""

import numpy as np
import pytest
from scipy import special

from comcore.active._grid import logsumexp


def bits(x) -> np.ndarray:
    return np.asarray(x, dtype=np.float64).view(np.int64)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("axis", [None, 0, (1, 2), (1, 2, 3)])
def test_logsumexp_is_scipy_bit_for_bit(seed, axis):
    rng = np.random.default_rng(seed)
    a = rng.normal(scale=30.0, size=(3, 50, 4, 6))
    a[0, :3] = a[0, 3]  # ties at the largest term
    for b in (None, rng.uniform(0, 1, size=(3, 1, 1, 1)), rng.uniform(0, 1, size=a.shape)):
        for keepdims in (False, True):
            got = logsumexp(a, axis=axis, b=b, keepdims=keepdims)
            expected = special.logsumexp(a, axis=axis, b=b, keepdims=keepdims)
            assert np.shape(got) == np.shape(expected)
            np.testing.assert_array_equal(bits(got), bits(expected))


def test_logsumexp_leaves_infinite_results_to_scipy():
    a = np.array([[-np.inf, -np.inf], [0.0, np.inf], [1.0, 2.0]])
    b = np.array([[1.0, 1.0], [1.0, 1.0], [0.0, 0.0]])
    for weights in (None, b):
        expected = special.logsumexp(a, axis=1, b=weights)
        np.testing.assert_array_equal(logsumexp(a, axis=1, b=weights), expected)
