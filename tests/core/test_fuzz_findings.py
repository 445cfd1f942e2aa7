"""Inputs a fuzzing pass of the public API found unchecked: each now gets a named error."""

import numpy as np
import pytest

import comcore


@pytest.fixture
def rect():
    return comcore.Mask(np.pad(np.ones((40, 60), bool), 10))


@pytest.mark.parametrize(
    ("points", "match"),
    [
        (0.0, r"points must have shape \(n, 2\), got \(\)"),
        (np.zeros((2, 2, 2)), r"points must have shape \(n, 2\), got \(2, 2, 2\)"),
        ([[np.nan, 3.0]], "points must be finite"),
    ],
)
def test_inward_normals_checks_its_points_as_its_siblings_do(rect, points, match):
    with pytest.raises(ValueError, match=match):
        rect.inward_normals(points)


def test_inward_normals_of_no_points_is_empty(rect):
    assert rect.inward_normals([]).shape == (0, 2)
