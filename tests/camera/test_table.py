"""comcore.calibrate_table: a tilted camera's frames to the table plane and the robot's metres."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import comcore
from comcore.camera import RobotFromTable, fit_robot_from_table

FRAME = (720, 1280)
K = np.array([[900.0, 0, 640], [0, 900.0, 360], [0, 0, 1]])
#: The corners of a printed board, table metres (right-handed seen from above).
BOARD = np.array([(0.15, 0.05), (0.45, 0.05), (0.45, 0.35), (0.15, 0.35)])
#: A convex object on the table, metres, counter-clockwise seen from above.
OBJECT = np.array([(0.27, 0.17), (0.34, 0.18), (0.355, 0.225), (0.31, 0.255), (0.265, 0.23)])
REGION = (0.2, 0.1, 0.4, 0.3)


def camera_homography(tilt_deg: float, *, look_at=(0.3, 0.2), distance=0.8) -> np.ndarray:
    """Table metres to pixels of a pinhole camera ``distance`` from ``look_at``, tilted."""
    a = np.radians(tilt_deg)
    down = np.diag([1.0, -1.0, -1.0])  # camera x = table x, image y down = table -y
    tilt = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    r = tilt @ down
    centre = np.array([*look_at, 0.0]) - distance * r.T @ np.array([0, 0, 1.0])
    t = -r @ centre
    h = K @ np.column_stack([r[:, 0], r[:, 1], t])
    return h / h[2, 2]


def project(h, points, distortion=None):
    p = np.column_stack([points, np.ones(len(points))]) @ h.T
    p = p[:, :2] / p[:, 2:]
    if distortion is None:
        return p
    import cv2

    rays = np.column_stack([(p - K[:2, 2]) / np.diag(K)[:2], np.ones(len(p))])
    out, _ = cv2.projectPoints(rays, np.zeros(3), np.zeros(3), K, distortion)
    return out.reshape(-1, 2)


def inside(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Which points lie in a convex counter-clockwise polygon."""
    ok = np.ones(len(points), bool)
    for a, b in zip(polygon, np.roll(polygon, -1, axis=0)):
        ok &= (b[0] - a[0]) * (points[:, 1] - a[1]) - (b[1] - a[1]) * (points[:, 0] - a[0]) >= 0
    return ok


def render(h, rng, distortion=None, samples=3):
    """A noisy uint8 camera frame of the dark object on a light table, anti-aliased."""
    offsets = (np.arange(samples) + 0.5) / samples - 0.5
    (x0, y0), (x1, y1) = (
        project(h, OBJECT, distortion).min(0) - 8,
        project(h, OBJECT, distortion).max(0) + 8,
    )
    rows, cols = np.mgrid[int(y0) : int(y1), int(x0) : int(x1)]
    cover = np.zeros(FRAME)
    inv = np.linalg.inv(h)
    for dy in offsets:
        for dx in offsets:
            pix = np.column_stack([cols.ravel() + dx, rows.ravel() + dy])
            if distortion is not None:
                import cv2

                pix = cv2.undistortPoints(pix.reshape(-1, 1, 2), K, distortion, P=K).reshape(-1, 2)
            table = np.column_stack([pix, np.ones(len(pix))]) @ inv.T
            cover[rows, cols] += inside(table[:, :2] / table[:, 2:], OBJECT).reshape(rows.shape)
    grey = 190 - 130 * cover / samples**2 + rng.normal(0, 3, FRAME)
    return np.clip(np.rint(grey), 0, 255).astype(np.uint8)


def polygon_centroid(poly):
    x, y = poly.T
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = cross.sum() / 2
    return np.array(
        [((x + np.roll(x, -1)) * cross).sum(), ((y + np.roll(y, -1)) * cross).sum()]
    ) / (6 * area)


