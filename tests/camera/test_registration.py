"""comcore.measure_motion: the rigid motion between two masks of one camera."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings

import comcore
from tests import strategies as cst
from tests.extras import require_simulators

SIDE = 120
CENTRE = np.array([60.0, 60.0])


def polygon(n, radius, aspect=1.0, phase=0.0):
    t = phase + np.arange(n) * 2 * np.pi / n
    return CENTRE + np.column_stack([radius * aspect * np.cos(t), radius * np.sin(t)])


def rectangle(half_w, half_h):
    return CENTRE + np.array([[-half_w, -half_h], [half_w, -half_h], [half_w, half_h], [-half_w, half_h]])


L_SHAPE = CENTRE + np.array([[-25, -8], [25, -8], [25, 6], [-11, 6], [-11, 30], [-25, 30]], float)


def pair(vertices, theta, shift=(0.0, 0.0), start=0.37):
    """Masks of ``vertices`` turned by ``start`` (off the pixel grid), then moved by (theta, shift)."""
    v0 = comcore.apply_motion(vertices, start, (0.0, 0.0), CENTRE)
    before = comcore.Mask(comcore.geometry.rasterise_polygon(v0, (SIDE, SIDE)))
    v1 = comcore.apply_motion(v0, theta, shift, before.centroid)
    after = comcore.Mask(comcore.geometry.rasterise_polygon(v1, (SIDE, SIDE)))
    return before, after


def angle_error(measured, truth, order=1):
    """|measured - truth| modulo 2 pi / order, in radians."""
    period = 2 * np.pi / order
    return abs((measured - truth + period / 2) % period - period / 2)


# -- laws -----------------------------------------------------------------------------------
@settings(max_examples=20)
@given(cst.masks())
def test_a_mask_against_itself_did_not_move(mask):
    m = comcore.measure_motion(mask, mask)
    assert abs(m.motion.theta) < 1e-3 and math.hypot(m.motion.tx, m.motion.ty) < 1e-3


def displacement_rms(mask, a, b):
    """RMS distance (px) between the object's pixels moved by motion a and by motion b."""
    pa = comcore.apply_motion(mask.pixels, a[0], a[1:], mask.centroid)
    pb = comcore.apply_motion(mask.pixels, b[0], b[1:], mask.centroid)
    return float(np.sqrt(np.mean(np.sum((pa - pb) ** 2, axis=1))))


@settings(max_examples=30)
@given(cst.moved_polygon_masks())
def test_recovers_the_rigid_motion_of_a_rendered_polygon_to_half_a_pixel(case):
    # the law: the measured motion moves the object's pixels within half a pixel (RMS) of
    # where the true motion moves them (modulo the symmetry); an ambiguous theta is not held to it
    before, after, truth = case
    m = comcore.measure_motion(before, after)
    assert math.hypot(m.motion.tx - truth.tx, m.motion.ty - truth.ty) < 0.5
    if not m.ambiguous:
        period = 2 * np.pi / m.symmetry
        nearest = truth.theta + period * round((m.motion.theta - truth.theta) / period)
        assert displacement_rms(before, m.motion, (nearest, truth.tx, truth.ty)) < 0.5


@settings(max_examples=20)
@given(cst.moved_polygon_masks())
def test_theta_is_the_smallest_consistent_rotation(case):
    m = comcore.measure_motion(*case[:2])
    assert abs(m.motion.theta) <= np.pi / m.symmetry + 1e-9


@settings(max_examples=15)
@given(cst.moved_polygon_masks())
def test_measuring_backwards_gives_the_inverse_rotation(case):
    before, after, _ = case
    forward = comcore.measure_motion(before, after)
    backward = comcore.measure_motion(after, before)
    if not forward.ambiguous and not backward.ambiguous:
        assert angle_error(forward.motion.theta, -backward.motion.theta, forward.symmetry) < 0.02


def test_apply_motion_of_the_measurement_lands_before_on_after():
    before, after = pair(L_SHAPE, 0.25, (4.0, -3.0))
    m = comcore.measure_motion(before, after)
    moved = comcore.apply_motion(before.pixels, m.motion.theta, m.motion[1:], before.centroid)
    assert after.contains(moved).mean() > 0.97
    assert m.residual_px < 0.4 and not m.ambiguous and m.symmetry == 1


