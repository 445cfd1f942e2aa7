"""Tag-tracked objects (comcore/camera/_tags.py) on frames rendered by simulators/tag_frames.py."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest

import comcore
from comcore.camera import (
    TAG_DICTIONARIES,
    TagPose,
    centroid_in_tag,
    motion_from_tags,
    track_tag,
)
from comcore.conventions import apply_motion
from tests.extras import require_simulators

#: An irregular pentagon (pixels, 1 mm each), not symmetric: its masks' motion is measurable.
OUTLINE = np.array([(0, 0), (150, 0), (150, 70), (110, 115), (0, 115)], float) + np.array([100, 70])
#: Its area centroid (the polygon's, not the mask's).
_x, _y = OUTLINE[:, 0], OUTLINE[:, 1]
_cross = _x * np.roll(_y, -1) - np.roll(_x, -1) * _y
CENTROID = np.array(
    [((_x + np.roll(_x, -1)) * _cross).sum(), ((_y + np.roll(_y, -1)) * _cross).sum()]
) / (3 * _cross.sum())
TAG_ID = 3
TAG_SIDE = 40.0  # pixels: 5 px per cell of a 36h11 marker
TAG_AT = CENTROID + np.array([8.0, -5.0])  # where the tag is stuck, at rest
TAG_TURN = 0.4  # the tag's rotation on the object (radians)
SHAPE = (300, 400)
#: A camera that does not look straight down: comcore pixels -> image pixels.
IMAGE_FROM_PIXELS = np.array([[1.02, 0.05, 12.0], [-0.04, 0.98, 6.0], [1e-4, -5e-5, 1.0]])


@pytest.fixture(autouse=True)
def _cv2():
    pytest.importorskip("cv2")


def scene(theta, shift, rng, *, tag_id=TAG_ID, camera=None, **kw):
    """The image of the object turned by ``theta`` about CENTROID and moved by ``shift``."""
    outline = apply_motion(OUTLINE, theta, shift, CENTROID)
    centre = apply_motion(TAG_AT, theta, shift, CENTROID)
    from simulators.tag_frames import render_tag_frame

    return render_tag_frame(
        outline, centre, theta + TAG_TURN, TAG_SIDE, tag_id=tag_id, shape=SHAPE,
        image_from_pixels=camera, rng=rng, **kw,
    )  # fmt: skip


def true_tag(theta, shift) -> np.ndarray:
    return np.array([*apply_motion(TAG_AT, theta, shift, CENTROID), theta + TAG_TURN])


def mask_at(theta, shift) -> comcore.Mask:
    outline = apply_motion(OUTLINE, theta, shift, CENTROID)
    return comcore.Mask(comcore.geometry.rasterise_polygon(outline, SHAPE), resolution=0.001)


def angle_error(a, b) -> float:
    return abs(math.remainder(a - b, 2 * math.pi))


def random_poses(rng, n):
    return [(rng.uniform(-0.6, 0.6), rng.uniform(-15, 15, 2)) for _ in range(n)]


# -- poses --------------------------------------------------------------------------------------
def test_poses_are_recovered_through_a_perspective_camera():
    rng = np.random.default_rng(0)
    poses = random_poses(rng, 6)
    frames = [scene(th, t, rng, camera=IMAGE_FROM_PIXELS) for th, t in poses]
    track = track_tag(frames, TAG_ID, pixels_from_image=np.linalg.inv(IMAGE_FROM_PIXELS))
    assert track.lost == () and set(track.status) == {"found"}
    for (th, t), found in zip(poses, track.poses):
        x, y, theta = true_tag(th, t)
        assert math.hypot(found.x - x, found.y - y) < 0.2
        assert angle_error(found.theta, theta) < math.radians(0.2)
        assert found.side == pytest.approx(TAG_SIDE, abs=0.3)


def test_without_the_homography_the_perspective_camera_reads_wrong():
    """The homography is used, not ignored: the raw image's pose is off by pixels."""
    rng = np.random.default_rng(1)
    frame = scene(0.2, (0.0, 0.0), rng, camera=IMAGE_FROM_PIXELS)
    raw = track_tag([frame], TAG_ID).poses[0]
    x, y, _ = true_tag(0.2, (0.0, 0.0))
    assert math.hypot(raw.x - x, raw.y - y) > 5