@pytest.mark.parametrize(
    ("tilt", "lens"), [(20, False), (28, False), (35, False), (30, True)], ids=str
)
def test_a_tilted_view_rectifies_to_the_object_on_the_table(tilt, lens):
    distortion = np.array([-0.12, 0.03, 0.001, -0.0005, 0.0]) if lens else None
    if lens:
        pytest.importorskip("cv2")
    h = camera_homography(tilt)
    rng = np.random.default_rng(tilt)
    frame = render(h, rng, distortion)
    seen = project(h, BOARD, distortion) + rng.normal(0, 0.3, (4, 2))
    intrinsics = {"camera_matrix": K, "distortion": distortion} if lens else {}
    cal = comcore.calibrate_table(seen, BOARD, **intrinsics)
    view = cal.view(REGION, resolution=0.001)
    top = view.rectify(frame)
    assert top.shape == view.shape == (201, 201) and top.dtype == np.uint8
    mask = comcore.mask_from_image(top, resolution=view.resolution)
    rows, cols = np.mgrid[0 : view.shape[0], 0 : view.shape[1]]
    centres = np.column_stack([cols.ravel(), rows.ravel()])
    truth = inside(view.table_from_pixels(centres), OBJECT).reshape(view.shape)
    iou = (mask.data & truth).sum() / (mask.data | truth).sum()
    assert iou >= 0.95
    centroid = view.table_from_pixels(np.array(mask.centroid))
    assert np.hypot(*(centroid - polygon_centroid(OBJECT))) <= 0.002
    # one resolution for the whole camera frame would not do: the scale changes across it
    edges = project(h, np.array([(0.3, 0.05), (0.31, 0.05), (0.3, 0.35), (0.31, 0.35)]))
    lengths = np.hypot(*(edges[1::2] - edges[::2]).T)
    assert lengths.max() / lengths.min() > 1.1


def test_pixels_table_and_robot_round_trip():
    h = camera_homography(25)
    robot = RobotFromTable(np.radians(30), 0.4, -0.1)
    cal = comcore.calibrate_table(project(h, BOARD), BOARD, robot=robot)
    assert cal.residual_px < 1e-6
    points = np.array([(0.21, 0.12), (0.33, 0.29)])
    assert np.allclose(cal.table_from_image(cal.image_from_table(points)), points)
    assert np.allclose(robot.invert(cal.robot_from_table(points)), points)
    view = cal.view(REGION, resolution=0.002)
    assert np.allclose(view.pixels_from_table(view.table_from_pixels(points * 100)), points * 100)
    # row 0 is the region's far edge: y up the top-down image is y up the table
    assert np.allclose(view.table_from_pixels([(0, 0), (10, 5)]), [(0.2, 0.3), (0.22, 0.29)])
    # the robot's frame: the table turned 30 degrees counter-clockwise and moved
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    expected = np.array([0.4 + c * 0.2 - s * 0.3, -0.1 + s * 0.2 + c * 0.3])
    assert np.allclose(view.robot_from_pixels((0, 0)), expected)


def test_a_sessions_pushes_come_out_in_the_robots_metres():
    cal = comcore.calibrate_table(project(camera_homography(30), BOARD), BOARD,
                                  robot=RobotFromTable(np.pi / 2, 0.5, 0.0))  # fmt: skip
    view = cal.view(REGION, resolution=0.001)
    pushes = [comcore.Action(0, 100, 50, 100), comcore.Action(100, 0, 100, 40)]
    out = view.robot_pushes(pushes)
    assert out.shape == (2, 4)
    # push 0 runs along table +x from (0.2, 0.2): in the robot's frame, +y from (0.3, 0.2)
    assert np.allclose(out[0], [0.5 - 0.2, 0.2, 0.5 - 0.2, 0.25])
    # push 1 runs down the image: table -y, robot +x
    assert np.allclose(out[1], [0.5 - 0.3, 0.3, 0.5 - 0.26, 0.3])
    assert np.allclose(view.robot_pushes(np.array([tuple(p) for p in pushes])), out)


def test_the_robots_frame_is_fitted_from_touched_points_with_its_residual():
    rng = np.random.default_rng(3)
    table = rng.uniform(0, 0.5, (6, 2))
    truth = RobotFromTable(-0.7, 0.25, 0.6)
    touched = truth.apply(table) + rng.normal(0, 0.0005, table.shape)
    fit = fit_robot_from_table(table, touched)
    assert abs(fit.theta - truth.theta) < 0.01 and np.hypot(fit.tx - 0.25, fit.ty - 0.6) < 0.002
    assert 0.0002 < fit.residual < 0.001
    expected = np.sqrt(np.mean(np.sum((fit.apply(table) - touched) ** 2, axis=1)))
    assert fit.residual == pytest.approx(expected)


