"""comcore._numeric: the same numbers as the scipy routines it stands in for, bit for bit."""

import numpy as np
import pytest
from scipy import ndimage, special

from comcore._numeric import bilinear, logsumexp


def bits(x) -> np.ndarray:
    return np.asarray(x, dtype=np.float64).view(np.int64)


@pytest.mark.parametrize("seed", range(6))
def test_bilinear_is_map_coordinates_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    h, w = (int(v) for v in rng.integers(1, 40, 2))
    a = rng.normal(size=(h, w)) * 10.0 ** rng.uniform(-3, 3)
    a[rng.random((h, w)) < 0.2] = -0.0  # signed zeros: scipy's sum starts from +0.0
    n = 4000
    c0, c1 = rng.uniform(-3, h + 2, n), rng.uniform(-3, w + 2, n)  # beyond the edges too
    c0[::7], c1[::5] = np.round(c0[::7]), np.round(c1[::5])  # on the nodes
    c0[::11], c1[::13] = h - 1.0, -0.0
    expected = ndimage.map_coordinates(a, np.vstack([c0, c1]), order=1, mode="nearest")
    np.testing.assert_array_equal(bits(bilinear(a, c0, c1)), bits(expected))


def test_bilinear_hands_non_finite_points_to_scipy():
    a = np.arange(12.0).reshape(3, 4)
    c0, c1 = np.array([np.nan, 1.0]), np.array([1.0, 1.5])
    expected = ndimage.map_coordinates(a, np.vstack([c0, c1]), order=1, mode="nearest")
    np.testing.assert_array_equal(bilinear(a, c0, c1), expected)


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