def test_a_counter_clockwise_turn_on_screen_gives_a_positive_theta():
    rng = np.random.default_rng(2)
    rest = scene(-TAG_TURN, (0.0, 0.0), rng)  # the tag upright
    assert abs(track_tag([rest], TAG_ID).poses[0].theta) < math.radians(0.2)
    # Turn the image itself 10 degrees counter-clockwise as displayed (OpenCV's positive
    # angle, origin top-left): a convention that does not come from the renderer.
    import cv2

    x, y, _ = true_tag(-TAG_TURN, (0.0, 0.0))
    turn = cv2.getRotationMatrix2D((float(x), float(y)), 10.0, 1.0)
    turned = cv2.warpAffine(rest, turn, SHAPE[::-1], flags=cv2.INTER_LINEAR, borderValue=70)
    track = track_tag([rest, turned], TAG_ID)
    assert track.poses[1].theta == pytest.approx(math.radians(10.0), abs=math.radians(0.2))
    motion = track.motion(0, 1, (0.0, 0.0))  # about the tag's centre, which stays
    assert motion.theta > 0 and motion.sense == 1
    assert math.hypot(motion.tx, motion.ty) < 0.2


def test_a_copy_of_the_marker_far_away_makes_a_frame_ambiguous_after_a_found_one():
    """Each frame is searched whole: a copy away from the last pose is seen."""
    rng = np.random.default_rng(3)
    seen = scene(0.0, (0, 0), rng)
    x, y, _ = true_tag(0.0, (0, 0))
    r0, c0 = int(y) - 30, int(x) - 30
    twice = seen.copy()
    twice[r0 : r0 + 60, c0 + 170 : c0 + 230] = seen[r0 : r0 + 60, c0 : c0 + 60]  # on the table
    assert track_tag([seen, twice], TAG_ID).status == ("found", "ambiguous")
    frames = [scene(th, t, rng) for th, t in random_poses(rng, 3)]
    tracked = track_tag(frames, TAG_ID).poses
    alone = [track_tag([f], TAG_ID).poses[0] for f in frames]
    assert list(tracked) == alone  # frames are read on their own


def test_distorted_frames_are_read_with_the_camera_matrix():
    import cv2

    rng = np.random.default_rng(4)
    k = np.array([[380.0, 0.0, 200.0], [0.0, 380.0, 150.0], [0.0, 0.0, 1.0]])
    dist = np.array([-0.4, 0.1, 0.0, 0.0, 0.0])
    sharp = scene(0.3, (100.0, 80.0), rng)  # what an ideal pinhole camera sees
    # the lens bends it: each distorted pixel shows the undistorted point under it
    rows, cols = np.mgrid[0 : SHAPE[0], 0 : SHAPE[1]].astype(np.float32)
    grid = np.stack([cols, rows], axis=-1).reshape(-1, 1, 2)
    src = cv2.undistortPoints(grid, k, dist, P=k).reshape(SHAPE[0], SHAPE[1], 2)
    bent = cv2.remap(sharp, src[..., 0], src[..., 1], cv2.INTER_LINEAR, borderValue=70)
    x, y, theta = true_tag(0.3, (100.0, 80.0))
    fixed = track_tag([bent], TAG_ID, camera_matrix=k, distortion=dist).poses[0]
    assert math.hypot(fixed.x - x, fixed.y - y) < 0.3
    assert angle_error(fixed.theta, theta) < math.radians(0.3)
    raw = track_tag([bent], TAG_ID).poses[0]
    assert math.hypot(raw.x - x, raw.y - y) > 1.0  # the distortion is there to undo


