"""comcore.geometry.rasterise_polygon: pixel centres inside a polygon, even-odd rule."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import comcore
from tests import strategies as cst


def every_pixel(vertices, shape):
    """The even-odd rule evaluated at every pixel centre of the image (no bounding box)."""
    h, w = shape
    ys, xs = np.mgrid[0:h, 0:w].astype(float)
    inside = np.zeros(shape, bool)
    for (a, b), (c, d) in zip(vertices, np.roll(vertices, -1, axis=0)):
        crosses = (b > ys) != (d > ys)
        with np.errstate(divide="ignore", invalid="ignore"):
            inside ^= crosses & (xs < a + (ys - b) * (c - a) / (d - b))
    return inside


def test_a_rectangle_holds_the_pixel_centres_strictly_inside_it():
    img = comcore.geometry.rasterise_polygon([(1.5, 0.5), (4.2, 0.5), (4.2, 2.5), (1.5, 2.5)], (4, 6))
    expected = np.zeros((4, 6), bool)
    expected[1:3, 2:5] = True
    assert np.array_equal(img, expected)


@given(cst.star_polygons(size=20.0), st.integers(-30, 30), st.integers(-30, 30))
def test_only_the_bounding_box_is_computed_and_nothing_changes(poly, dx, dy):
    shifted = poly + np.array([dx, dy])  # often partly or wholly off the image
    assert np.array_equal(
        comcore.geometry.rasterise_polygon(shifted, (50, 60)), every_pixel(shifted, (50, 60))
    )


@given(cst.star_polygons(size=20.0))
def test_the_orientation_of_the_outline_does_not_matter(poly):
    shape = (60, 60)
    assert np.array_equal(
        comcore.geometry.rasterise_polygon(poly, shape), comcore.geometry.rasterise_polygon(poly[::-1], shape)
    )


@given(cst.star_polygons(size=20.0))
def test_the_pixel_count_is_the_area_within_the_outline_length(poly):
    x, y = poly[:, 0], poly[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    perimeter = np.linalg.norm(poly - np.roll(poly, -1, axis=0), axis=1).sum()
    count = comcore.geometry.rasterise_polygon(poly, (60, 60)).sum()
    assert abs(count - area) <= perimeter


def test_a_self_intersecting_outline_follows_the_even_odd_rule():
    # two overlapping squares traced as one outline: the overlap is outside
    bow = [(1, 1), (5, 1), (5, 5), (3, 5), (3, 3), (7, 3), (7, 7), (1, 7)]
    img = comcore.geometry.rasterise_polygon(np.array(bow, float) - 0.25, (8, 8))
    assert not img[4, 4] and img[2, 2] and img[6, 6]


def test_an_empty_image_and_a_polygon_off_the_image():
    assert comcore.geometry.rasterise_polygon([(0, 0), (3, 0), (0, 3)], (0, 5)).shape == (0, 5)
    off = comcore.geometry.rasterise_polygon([(-9, -9), (-5, -9), (-9, -5)], (4, 4))
    assert off.shape == (4, 4) and not off.any()


@pytest.mark.parametrize(
    ("vertices", "shape", "error", "match"),
    [
        ([(0, 0), (1, 1)], (4, 4), ValueError, "at least 3 points"),
        ([(0, 0), (1, np.nan), (2, 0)], (4, 4), ValueError, "vertices must be finite"),
        ([(0, 0, 0), (1, 1, 1), (2, 0, 0)], (4, 4), ValueError, r"shape \(n, 2\)"),
        ([(0, 0), (1, 1), (2, 0)], 4, TypeError, r"shape must be \(rows, cols\)"),
        ([(0, 0), (1, 1), (2, 0)], (4.0, 4), TypeError, "two integers"),
        ([(0, 0), (1, 1), (2, 0)], (4, -1), ValueError, ">= 0"),
    ],
)
def test_bad_input_is_refused_with_its_name(vertices, shape, error, match):
    with pytest.raises(error, match=match):
        comcore.geometry.rasterise_polygon(vertices, shape)