# -- mistakes -------------------------------------------------------------------------------
IMAGE = project(camera_homography(25), BOARD)


@pytest.mark.parametrize(
    ("image", "table", "match"),
    [
        (IMAGE[:3], BOARD[:3], r"image_points must hold at least 4 points, got 3"),
        (IMAGE, np.array([(0, 0), (0.1, 0), (0.2, 0), (0.3, 0)]), r"table_points lie on a line"),
        (IMAGE, np.array([(0, 0), (0.1, 0), (0.1, 0), (0, 0.1)]),
         r"table_points repeats a point \(points 1 and 2"),
        (IMAGE, np.array([(0, 0), (0.1, 0), (0.2, 0), (0, 0.1)]), r"three of the four points lie on a line \(all but point 3\)"),
        (IMAGE, BOARD * 1000, r"span 424.264 m.*millimetres given for metres\? divide by 1000"),
        (IMAGE, BOARD * [1, -1], r"mirrored.*y down the table, or swap x and y"),
        (IMAGE, BOARD[:, ::-1], r"mirrored"),
        (IMAGE, BOARD[:3], r"must hold the same points, got 4 and 3"),
    ],
    ids=["three", "collinear", "repeated", "three of four on a line", "millimetres",
         "y down", "x and y swapped", "counts"],
)  # fmt: skip
def test_degenerate_points_are_named(image, table, match):
    with pytest.raises(ValueError, match=match):
        comcore.calibrate_table(image, table)


def test_bad_views_and_intrinsics_are_named():
    cal = comcore.calibrate_table(IMAGE, BOARD)
    with pytest.raises(ValueError, match=r"resolution 1 m per pixel is implausible.*millimetres"):
        cal.view(REGION, resolution=1.0)
    with pytest.raises(ValueError, match=r"region must be \(x_min, y_min, x_max, y_max\)"):
        cal.view((0.4, 0.1, 0.2, 0.3), resolution=0.001)
    with pytest.raises(ValueError, match="larger than MAX_IMAGE_PIXELS"):
        cal.view((0, 0, 100, 100), resolution=0.001)
    with pytest.raises(ValueError, match="reaches the camera's horizon"):
        cal.view((0, 0, 4, 4), resolution=0.01)
    with pytest.raises(ValueError, match="distortion needs camera_matrix"):
        comcore.calibrate_table(IMAGE, BOARD, distortion=[0.1, 0, 0, 0])
    with pytest.raises(ValueError, match=r"camera_matrix must be a finite 3 x 3"):
        comcore.calibrate_table(IMAGE, BOARD, camera_matrix=np.eye(2))
    with pytest.raises(ValueError, match="robot_points match table_points only through a mirror"):
        fit_robot_from_table(BOARD, BOARD * [1, -1] + 1)
    with pytest.raises(TypeError, match="robot must be a RobotFromTable"):
        comcore.calibrate_table(IMAGE, BOARD, robot=(0, 0, 0))


def test_a_lens_without_opencv_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "cv2", None)
    with pytest.raises(ImportError, match=r"pip install comcore\[sim\]"):
        comcore.calibrate_table(IMAGE, BOARD, camera_matrix=K, distortion=[0.1, 0, 0, 0])


def test_the_inputs_are_not_changed_and_colour_frames_keep_their_channels():
    image, table = IMAGE.copy(), BOARD.copy()
    cal = comcore.calibrate_table(image, table)
    assert np.array_equal(image, IMAGE) and np.array_equal(table, BOARD)
    assert not cal.homography.flags.writeable
    frame = np.zeros((*FRAME, 3), np.uint8)
    frame[..., 1] = 200
    view = cal.view(REGION, resolution=0.002)
    top = view.rectify(frame)
    assert top.shape == (*view.shape, 3) and np.all(top[..., 1] == 200)
    assert view.in_view(FRAME).all()