# -- motions ------------------------------------------------------------------------------------
def test_motions_are_about_the_centroid_before_as_measure_motion_gives_them():
    rng = np.random.default_rng(5)
    poses = random_poses(rng, 6)
    frames = [scene(th, t, rng) for th, t in poses]
    track = track_tag(frames, TAG_ID)
    offset = centroid_in_tag(track.poses[0], mask_at(*poses[0]))
    motions = track.motions(offset)
    assert len(motions) == len(frames) - 1
    for i, motion in enumerate(motions):
        (th0, t0), (th1, t1) = poses[i], poses[i + 1]
        # the centroid turns about itself: it moves by the shift's change only
        truth = comcore.Motion(th1 - th0, *(np.asarray(t1) - t0))
        assert angle_error(motion.theta, truth.theta) < math.radians(0.15)
        assert math.hypot(motion.tx - truth.tx, motion.ty - truth.ty) < 0.3
        masks = comcore.measure_motion(mask_at(th0, t0), mask_at(th1, t1)).motion
        assert angle_error(motion.theta, masks.theta) < math.radians(1.0)
        assert math.hypot(motion.tx - masks.tx, motion.ty - masks.ty) < 1.0
        assert motion == track.motion(i, i + 1, offset)


def test_a_turn_about_the_centroid_moves_the_tag_but_not_the_motion_translation():
    """The translation is the centroid's, not the tag's (which swings about it)."""
    rng = np.random.default_rng(6)
    track = track_tag([scene(0.0, (0, 0), rng), scene(0.5, (0, 0), rng)], TAG_ID)
    swing = math.hypot(track.poses[1].x - track.poses[0].x, track.poses[1].y - track.poses[0].y)
    assert swing > 4
    motion = track.motion(0, 1, centroid_in_tag(track.poses[0], CENTROID))
    assert motion.theta == pytest.approx(0.5, abs=math.radians(0.15))
    assert math.hypot(motion.tx, motion.ty) < 0.2


def test_motion_from_tags_is_rigid_for_any_offset():
    before = TagPose(40.0, 50.0, 0.3, 20.0)
    after = TagPose(47.0, 41.0, 0.8, 20.0)
    for offset in [(0.0, 0.0), (10.0, -3.0), (-25.0, 14.0)]:
        m = motion_from_tags(before, after, offset)
        c0 = np.array([40.0, 50.0]) + comcore.conventions.rotation_matrix(0.3) @ offset
        point = c0 + np.array([5.0, 2.0])  # any body point
        moved = apply_motion(point, m.theta, (m.tx, m.ty), c0)
        tag_point = comcore.conventions.rotation_matrix(-0.3) @ (point - (40, 50))
        expect = np.array([47.0, 41.0]) + comcore.conventions.rotation_matrix(0.8) @ tag_point
        np.testing.assert_allclose(moved, expect, atol=1e-9)
        assert m.theta == pytest.approx(0.5)


# -- lost frames --------------------------------------------------------------------------------
def test_lost_frames_are_reported_never_filled():
    rng = np.random.default_rng(7)
    seen = scene(0.1, (0, 0), rng)
    x, y, _ = true_tag(0.1, (0, 0))
    r0, r1, c0, c1 = int(y) - 35, int(y) + 35, int(x) - 35, int(x) + 35
    hidden = seen.copy()
    hidden[r0 + 20 : r1 - 20, c0:c1] = 60  # the arm across the tag
    gone = scene(0.1, (0.0, 180.0), rng)  # the tag out of view (the object mostly too)
    other = scene(0.1, (0, 0), rng, tag_id=5)
    twice = seen.copy()
    twice[r0:r1, c0 + 150 : c1 + 150] = seen[r0:r1, c0:c1]  # a second marker with the id
    frames = [seen, hidden, gone, other, twice, seen]
    track = track_tag(frames, TAG_ID)
    assert track.status == ("found", "missing", "missing", "missing", "ambiguous", "found")
    assert track.lost == (1, 2, 3, 4)
    assert [p is None for p in track.poses] == [False, True, True, True, True, False]
    motions = track.motions((0.0, 0.0))
    assert motions[:5] == (None,) * 5
    assert track.motion(0, 5, (0.0, 0.0)).theta == pytest.approx(0.0, abs=1e-3)
    with pytest.raises(ValueError, match=r"after frame 2 has no tag pose \(status 'missing'\)"):
        track.motion(0, 2, (0.0, 0.0))
    with pytest.raises(ValueError, match="before must be a frame index below 6, got 6"):
        track.motion(6, 0, (0.0, 0.0))