def test_counter_clockwise_on_screen_is_positive():
    # a bar along x, turned so that its right end moves UP the screen (to smaller rows)
    bar = rectangle(30, 4) - CENTRE
    c, s = math.cos(0.2), math.sin(0.2)
    turned = np.column_stack([c * bar[:, 0] + s * bar[:, 1], -s * bar[:, 0] + c * bar[:, 1]])
    before = comcore.Mask(comcore.geometry.rasterise_polygon(bar + CENTRE, (SIDE, SIDE)))
    after = comcore.Mask(comcore.geometry.rasterise_polygon(turned + CENTRE, (SIDE, SIDE)))
    right_end = after.pixels[after.pixels[:, 0] > CENTRE[0] + 25]
    assert right_end[:, 1].mean() < CENTRE[1] - 3  # the right end is above the centre now
    assert comcore.measure_motion(before, after).motion.theta == pytest.approx(0.2, abs=0.01)


# -- symmetry and observability --------------------------------------------------------------
@pytest.mark.parametrize(
    ("vertices", "order"),
    [(rectangle(30, 15), 2), (polygon(4, 28), 4), (polygon(6, 30), 6), (polygon(3, 30), 3)],
    ids=["rectangle", "square", "hexagon", "triangle"],
)
def test_a_symmetric_shape_reports_its_order(vertices, order):
    m = comcore.measure_motion(*pair(vertices, 0.15, (3.0, 2.0)))
    assert (m.symmetry, m.ambiguous) == (order, False)
    assert m.motion.theta == pytest.approx(0.15, abs=math.radians(1.0))


def test_a_rectangle_turned_nearly_half_a_turn_reports_the_small_rotation():
    m = comcore.measure_motion(*pair(rectangle(30, 15), math.radians(175)))
    assert m.symmetry == 2
    assert m.motion.theta == pytest.approx(math.radians(-5), abs=math.radians(0.5))


def test_near_theta_picks_the_consistent_rotation_nearest_to_it():
    before, after = pair(rectangle(30, 15), math.radians(100))
    assert comcore.measure_motion(before, after).motion.theta == pytest.approx(
        math.radians(-80), abs=math.radians(1.0)
    )
    m = comcore.measure_motion(before, after, near_theta=1.6)
    assert m.motion.theta == pytest.approx(math.radians(100), abs=math.radians(1.0))


def test_near_theta_puts_an_asymmetric_rotation_on_its_branch():
    m = comcore.measure_motion(*pair(L_SHAPE, math.radians(150)), near_theta=2 * np.pi)
    assert m.motion.theta == pytest.approx(math.radians(150) + 2 * np.pi, abs=math.radians(0.5))


def test_near_theta_must_be_finite():
    mask = comcore.Mask(np.pad(np.ones((10, 10), bool), 5))
    with pytest.raises(ValueError, match="near_theta must be a finite number, got nan"):
        comcore.measure_motion(mask, mask, near_theta=float("nan"))


def test_an_asymmetric_shape_turned_far_is_measured_in_full():
    m = comcore.measure_motion(*pair(L_SHAPE, math.radians(150)))
    assert m.symmetry == 1
    assert m.motion.theta == pytest.approx(math.radians(150), abs=math.radians(0.5))


@pytest.mark.parametrize("radius", [6, 15, 40])
def test_a_disc_is_ambiguous_and_its_translation_is_right(radius):
    m = comcore.measure_motion(*pair(polygon(180, radius), 0.3, (5.0, -2.5)))
    assert m.ambiguous and m.symmetry == 1
    assert (m.motion.tx, m.motion.ty) == pytest.approx((5.0, -2.5), abs=0.3)


def test_a_near_disc_is_ambiguous():
    m = comcore.measure_motion(*pair(polygon(120, 25, aspect=1.03), 0.2))
    assert m.ambiguous


def test_an_elongated_ellipse_is_not_ambiguous():
    m = comcore.measure_motion(*pair(polygon(120, 20, aspect=1.6), 0.2))
    assert not m.ambiguous and m.symmetry == 2
    assert m.motion.theta == pytest.approx(0.2, abs=math.radians(1.0))


