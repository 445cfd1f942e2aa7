import numpy as np
import pytest

import comcore


def test_largest_component_takes_a_nested_list_and_leaves_it_alone():
    # A list used to fail with "'list' object has no attribute 'astype'".
    image = [[1, 1, 0, 1], [0, 0, 0, 1], [0, 0, 0, 1]]
    out = comcore.geometry.largest_component(image)
    assert out.dtype == bool and out.sum() == 3 and out[:, 3].all()
    assert image == [[1, 1, 0, 1], [0, 0, 0, 1], [0, 0, 0, 1]]


def test_largest_component_returns_a_copy():
    image = np.eye(3, dtype=bool)
    out = comcore.geometry.largest_component(image)
    out[0, 0] = False
    assert image[0, 0]


@pytest.mark.parametrize(
    ("image", "error", "match"),
    [
        ([1, 0, 1], ValueError, r"image must be a 2-D boolean array, got shape \(3,\)"),
        ([[0, 2]], ValueError, "image must hold booleans .or 0 / 1., got the value 2"),
        ([[0.0, np.nan]], ValueError, "got the value nan"),
        ([["a", "b"]], TypeError, "image must be a 2-D boolean array, got dtype"),
        ("ab", TypeError, "image must be a 2-D boolean array, got str"),
        ([[1, 0], [1]], TypeError, "image must be a 2-D boolean array"),
    ],
)
def test_largest_component_rejects_bad_images(image, error, match):
    with pytest.raises(error, match=match):
        comcore.geometry.largest_component(image)