def test_a_marker_of_the_wrong_size_is_refused_with_tag_size():
    rng = np.random.default_rng(8)
    frame = scene(0.0, (0, 0), rng)
    assert track_tag([frame], TAG_ID, tag_size=0.040, resolution=0.001).status == ("found",)
    wrong = track_tag([frame], TAG_ID, tag_size=0.060, resolution=0.001)
    assert wrong.status == ("wrong_size",) and wrong.lost == (0,)


# -- errors, and nothing changed ----------------------------------------------------------------
def _frame():
    return scene(0.0, (0, 0), np.random.default_rng(9))


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"pixels_from_image": np.eye(2)}, ValueError, r"pixels_from_image must have shape \(3, 3\), got \(2, 2\)"),
        ({"pixels_from_image": np.full((3, 3), np.nan)}, ValueError, "pixels_from_image must be finite"),
        ({"pixels_from_image": np.zeros((3, 3))}, ValueError, "pixels_from_image must be an invertible"),
        ({"pixels_from_image": "eye"}, TypeError, "pixels_from_image must be an array of numbers"),
        ({"pixels_from_image": np.diag([-1.0, 1.0, 1.0])}, ValueError, "pixels_from_image mirrors"),
        ({"tag_size": 0.0, "resolution": 0.001}, ValueError, "tag_size must be a finite number > 0, got 0.0"),
        ({"tag_size": -0.04, "resolution": 0.001}, ValueError, "tag_size must be a finite number > 0"),
        ({"tag_size": 0.04}, ValueError, "tag_size and resolution go together"),
        ({"dictionary": "apriltag_36h12"}, ValueError, r"dictionary must be one of \['apriltag_16h5', .*'4x4_50'"),
        ({"dictionary": 11}, TypeError, "dictionary must be a name"),
        ({"camera_matrix": np.eye(2)}, ValueError, r"camera_matrix must have shape \(3, 3\)"),
        ({"distortion": [0.1, 0.0, 0.0, 0.0]}, ValueError, "distortion needs camera_matrix"),
        ({"camera_matrix": np.eye(3), "distortion": [0.1, 0.2]}, ValueError, "distortion must hold 4, 5"),
    ],
)  # fmt: skip
def test_bad_arguments_are_named(kwargs, error, match):
    with pytest.raises(error, match=match):
        track_tag([_frame()], TAG_ID, **kwargs)


def test_bad_frames_and_ids_are_named():
    frame = _frame()
    with pytest.raises(ValueError, match=r"one 2-D image: pass \[image\]"):
        track_tag(frame, TAG_ID)
    with pytest.raises(TypeError, match=r"images\[0\] must be a uint8 image, got dtype float64"):
        track_tag([frame.astype(float)], TAG_ID)
    with pytest.raises(ValueError, match="images must hold at least one frame"):
        track_tag([], TAG_ID)
    with pytest.raises(ValueError, match=r"tag_id must be in 0..586 for 'apriltag_36h11', got 587"):
        track_tag([frame], 587)
    with pytest.raises(TypeError, match="tag_id must be an int, got float"):
        track_tag([frame], 3.0)
    with pytest.raises(TypeError, match=r"centroid_in_tag must be a point \(x, y\) of 2 numbers, got str"):
        track_tag([frame], TAG_ID).motions("centre")
    with pytest.raises(ValueError, match=r"mask must be a single point of shape \(2,\), got shape \(3,\)"):
        centroid_in_tag(TagPose(0.0, 0.0, 0.0, 1.0), (1.0, 2.0, 3.0))
    with pytest.raises(TypeError, match="before must be a TagPose, got tuple"):
        motion_from_tags((0.0, 0.0, 0.0, 1.0), TagPose(0.0, 0.0, 0.0, 1.0), (0.0, 0.0))