def test_a_single_pixel_moved_is_ambiguous_and_its_translation_exact():
    a = np.zeros((20, 20), bool)
    a[10, 10] = True
    b = np.zeros((20, 20), bool)
    b[11, 12] = True
    m = comcore.measure_motion(comcore.Mask(a), comcore.Mask(b))
    assert m.ambiguous and (m.motion.tx, m.motion.ty) == pytest.approx((2.0, 1.0), abs=1e-6)


def test_a_one_pixel_wide_bar_turned_a_quarter_turn():
    a = np.zeros((30, 30), bool)
    a[15, 5:25] = True
    b = np.zeros((30, 30), bool)
    b[5:25, 15] = True
    m = comcore.measure_motion(comcore.Mask(a), comcore.Mask(b))
    assert m.symmetry == 2 and abs(m.motion.theta) == pytest.approx(np.pi / 2, abs=0.01)
    assert m.residual_px < 0.1


# -- simulator-rendered masks ---------------------------------------------------------------
@pytest.mark.parametrize("name", ["Obj5", "Obj14"])
def test_motions_of_simulated_pushes(name):
    simulators = require_simulators()
    pytest.importorskip("shapely")
    sim = simulators.random_simulator(name, "low", rng=3, margin=0.12)
    actions = comcore.sample_pushes(sim.mask, 3, cone=0.3, rng=4)
    for action in actions:
        res = sim.push(action)
        m = comcore.measure_motion(sim.mask, sim.mask_at(res.pose))
        assert (m.symmetry, m.ambiguous) == (1, False)
        assert abs(m.motion.theta - res.motion.theta) < math.radians(0.5)
        assert math.hypot(m.motion.tx - res.motion.tx, m.motion.ty - res.motion.ty) < 0.5


# -- bad input ------------------------------------------------------------------------------
def test_masks_of_different_shapes_are_refused():
    a = comcore.Mask(np.pad(np.ones((10, 10), bool), 5))
    b = comcore.Mask(np.pad(np.ones((10, 10), bool), 6))
    with pytest.raises(
        ValueError, match=r"after must have the shape of before.*\(20, 20\).*\(22, 22\)"
    ):
        comcore.measure_motion(a, b)


def test_masks_of_different_resolutions_are_refused():
    img = np.pad(np.ones((10, 10), bool), 5)
    with pytest.raises(ValueError, match="after must have the resolution of before"):
        comcore.measure_motion(comcore.Mask(img, 0.0025), comcore.Mask(img, 0.001))


def test_an_array_is_refused_with_its_type():
    img = np.pad(np.ones((10, 10), bool), 5)
    with pytest.raises(TypeError, match="before must be a comcore.Mask, got ndarray"):
        comcore.measure_motion(img, comcore.Mask(img))


def test_a_mask_touching_the_border_is_refused():
    inside = comcore.Mask(np.pad(np.ones((10, 10), bool), 5))
    cut = comcore.Mask(np.pad(np.ones((10, 10), bool), ((0, 10), (5, 5))))
    with pytest.raises(comcore.ImageError, match=r"after touches the image border \(top\)"):
        comcore.measure_motion(inside, cut)
    with pytest.raises(ValueError, match="before touches the image border"):
        comcore.measure_motion(cut, inside)


@pytest.mark.parametrize("offset", [(0, 0), (517, 301), (1150, 590)])
def test_a_wide_camera_frame_gives_the_motion_of_the_masks_alone(offset):
    # the fit runs on a window around the two objects: where they lie in a 1280 x 720
    # frame changes nothing, bit for bit
    before, after = pair(L_SHAPE, 0.2, (4.0, -3.0))
    alone = comcore.measure_motion(before, after)

    def in_frame(mask):
        data = np.zeros((720, 1280), bool)
        data[offset[1] : offset[1] + SIDE, offset[0] : offset[0] + SIDE] = mask.data
        return comcore.Mask(data)

    wide = comcore.measure_motion(in_frame(before), in_frame(after))
    assert wide.motion == alone.motion and wide.residual_px == alone.residual_px
    assert (wide.ambiguous, wide.symmetry) == (alone.ambiguous, alone.symmetry)
