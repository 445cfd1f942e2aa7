"""comcore.testing: the shipped strategies draw valid objects; a Mask prints so it rebuilds."""

import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

import comcore
from comcore import Mask
from comcore.geometry import contacts
from comcore.testing import strategies as cst


def run(code: str) -> str:
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    return out.stdout + out.stderr


def test_import_comcore_does_not_load_hypothesis():
    assert run("import sys, comcore, comcore.testing; print('hypothesis' in sys.modules)").strip() == "False"


def test_strategies_without_hypothesis_name_the_extra():
    out = run(
        "import sys; sys.modules['hypothesis'] = None\n"
        "try:\n    from comcore.testing import strategies\n"
        "except ImportError as e:\n    print(e, '|', type(e.__cause__).__name__)"
    )
    assert "pip install comcore[test] | ModuleNotFoundError" in out


def test_tests_draw_from_the_shipped_strategies():
    from tests import strategies

    assert strategies.masks is cst.masks and strategies.star_polygons is cst.star_polygons


@settings(max_examples=15, deadline=None)
@given(st.data(), st.sampled_from([True, False, None]))
def test_masks_are_one_piece_and_holes_are_enclosed(data, holes):
    mask = data.draw(cst.masks(holes=holes))
    assert mask.area_px >= 200
    assert ndimage.label(mask.data, structure=np.ones((3, 3)))[1] == 1  # 8-connected
    if holes is not None:
        assert (ndimage.binary_fill_holes(mask.data).sum() > mask.area_px) == holes


@settings(max_examples=15, deadline=None)
@given(st.data(), st.booleans())
def test_convex_and_concave_polygons_are_what_they_say(data, convex):
    poly = data.draw(cst.star_polygons(size=20.0, convex=convex))
    edges = np.roll(poly, -1, axis=0) - poly
    following = np.roll(edges, -1, axis=0)
    turns = edges[:, 0] * following[:, 1] - edges[:, 1] * following[:, 0]
    assert (turns.min() < -1e-9 < 1e-9 < turns.max()) != convex


@settings(max_examples=15, deadline=None)
@given(cst.masks_with_pushes(holes=None), st.data())
def test_pushes_start_off_the_object_and_meet_it_and_coms_lie_inside(mask_and_push, data):
    mask, push = mask_and_push
    assert isinstance(push, comcore.Action)
    filled = Mask(ndimage.binary_fill_holes(mask.data), mask.resolution)
    assert not filled.contains([push.start])[0]
    assert contacts(mask, push).hit.all()
    assert mask.contains([data.draw(cst.coms(mask))])[0]


@given(cst.friction_ranges(), cst.motions())
def test_friction_ranges_are_ordered_and_motions_are_small(mu, motion):
    assert 0 <= mu[0] <= mu[1] <= 2
    assert abs(motion.theta) <= 0.6 and max(abs(motion.tx), abs(motion.ty)) <= 6


@settings(max_examples=10, deadline=None)
@given(cst.outlines())
def test_outlines_are_in_metres_and_rasterise(outline):
    assert np.abs(outline).max() <= 0.05 + 1e-12
    assert comcore.geometry.mask_from_outline(outline, resolution=0.0025).area_px > 0


# -- the Mask's repr ---------------------------------------------------------------------------
@settings(max_examples=20, deadline=None)
@given(cst.masks(holes=None), st.sampled_from([0.001, 0.0025, 0.004]))
def test_a_masks_repr_rebuilds_it_exactly(mask, resolution):
    mask = Mask(mask.data, resolution)
    text = repr(mask)
    again = eval(text, {"Mask": Mask})
    assert np.array_equal(again.data, mask.data) and again.resolution == mask.resolution
    assert Mask.from_rle(mask.shape, mask.to_rle(), resolution).area_px == mask.area_px
    assert f"area_px={mask.area_px}" in text and f"{mask.shape}" in text


def test_hypothesis_prints_a_drawn_mask_in_its_rebuildable_form():
    from hypothesis.vendor.pretty import pretty

    mask = Mask(np.pad(np.ones((2, 3), bool), 1), resolution=0.01)
    assert pretty(mask) == repr(mask)


def test_the_repr_states_shape_area_resolution_and_centroid():
    mask = Mask(np.pad(np.ones((2, 3), bool), 1), resolution=0.01)
    assert repr(mask) == (
        "Mask.from_rle((4, 5), '6 3 2 3', resolution=0.01, area_px=6, centroid=(2.0, 1.5))"
    )
    assert Mask(np.ones((2, 2), bool)).to_rle() == "0 4"


@pytest.mark.parametrize(
    ("args", "kwargs", "match"),
    [
        (((4, 5), "6 3 2 3"), {"area_px": 7}, "area_px 7 disagrees with the runs' 6 pixels"),
        (((4, 5), "6 3 2 3"), {"centroid": (2.5, 1.5)}, r"centroid \(2.5, 1.5\) disagrees"),
        (((4, 5), "6 3 2 30"), {}, "adding up to at most 4 \\* 5 = 20 pixels, got runs adding up to 41"),
        (((4, 5), "6 -3"), {}, "non-negative run lengths"),
        (((4, 5), "6 x"), {}, "rle must hold non-negative integers separated by spaces"),
        (((4,), "6 3"), {}, r"shape must be two integers \(H, W\), got \(4,\)"),
        (((0, 5), "6 3"), {}, "shape must be two positive integers"),
        (((4, 5), "6"), {}, "at least one object pixel"),
    ],
)
def test_from_rle_refuses_runs_that_do_not_fit(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        Mask.from_rle(*args, **kwargs)


def test_from_rle_refuses_a_non_string():
    with pytest.raises(TypeError, match="rle must be a string of run lengths, got list"):
        Mask.from_rle((4, 5), [6, 3])
