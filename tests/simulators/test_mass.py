"""Mass distributions: support grid, point masses, gradients, the exponential tilt."""

import numpy as np
import pytest

pytest.importorskip("shapely")
pytest.importorskip("trimesh")

import simulators
from simulators import MassDistribution, ObjectShape, tilt_to_com

L_SHAPE = ObjectShape([(0, 0), (0.06, 0), (0.06, 0.02), (0.02, 0.02), (0.02, 0.05), (0, 0.05)])


def test_uniform_support_has_the_area_centroid_and_the_mass():
    dist = MassDistribution.on_shape(L_SHAPE, mass=2.0, n_support=64)
    assert dist.total_mass == pytest.approx(2.0)
    assert dist.com_m == pytest.approx(L_SHAPE.centroid_m, abs=1e-12)
    assert 50 <= len(dist.masses) <= 100
    assert (dist.masses > 0).all() and not dist.masses.flags.writeable


def test_point_masses_move_the_com():
    pm = [(0.05, 0.01, 1.0)]
    dist = MassDistribution.on_shape(L_SHAPE, point_masses=pm)
    uniform = np.asarray(L_SHAPE.centroid_m)
    expected = (uniform * 1.0 + np.array([0.05, 0.01]) * 1.0) / 2.0
    assert dist.com_m == pytest.approx(tuple(expected), abs=1e-12)
    assert dist.total_mass == pytest.approx(2.0)


def test_density_gradient_moves_the_com_towards_the_dense_side():
    dist = MassDistribution.on_shape(L_SHAPE, density_gradient=(10.0, 0.0))
    assert dist.com_m[0] > L_SHAPE.centroid_m[0] + 1e-3
    with pytest.raises(ValueError, match="too steep"):
        MassDistribution.on_shape(L_SHAPE, density_gradient=(100.0, 0.0))


@pytest.mark.parametrize("target", [(0.01, 0.04), (0.055, 0.005), (0.012, 0.012)])
def test_com_is_put_where_asked(target):
    dist = MassDistribution.on_shape(L_SHAPE, com=target, point_masses=[(0.01, 0.01, 0.5)])
    assert dist.com_m == pytest.approx(target, abs=1e-9)


def test_com_outside_the_footprint_is_rejected():
    with pytest.raises(ValueError, match="inside the footprint"):
        MassDistribution.on_shape(L_SHAPE, com=(0.05, 0.04))  # in the L's notch
    with pytest.raises(ValueError, match="point_masses must lie inside"):
        MassDistribution.on_shape(L_SHAPE, point_masses=[(0.05, 0.04, 1.0)])


def test_tilt_preserves_total_and_is_closest_to_the_original():
    rng = np.random.default_rng(0)
    p = rng.uniform(size=(50, 2))
    w = rng.uniform(0.5, 1.5, size=50)
    out = tilt_to_com(p, w, (0.3, 0.6))
    assert out.sum() == pytest.approx(w.sum())
    assert out @ p / out.sum() == pytest.approx([0.3, 0.6], abs=1e-9)
    # the ratio out / w is exponential in the position (an exponential tilt)
    log_ratio = np.log(out / w)
    design = np.column_stack([np.ones(50), p])
    coef, *_ = np.linalg.lstsq(design, log_ratio, rcond=None)
    assert np.allclose(design @ coef, log_ratio, atol=1e-9)
    with pytest.raises(ValueError, match="strictly inside"):
        tilt_to_com(p, w, (2.0, 0.5))


def test_tilt_that_stalls_at_rounding_level_is_accepted():
    """Obj11, seed 51: Newton stops 0.1 nm short of the 1e-10 m tolerance, 7.7 mm inside the hull.

    This used to raise "not strictly inside the support points" (2 of 6,000 random trials).
    """
    sim = simulators.random_simulator("Obj11", "low", rng=51)
    assert sim.com_m == pytest.approx((0.06738180090598837, -0.010616670141481818), abs=1e-9)


def test_bad_arguments():
    with pytest.raises(ValueError, match="n_support"):
        MassDistribution.on_shape(L_SHAPE, n_support=2)
    with pytest.raises(ValueError, match="mass must be"):
        MassDistribution.on_shape(L_SHAPE, mass=-1.0)
    with pytest.raises(ValueError, match="masses must be finite and > 0"):
        MassDistribution(np.zeros((2, 2)), np.array([1.0, 0.0]), 0.01)


SQUARE = np.array([[0.0, 0.0], [0.08, 0.0], [0.08, 0.06], [0.0, 0.06]])


@pytest.mark.parametrize(
    ("weights", "target", "error", "match"),
    [
        (np.zeros(4), (0.04, 0.03), ValueError, r"weights must be finite and > 0.*\[0, 1, 2, 3\]"),
        (np.array([1.0, 1.0, 1.0, -1.0]), (0.04, 0.03), ValueError, r"weight\(s\) \[3\]"),
        (np.array([1.0, np.nan, 1.0, 1.0]), (0.04, 0.03), ValueError, r"weight\(s\) \[1\]"),
        (np.ones(3), (0.04, 0.03), ValueError, r"weights must have shape \(4,\)"),
        (np.ones(4), None, TypeError, "target must be two finite numbers"),
        (np.ones(4), (0.04, 0.03, 0.0), ValueError, "target must be two finite numbers"),
        (np.ones(4), (0.04, np.inf), ValueError, "target must be two finite numbers"),
    ],
)
def test_tilt_to_com_refuses_what_has_no_tilt_by_name(weights, target, error, match):
    before = weights.copy()
    with pytest.raises(error, match=match):
        tilt_to_com(SQUARE, weights, target)
    np.testing.assert_array_equal(weights, before)


def test_tilt_to_com_refuses_points_of_the_wrong_shape():
    with pytest.raises(ValueError, match=r"points must be finite, of shape \(n, 2\)"):
        tilt_to_com(SQUARE[:, :1], np.ones(4), (0.04, 0.03))


@pytest.mark.parametrize("cell", [float("nan"), float("inf"), -0.01, 0.0])
def test_a_mass_distribution_needs_a_finite_positive_cell_size(cell):
    with pytest.raises(ValueError, match="cell_size_m"):
        MassDistribution(SQUARE, np.ones(4), cell)