def test_nothing_passed_in_is_changed_and_colour_frames_are_read():
    frame = _frame()
    h = np.diag([0.5, 0.5, 1.0])  # half the size: a homography too
    copies = frame.copy(), h.copy()
    colour = np.repeat(frame[..., None], 3, axis=2)
    grey = track_tag([frame], TAG_ID, pixels_from_image=h)
    assert track_tag([colour], TAG_ID, pixels_from_image=h) == grey
    np.testing.assert_array_equal(frame, copies[0])
    np.testing.assert_array_equal(h, copies[1])
    assert grey.poses[0].side == pytest.approx(TAG_SIDE / 2, abs=0.2)


def test_every_dictionary_is_known_to_opencv():
    import cv2

    for name in TAG_DICTIONARIES:
        assert hasattr(cv2.aruco, "DICT_" + name.upper()), name


def test_without_opencv_the_error_says_which_install(monkeypatch):
    frame = _frame()
    monkeypatch.setitem(sys.modules, "cv2", None)
    monkeypatch.setitem(sys.modules, "cv2.aruco", None)
    with pytest.raises(ImportError, match=r"pip install comcore\[sim\]") as info:
        track_tag([frame], TAG_ID)
    assert isinstance(info.value.__cause__, ImportError)


# -- a session fed by the tag ------------------------------------------------------------------
def test_a_session_takes_the_tag_motions_instead_of_masks():
    simulators = require_simulators()
    from simulators.tag_frames import render_tag_frame

    sim = simulators.random_simulator("Obj3", friction="high", rng=1)
    robot = simulators.SimulatedRobot(sim, resolution=0.001, camera_margin=0.04, rng=0)
    first = robot.camera_mask()
    c0 = np.asarray(first.centroid)
    stuck = c0 + np.array([-6.0, 4.0])  # the tag, 30 mm, near the centroid
    rng = np.random.default_rng(10)

    def frame():
        pose = robot.pose
        outline = robot.simulator.to_pixels(robot.simulator.outline_at(robot.world_pose))
        centre = apply_motion(stuck, pose.theta, (pose.tx, pose.ty), c0)
        return render_tag_frame(outline, centre, pose.theta, 30, shape=first.shape, rng=rng)

    before = track_tag([frame()], 0).poses[0]
    offset = centroid_in_tag(before, first)
    session = comcore.ActiveSession(
        first, rng=0, model=None, stop=comcore.StopRule(max_pushes=6, target_radius=1e-4)
    )
    while not session.done:
        push = robot.execute(session.next_push())
        after = track_tag([frame()], 0).poses[0]
        motion = motion_from_tags(before, after, offset)
        assert angle_error(motion.theta, push.motion.theta) < math.radians(0.3)
        assert math.hypot(motion.tx - push.motion.tx, motion.ty - push.motion.ty) < 0.5
        session.observe(motion=motion)
        before = after
    assert len(session.actions) == 6
    assert angle_error(session.pose.theta, robot.pose.theta) < math.radians(0.5)
    assert math.hypot(session.pose.tx - robot.pose.tx, session.pose.ty - robot.pose.ty) < 1.0
    assert session.estimate().error_px(robot.true_com_px) < 8.0
