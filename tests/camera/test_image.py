"""comcore.mask_from_image: a camera image of one object to a Mask."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

import comcore
from comcore.camera._image import otsu_threshold
from simulators import frames
from tests import strategies as cst
from tests.extras import require_simulators


def scene(object_value=30, table_value=200, dtype=np.uint8, shape=(40, 60)):
    """A table with one rectangular object (rows 10..29, cols 15..44)."""
    img = np.full(shape, table_value, dtype)
    img[10:30, 15:45] = object_value
    truth = np.zeros(shape, bool)
    truth[10:30, 15:45] = True
    return img, truth


# -- laws -----------------------------------------------------------------------------------
@settings(max_examples=30)
@given(cst.masks(), st.integers(0, 255), st.integers(0, 255))
def test_an_image_of_a_mask_gives_the_mask_back(mask, object_value, table_value):
    # A rasterised star can leave a pixel notch closed on its four sides (open only
    # diagonally): with the object 8-connected, the table is 4-connected, so that pixel
    # is a hole, and fill_holes (the default) fills it. Without filling, the mask exactly.
    if abs(object_value - table_value) < 1:
        return
    img = np.where(mask.data, object_value, table_value).astype(np.uint8)
    assert np.array_equal(comcore.mask_from_image(img, fill_holes=False).data, mask.data)
    filled = ndimage.binary_fill_holes(mask.data)
    assert np.array_equal(comcore.mask_from_image(img).data, filled)


@pytest.mark.parametrize(
    ("object_value", "table_value", "dtype"),
    [
        (30, 200, np.uint8),
        (220, 10, np.uint8),
        (60000, 1000, np.uint16),
        (0.9, 0.2, np.float32),
        (True, False, bool),
        (255, 0, np.uint8),
    ],
    ids=["dark-uint8", "bright-uint8", "uint16", "float", "bool", "0-255"],
)
def test_grey_images_of_any_type(object_value, table_value, dtype):
    img, truth = scene(object_value, table_value, dtype)
    mask = comcore.mask_from_image(img, resolution=0.001)
    assert np.array_equal(mask.data, truth) and mask.resolution == 0.001


@pytest.mark.parametrize("channels", [3, 4])
def test_colour_images(channels):
    img = np.zeros((40, 60, channels), np.uint8)
    img[...] = (90, 90, 90, 255)[:channels]  # grey table
    img[10:30, 15:45] = (250, 240, 10, 255)[:channels]  # a yellow object
    _, truth = scene()
    assert np.array_equal(comcore.mask_from_image(img).data, truth)


def test_the_input_is_not_changed():
    img, _ = scene()
    copy = img.copy()
    comcore.mask_from_image(img)
    assert np.array_equal(img, copy)


def test_a_given_threshold_and_side_are_used():
    img, truth = scene(object_value=100, table_value=200)
    img[0:5, 0:5] = 150  # a mid-grey patch in a corner
    assert np.array_equal(comcore.mask_from_image(img, threshold=120, object="dark").data, truth)


def test_the_largest_region_is_kept():
    img, truth = scene()
    img[35:37, 2:4] = 30  # a small dark speck
    assert np.array_equal(comcore.mask_from_image(img).data, truth)


def test_holes_are_filled_unless_asked_not_to():
    img, truth = scene()
    img[18:22, 25:30] = 200  # a hole the table shows through
    assert np.array_equal(comcore.mask_from_image(img).data, truth)
    kept = comcore.mask_from_image(img, fill_holes=False)
    assert kept.area_px == truth.sum() - 20


def test_auto_takes_the_side_off_the_border_even_when_it_is_the_majority():
    img = np.full((40, 40), 200, np.uint8)
    img[2:38, 2:38] = 30  # a big dark object, bigger than the bright table around it
    mask = comcore.mask_from_image(img)
    assert mask.area_px == 36 * 36


def test_otsu_splits_two_modes():
    rng = np.random.default_rng(0)
    grey = np.concatenate([rng.normal(50, 5, 500), rng.normal(180, 5, 300)]).reshape(40, 20)
    assert 70 < otsu_threshold(grey) < 160


# -- files ----------------------------------------------------------------------------------
def test_a_path_is_read_with_opencv(tmp_path):
    cv2 = pytest.importorskip("cv2")
    img = np.zeros((40, 60, 3), np.uint8)
    img[...] = (200, 200, 200)
    img[10:30, 15:45] = (0, 0, 255)  # red in RGB order
    path = tmp_path / "scene.png"
    cv2.imwrite(str(path), img[..., ::-1])  # opencv writes BGR
    _, truth = scene()
    assert np.array_equal(comcore.mask_from_image(path).data, truth)
    assert np.array_equal(comcore.mask_from_image(str(path)).data, truth)


def test_a_missing_file_is_named(tmp_path):
    pytest.importorskip("cv2")
    with pytest.raises(ValueError, match=r"could not be read from '.*nowhere\.png'"):
        comcore.mask_from_image(tmp_path / "nowhere.png")


def test_a_path_without_opencv_says_what_to_install(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "cv2", None)
    with pytest.raises(ImportError, match=r"pip install comcore\[sim\]"):
        comcore.mask_from_image(tmp_path / "scene.png")


# -- what the camera saw --------------------------------------------------------------------
@pytest.mark.parametrize("value", [0, 255])
def test_a_constant_image_is_refused(value):
    with pytest.raises(comcore.ImageError, match=f"image is constant \\(every pixel is {value}\\)"):
        comcore.mask_from_image(np.full((20, 20), value, np.uint8))


def test_an_object_touching_the_border_is_refused():
    img = np.full((40, 60), 200, np.uint8)
    img[10:30, 0:20] = 30
    with pytest.raises(comcore.ImageError, match=r"touches the image border \(left\).*out of view"):
        comcore.mask_from_image(img)


def test_a_speckled_image_is_refused():
    rng = np.random.default_rng(1)
    img = (rng.random((60, 60)) < 0.2).astype(np.uint8) * 255
    with pytest.raises(comcore.ImageError, match="speckled result"):
        comcore.mask_from_image(img)


def test_two_objects_of_similar_size_are_refused():
    img = np.full((40, 60), 200, np.uint8)
    img[5:15, 5:15] = 30
    img[20:30, 30:41] = 30
    with pytest.raises(comcore.ImageError, match=r"several objects.*110 and 100 pixels"):
        comcore.mask_from_image(img)


def test_a_threshold_outside_the_image_gives_an_empty_result():
    img, _ = scene()
    with pytest.raises(comcore.ImageError, match=r"no bright pixel at threshold 300.*30 to 200"):
        comcore.mask_from_image(img, threshold=300, object="bright")


# -- bad input ------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("image", "kwargs", "error", "match"),
    [
        (np.zeros((4, 4, 2)), {}, ValueError, r"grey \(H, W\) or colour.*got shape \(4, 4, 2\)"),
        (np.zeros(10), {}, ValueError, "got shape"),
        (np.array([["a"] * 4] * 4), {}, TypeError, "image must be a numeric"),
        (np.full((4, 4), np.nan), {}, ValueError, "NaN or inf"),
        (
            scene()[0],
            {"object": "grey"},
            ValueError,
            "object must be one of 'auto', 'bright', 'dark'",
        ),
        (
            scene()[0],
            {"threshold": "high"},
            ValueError,
            "threshold must be a grey level or one of 'auto', 'otsu', got 'high'",
        ),
        (
            scene()[0],
            {"threshold": [120]},
            TypeError,
            "threshold must be a number, 'auto', 'otsu' or None, got list",
        ),
        (scene()[0], {"threshold": np.inf}, ValueError, "threshold must be finite"),
    ],
)
def test_bad_input_is_named(image, kwargs, error, match):
    with pytest.raises(error, match=match):
        comcore.mask_from_image(image, **kwargs)


def test_mask_of_a_camera_image_points_at_mask_from_image():
    img, _ = scene(0, 255)
    with pytest.raises(ValueError, match=r"got values from 0 to 255.*comcore.mask_from_image"):
        comcore.Mask(img)


# -- a camera's view ------------------------------------------------------------------------
def camera_image(mask, rng, table=180.0, ink=60.0, blur=1.0, noise=8.0):
    """A blurred, noisy uint8 camera image of a dark object given by a mask."""
    from scipy import ndimage

    grey = np.where(mask.data, ink, table)
    grey = ndimage.gaussian_filter(grey, blur) + rng.normal(0.0, noise, grey.shape)
    return np.clip(grey, 0, 255).astype(np.uint8)


def test_a_blurred_noisy_camera_image_of_a_simulated_object():
    simulators = require_simulators()
    pytest.importorskip("shapely")
    sim = simulators.random_simulator("Obj12", "low", rng=0)
    image = camera_image(sim.mask, np.random.default_rng(1))
    mask = comcore.mask_from_image(image)
    overlap = (mask.data & sim.mask.data).sum() / (mask.data | sim.mask.data).sum()
    assert overlap > 0.97


def test_images_to_motion():
    simulators = require_simulators()
    pytest.importorskip("shapely")
    sim = simulators.random_simulator("Obj5", "low", rng=2, margin=0.08)
    res = sim.push(comcore.sample_pushes(sim.mask, 1, cone=0.2, rng=3)[0])
    rng = np.random.default_rng(4)
    before = comcore.mask_from_image(camera_image(sim.mask, rng, noise=3.0))
    after = comcore.mask_from_image(camera_image(sim.mask_at(res.pose), rng, noise=3.0))
    m = comcore.measure_motion(before, after)
    assert not m.ambiguous and abs(m.motion.theta - res.motion.theta) < np.radians(1.0)


# -- camera frames as they are (simulators/frames.py) ---------------------------------------
# Seed 2 here: the thresholds were tuned on seed 0, the benchmark reports seed 1.
FOUND_IOU = 0.9


def wide_frame(condition, index=0, **kwargs):
    c = list(frames.CONDITIONS).index(condition)
    return frames.make_frame(
        np.random.default_rng([2, c, index]), **frames.CONDITIONS[condition], **kwargs
    )


@pytest.mark.parametrize(
    "condition",
    [
        "even",
        "gradient 60",
        "gradient 100",
        "vignetting",
        "frame shadow",
        "cast shadow",
        "textured table",
        "noisy",
        "low contrast",
        "small object",
        "large object",
        "all",
    ],
)
def test_the_object_is_found_in_a_wide_camera_frame(condition):
    frame = wide_frame(condition)
    mask = comcore.mask_from_image(frame.image, resolution=0.001)
    assert mask.shape == (720, 1280)
    assert frames.iou(mask.data, frame.truth) >= FOUND_IOU


@pytest.mark.parametrize("dark", [True, False])
def test_a_small_object_under_a_60_level_gradient_needs_no_option(dark):
    # a robot camera's frame: 1280 x 720, the object 0.2 % of it, the table lit 60+ levels unevenly
    frame = frames.make_frame(np.random.default_rng([2, 100, int(dark)]), gradient=70.0, dark=dark)
    assert frame.truth.sum() / frame.truth.size == pytest.approx(0.002, rel=0.05)
    smooth = ndimage.uniform_filter(frame.image.astype(float), 9)
    table = smooth[~ndimage.binary_dilation(frame.truth, iterations=20)]
    assert table.max() - table.min() >= 60
    with pytest.raises(comcore.ImageError, match="touches the image border"):
        comcore.mask_from_image(frame.image, threshold="otsu")  # comcore 0.1's one level
    mask = comcore.mask_from_image(frame.image)
    assert frames.iou(mask.data, frame.truth) >= FOUND_IOU


@pytest.mark.parametrize("condition", ["empty table", "empty + gradient + texture"])
def test_an_empty_table_is_no_object(condition):
    frame = wide_frame(condition)
    with pytest.raises(comcore.ImageError, match=r"^no object: the image matches the table \("):
        comcore.mask_from_image(frame.image)
    with pytest.raises(comcore.ImageError, match=r"^no object: the image matches the background"):
        comcore.mask_from_image(frame.image, background=frame.background)
    with pytest.raises(comcore.ImageError, match=r"^no object"):
        comcore.mask_from_image(frame.image, roi=frame.roi)


def test_an_image_identical_to_its_background_is_no_object():
    img, _ = scene()
    with pytest.raises(comcore.ImageError, match="no object: the image matches the background"):
        comcore.mask_from_image(img, background=img)


def test_the_background_finds_the_object_where_a_fixed_thing_would_be_a_second_object():
    frame = wide_frame("clutter")
    with pytest.raises(
        comcore.ImageError,
        match=r"several objects.*point=\(x, y\).*roi=\(x0, y0, x1, y1\).*background=",
    ):
        comcore.mask_from_image(frame.image)
    for kwargs in ({"background": frame.background}, {"roi": frame.roi}):
        mask = comcore.mask_from_image(frame.image, **kwargs)
        assert frames.iou(mask.data, frame.truth) >= FOUND_IOU


def test_the_background_takes_off_a_patterned_table():
    found = 0
    for index in range(3):
        frame = wide_frame("cutting mat", index)
        mask = comcore.mask_from_image(frame.image, background=frame.background)
        found += frames.iou(mask.data, frame.truth) >= FOUND_IOU
    assert found == 3


def test_the_background_may_be_a_path_and_is_not_changed(tmp_path):
    cv2 = pytest.importorskip("cv2")
    frame = wide_frame("textured table")
    path = tmp_path / "empty.png"
    cv2.imwrite(str(path), frame.background)
    image, background = frame.image.copy(), frame.background.copy()
    from_path = comcore.mask_from_image(frame.image, background=path)
    from_array = comcore.mask_from_image(frame.image, background=frame.background)
    assert np.array_equal(from_path.data, from_array.data)
    assert np.array_equal(frame.image, image) and np.array_equal(frame.background, background)


def test_a_threshold_with_a_background_is_the_least_difference():
    table = np.tile(np.arange(60, dtype=np.uint8) + 100, (40, 1))  # a ramp: no one grey level
    img = table.copy()
    img[10:30, 15:45] += 30  # the object: 30 levels brighter than the empty table
    mask = comcore.mask_from_image(img, background=table, threshold=25)
    assert mask.area_px == 600 and mask.centroid == (29.5, 19.5)
    assert np.array_equal(comcore.mask_from_image(img, background=table).data, mask.data)
    with pytest.raises(
        comcore.ImageError, match=r"no bright pixel at threshold 40 \(the difference"
    ):
        comcore.mask_from_image(img, background=table, threshold=40, object="bright")


def test_a_roi_looks_only_inside_and_keeps_the_pixel_frame():
    img, truth = scene(shape=(40, 100))
    img[5:35, 70:95] = 30  # a second object, as large, right of x = 60
    with pytest.raises(comcore.ImageError, match="several objects"):
        comcore.mask_from_image(img)
    for roi in ((0, 0, 60, 40), np.arange(100)[None, :].repeat(40, 0) < 60):
        mask = comcore.mask_from_image(img, roi=roi)
        assert mask.shape == (40, 100) and np.array_equal(mask.data, truth)
        assert np.array_equal(comcore.mask_from_image(img, roi=roi, threshold="otsu").data, truth)


def test_a_roi_gives_nearly_the_mask_of_the_whole_frame():
    # the light is fitted in the roi, so a few edge pixels may differ
    frame = wide_frame("all")
    whole = comcore.mask_from_image(frame.image)
    assert frames.iou(comcore.mask_from_image(frame.image, roi=frame.roi).data, whole.data) > 0.99


def test_an_object_cut_by_the_roi_is_refused():
    img, _ = scene()
    with pytest.raises(comcore.ImageError, match=r"touches the edge of roi \(right\).*larger roi"):
        comcore.mask_from_image(img, roi=(0, 0, 30, 40))
    with pytest.raises(comcore.ImageError, match=r"touches the image border \(top\)"):
        comcore.mask_from_image(img[15:], roi=(0, 0, 60, 22))  # cut by the image, not the roi


@pytest.mark.parametrize(
    ("roi", "match"),
    [
        ((0, 0, 2, 40), r"roi \(0, 0, 2, 40\) leaves less than 3 x 3 pixels of the 60 x 40 image"),
        ((1, 2, 3), r"roi must be a box \(x0, y0, x1, y1\)"),
        ((0, 0, np.nan, 5), "roi must be a box"),
        (np.zeros((40, 60), bool), r"roi holds no pixel"),
        (np.ones((60, 40), bool), r"roi as a boolean image must have the image's shape \(40, 60\)"),
    ],
)
def test_a_bad_roi_is_named(roi, match):
    with pytest.raises(ValueError, match=match):
        comcore.mask_from_image(scene()[0], roi=roi)


def test_a_background_of_another_camera_is_refused():
    with pytest.raises(
        ValueError,
        match=r"background must be an image of the empty table .*\(40, 60\), got \(40, 61\)",
    ):
        comcore.mask_from_image(scene()[0], background=np.zeros((40, 61), np.uint8))


def test_the_wrong_side_on_a_lit_table_is_no_object_of_that_side():
    frame = wide_frame("gradient 60", dark=True)
    with pytest.raises(
        comcore.ImageError, match=r"no object: the image matches the table \(no brighter region"
    ):
        comcore.mask_from_image(frame.image, object="bright")


@settings(max_examples=20)
@given(cst.masks(), st.integers(0, 255), st.integers(0, 255))
def test_auto_and_otsu_agree_on_an_evenly_lit_two_level_image(mask, object_value, table_value):
    if abs(object_value - table_value) < 1:
        return
    img = np.where(mask.data, object_value, table_value).astype(np.uint8)
    auto = comcore.mask_from_image(img, threshold="auto")
    assert np.array_equal(auto.data, comcore.mask_from_image(img, threshold="otsu").data)


@pytest.mark.parametrize("scale", [1, 255], ids=["floats k/255 (matplotlib's PNG)", "uint8"])
def test_a_drawn_lit_table_without_noise_is_not_an_object(scale):
    # a ramp rounded to grey levels leaves steps of one level (two where a colour map skips
    # one): they are not objects
    ramp = np.rint(np.linspace(51, 204, 160) + np.arange(160) % 3 // 2) * np.ones((120, 1))
    image = (ramp / 255 * scale).astype(np.float32 if scale == 1 else np.uint8)
    with pytest.raises(comcore.ImageError, match="no object: the image matches the table"):
        comcore.mask_from_image(image)
    image[54:74, 74:94] = 13 / 255 * scale
    assert comcore.mask_from_image(image).area_px == 400


# -- a robot cell's table (tests/camera/cell_frames.py) -------------------------------------
@pytest.mark.parametrize("seed", range(3))
def test_a_cell_frame_with_the_empty_table_and_a_box(seed):
    from tests.camera.cell_frames import iou, make_cell_frame

    frame = make_cell_frame(np.random.default_rng([11, seed]))
    mask = comcore.mask_from_image(frame.image, background=frame.background, roi=frame.box)
    assert iou(mask.data, frame.truth) >= 0.95
    # the soft shadow beside the object is no part of it (one pixel of its blurred edge may be)
    assert frame.shadow.sum() > 1000
    assert not (mask.data & frame.shadow & ~ndimage.binary_dilation(frame.truth)).any()
    # without the empty table: the object, or a refusal that names the empty-table frame
    for kwargs in ({}, {"roi": frame.box}):
        try:
            mask = comcore.mask_from_image(frame.image, **kwargs)
        except comcore.ImageError as e:
            assert "background=" in str(e)
        else:
            assert iou(mask.data, frame.truth) >= 0.95


@pytest.mark.parametrize("seed", range(3))
def test_a_low_contrast_object_is_whole_or_refused_with_its_contrast(seed):
    from tests.camera.cell_frames import iou, make_cell_frame

    frame = make_cell_frame(np.random.default_rng([12, seed]), "low contrast")
    for kwargs in ({"background": frame.background, "roi": frame.box}, {"roi": frame.box}):
        try:
            mask = comcore.mask_from_image(frame.image, **kwargs)
        except comcore.ImageError as e:
            if str(e).startswith("low contrast"):
                assert "grey levels" in str(e) and "times the table's noise" in str(e)
        else:
            assert iou(mask.data, frame.truth) >= 0.95


@pytest.mark.parametrize("seed", range(3))
def test_two_objects_are_refused_saying_how_to_choose_and_a_point_chooses(seed):
    from tests.camera.cell_frames import iou, make_cell_frame

    frame = make_cell_frame(np.random.default_rng([13, seed]), "two objects")
    with pytest.raises(comcore.ImageError, match=r"point=\(x, y\).*roi=\(x0, y0, x1, y1\)"):
        comcore.mask_from_image(frame.image, background=frame.background)
    mask = comcore.mask_from_image(frame.image, background=frame.background, roi=frame.box)
    assert iou(mask.data, frame.truth) >= 0.95


def _glossy_table(rng, shots):
    """A striped table with a glossy patch whose glints change from frame to frame."""
    rows, cols = np.mgrid[0:240, 0:320]
    table = 150 + 20 * np.sin(cols / 5.0)
    glossy = (np.abs(cols - 230) < 60) & (np.abs(rows - 120) < 60)
    glints = [ndimage.gaussian_filter(rng.normal(0, 300, table.shape), 4) for _ in range(shots)]
    frames = [table + rng.normal(0, 3, table.shape) + glossy * g for g in glints]
    return [np.clip(f, 0, 255).astype(np.uint8) for f in frames], table


def test_several_empty_table_frames_set_each_place_s_threshold():
    frames, table = _glossy_table(np.random.default_rng(5), 9)
    truth = np.zeros(table.shape, bool)
    truth[100:140, 65:115] = True
    image = frames[0].copy()
    image[truth] = (table[truth] - 45).astype(np.uint8)
    empty = frames[1:]
    # one frame: the glints differ from it as much as the object
    with pytest.raises(comcore.ImageError, match="speckled result"):
        comcore.mask_from_image(image, background=empty[0])
    kept = [f.copy() for f in empty]
    for background in (empty, np.stack(empty), tuple(empty)):
        mask = comcore.mask_from_image(image, background=background)
        assert np.array_equal(mask.data, truth)
    assert all(np.array_equal(a, b) for a, b in zip(empty, kept))
    # one frame in a stack is that frame
    img = np.full((40, 60), 200, np.uint8)
    img[10:30, 15:45] = 30
    bg = np.full((40, 60), 200, np.uint8)
    assert comcore.mask_from_image(img, background=bg[None]).area_px == 600


@pytest.mark.parametrize(
    "background, match",
    [
        ([], "background holds no frame"),
        ([np.zeros((10, 10))] * 65, "at most 64 frames"),
        ([np.zeros((40, 60)), np.zeros((40, 61))], r"background frame 1 must be an image.*\(40, 61\)"),
    ],
)  # fmt: skip
def test_bad_background_frames_are_named(background, match):
    with pytest.raises(ValueError, match=match):
        comcore.mask_from_image(np.zeros((40, 60), np.uint8), background=background)


def test_a_point_chooses_among_objects_and_the_robot_mask_is_left_out():
    img = np.full((40, 100), 200, np.uint8)
    img[10:30, 15:45] = 30
    img[5:35, 70:95] = 30
    with pytest.raises(comcore.ImageError, match=r"several objects.*point=\(x, y\)"):
        comcore.mask_from_image(img)
    assert comcore.mask_from_image(img, point=(30, 20)).area_px == 600
    assert comcore.mask_from_image(img, point=(80, 20)).area_px == 750
    arm = np.zeros(img.shape, bool)
    arm[:, 60:] = True
    assert comcore.mask_from_image(img, robot_mask=arm).area_px == 600
    arm[:, 44:] = True
    with pytest.raises(comcore.ImageError, match=r"touches the robot \(robot_mask\)"):
        comcore.mask_from_image(img, robot_mask=arm)
    with pytest.raises(ValueError, match="robot_mask must be a boolean image"):
        comcore.mask_from_image(img, robot_mask=arm[:, :50])
    with pytest.raises(ValueError, match=r"point \(500, 20\) must be a pixel"):
        comcore.mask_from_image(img, point=(500, 20))
