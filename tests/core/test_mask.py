import numpy as np
import pytest

from comcore import Mask


@pytest.mark.parametrize(
    ("data", "kwargs", "error", "match"),
    [
        (np.zeros((4, 4), bool), {}, ValueError, "at least one object pixel"),
        (np.ones(5, bool), {}, ValueError, r"2-D \(H, W\) array, got 1-D"),
        (np.ones((2, 2, 2), bool), {}, ValueError, "got 3-D"),
        (np.zeros((0, 3), bool), {}, ValueError, "must not be empty"),
        (np.full((3, 3), 0.5), {}, ValueError, "only 0 and 1"),
        (np.array([[1.0, np.nan]]), {}, ValueError, "NaN or inf"),
        (np.array([["a"]]), {}, TypeError, "boolean-like"),
        (np.ones((3, 3), bool), {"resolution": 0}, ValueError, "resolution must be a positive"),
        (np.ones((3, 3), bool), {"resolution": -1e-3}, ValueError, "resolution must be a positive"),
        (np.ones((3, 3), bool), {"resolution": float("nan")}, ValueError, "resolution"),
        (
            np.ones((3, 3), bool),
            {"resolution": "1"},
            TypeError,
            "resolution must be a positive number",
        ),
    ],
)
def test_mask_rejects_bad_input(data, kwargs, error, match):
    with pytest.raises(error, match=match):
        Mask(data, **kwargs)


def test_mask_is_read_only_and_copies(square_mask):
    img = np.pad(np.ones((3, 3), bool), 1)
    m = Mask(img)
    img[2, 2] = False
    assert m.data[2, 2]
    with pytest.raises(ValueError):
        m.data[0, 0] = True
    with pytest.raises(AttributeError):
        m.resolution = 1.0  # type: ignore[misc]


def test_numeric_zero_one_images_are_accepted():
    m = Mask(np.array([[0, 1], [1, 1]], dtype=np.uint8), resolution=0.01)
    assert m.area_px == 3 and m.area_m2 == pytest.approx(3e-4)


def test_area_centroid_and_boundary(square_mask):
    assert square_mask.area_px == 900
    assert square_mask.centroid == (24.5, 24.5)
    assert square_mask.centroid_m == pytest.approx((24.5 * 0.0025, 24.5 * 0.0025))
    assert square_mask.boundary.sum() == 4 * 30 - 4
    assert not square_mask.boundary[11:39, 11:39].any()


def test_centroid_of_an_asymmetric_shape(l_mask):
    rows, cols = np.nonzero(l_mask.data)
    assert l_mask.centroid == pytest.approx((cols.mean(), rows.mean()))


def test_inward_normals_of_a_disk_point_to_its_centre(disk_mask):
    angles = np.linspace(0, 2 * np.pi, 36, endpoint=False)
    pts = 26 + 20 * np.column_stack([np.cos(angles), np.sin(angles)])
    normals = disk_mask.inward_normals(pts)
    expected = -np.column_stack([np.cos(angles), np.sin(angles)])
    cos_err = np.sum(normals * expected, axis=1)
    assert np.all(cos_err > np.cos(np.deg2rad(6)))


def test_contains_uses_nearest_pixel(square_mask):
    assert square_mask.contains([[10.0, 10.0], [9.6, 10.0], [9.4, 10.0], [-5, 3]]).tolist() == [
        True,
        True,
        False,
        False,
    ]


@pytest.mark.parametrize("method", ["contains", "distance_to_object"])
@pytest.mark.parametrize(
    ("points", "match"),
    [
        ([[np.nan, 3.0]], r"points must be finite, got NaN or inf in row\(s\) \[0\]"),
        ([[1.0, 2.0], [np.inf, 0.0]], r"points must be finite.*row\(s\) \[1\]"),
        ([[1.0, 2.0, 3.0]], r"points must have shape \(n, 2\), got \(1, 3\)"),
    ],
)
def test_point_queries_reject_bad_points(square_mask, method, points, match):
    # NaN used to raise a bare IndexError (distance_to_object) or a RuntimeWarning (contains).
    with pytest.raises(ValueError, match=match):
        getattr(square_mask, method)(points)


def test_point_queries_accept_one_point_or_none(square_mask):
    assert square_mask.contains((10.0, 10.0)).tolist() == [True]
    assert square_mask.distance_to_object((7.0, 10.0)).tolist() == [3.0]
    assert square_mask.contains(np.zeros((0, 2))).shape == (0,)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_to_metres_refuses_coordinates_that_are_not_finite(square_mask, bad):
    # NaN used to come back as NaN metres, and inf as inf.
    with pytest.raises(ValueError, match=r"points_px must be finite pixel coordinates \(x, y\)"):
        square_mask.to_metres((bad, 3.0))
    with pytest.raises(ValueError, match=r"got \(1.0, " + ("nan" if np.isnan(bad) else "-?inf")):
        square_mask.to_metres([[0.0, 0.0], [1.0, bad]])
    with pytest.raises(ValueError, match=r"shape \(2,\) or \(n, 2\), got shape \(3,\)"):
        square_mask.to_metres([1.0, 2.0, 3.0])
    assert square_mask.to_metres((4.0, 2.0)) == (0.01, 0.005)
