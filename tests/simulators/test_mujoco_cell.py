"""The adapter of docs/how-to/your-robot.md on MuJoCo as a cell, and the robot's cell methods."""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

import numpy as np
import pytest

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("EGL_PLATFORM", "surfaceless")
pytest.importorskip("shapely", reason="the simulators need shapely: pip install comcore[sim]")
pytest.importorskip("mujoco", reason="the MuJoCo robot needs mujoco: pip install comcore[mujoco]")

import shapely

import comcore
import simulators
from benchmarks.mujoco.cell_adapter import CellAdapter

ROOT = Path(__file__).resolve().parents[2]
#: An L-shaped plate (table metres), its CoM off the middle.
PLATE = [(0.0, 0.0), (0.09, 0.0), (0.09, 0.03), (0.03, 0.03), (0.03, 0.07), (0.0, 0.07)]
CELL = simulators.CameraSettings((480, 360), tilt=math.radians(28), table="wood", arm=True)


@pytest.fixture(scope="module")
def cell_robot():
    sim = simulators.PushSimulator.from_polygon(PLATE, com=(0.03, 0.022), mu_contact=0.4)
    robot = simulators.MujocoRobot(sim, camera=CELL)
    yield robot
    robot.close()


def _adapter(robot, rng):
    """The adapter as a user makes it: four clicked board points, the empty table, a box."""
    cell = robot.cell_frame()
    x0, y0, x1, y1 = work_area = robot.camera_setup.bounds_m
    table = np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)]) + 0.04 * np.array(
        [(1, 1), (-1, 1), (-1, -1), (1, -1)]
    )
    seen = np.column_stack([table, np.ones(4)]) @ cell.top_to_image.T  # board at the top's height
    clicks = seen[:, :2] / seen[:, 2:] + rng.normal(0.0, 0.5, (4, 2))
    box = (*(cell.outline_m.min(axis=0) - 0.02), *(cell.outline_m.max(axis=0) + 0.02))
    return CellAdapter(clicks, table, [robot.empty_table_frame()], work_area, box), cell


def _truth(view, outline_m) -> np.ndarray:
    """The object rasterised on the view's pixels (a pixel is in if its centre is)."""
    h, w = view.shape
    rows, cols = np.mgrid[0:h, 0:w]
    points = view.table_from_pixels(np.column_stack([cols.ravel(), rows.ravel()]))
    return shapely.contains_xy(shapely.Polygon(outline_m), *points.T).reshape(h, w)


def _iou(a, b) -> float:
    return float((a & b).sum() / (a | b).sum())


def test_the_adapter_gives_the_objects_mask_and_pushes_in_the_arms_metres(cell_robot):
    robot = cell_robot
    adapter, cell = _adapter(robot, np.random.default_rng(3))
    mask = adapter.mask(cell.image)
    truth = _truth(adapter.view, cell.outline_m)
    assert mask.resolution == 0.001 and mask.shape == adapter.view.shape
    assert _iou(mask.data, truth) >= 0.93
    centroid_m = adapter.view.table_from_pixels(mask.centroid)
    assert np.hypot(*(centroid_m - shapely.Polygon(cell.outline_m).centroid.coords[0])) < 0.0015
    session = comcore.ActiveSession(mask, pusher_radius=robot.simulator.pusher_radius, rng=0)
    rest = (robot.camera_setup.bounds_m[2] - 0.03, robot.camera_setup.bounds_m[3] - 0.03)
    for _ in range(2):
        action = session.next_push()
        push_m = adapter.arm_push(action)
        # The push in metres is the session's push: its length, and its start where the
        # session's pixels put it on the table, the object (as the camera saw it) ahead.
        assert push_m.shape == (4,)
        length_px = math.hypot(action.ex - action.sx, action.ey - action.sy)
        assert math.hypot(*(push_m[2:] - push_m[:2])) == pytest.approx(0.001 * length_px)
        outline = shapely.Polygon(robot.outline_m)
        assert not shapely.contains_xy(outline, *push_m[:2])
        assert shapely.intersects(outline, shapely.LineString(push_m.reshape(2, 2)))
        record = robot.execute_table(push_m, rest=rest)
        assert record.hit
        np.testing.assert_allclose(
            robot.simulator.to_world(np.reshape(record.commanded, (2, 2))), push_m.reshape(2, 2),
            atol=1e-9,
        )
        frame = robot.cell_frame()
        mask = adapter.mask(frame.image)  # the arm in view, at rest
        assert _iou(mask.data, _truth(adapter.view, frame.outline_m)) >= 0.93
        session.observe(mask)
    assert [p.outcome for p in session.pushes] == ["evidence", "evidence"]


def test_the_empty_table_frame_leaves_the_scene_as_it_was(cell_robot):
    robot = cell_robot
    pose = robot.world_pose
    before = robot.camera_frame()
    empty = robot.empty_table_frame()
    assert robot.world_pose == pose
    np.testing.assert_array_equal(robot.camera_frame(), before)
    differ = np.abs(empty.astype(int) - before.astype(int)).max(axis=2) > 30
    seen = comcore.geometry.rasterise_polygon(
        _project(robot.cell_frame().top_to_image, robot.outline_m), before.shape[:2]
    )
    assert differ[seen].mean() > 0.9  # the object is gone from the frame, the rest is not
    assert differ[~seen].mean() < 0.05


def test_the_pusher_rests_in_view_but_never_on_the_object(cell_robot):
    robot = cell_robot
    x, y, _ = robot.world_pose
    with pytest.raises(ValueError, match=r"at=\(.*\) puts the pusher on the object"):
        robot.rest_pusher((x, y))
    with pytest.raises(ValueError, match=r"at must be a table point \(x, y\) in metres"):
        robot.rest_pusher((x, y, 0.0))
    with pytest.raises(ValueError, match=r"push_m must be four finite numbers"):
        robot.execute_table([0.0, 0.0, float("nan"), 0.1])
    robot.rest_pusher()  # parked out of view
    parked = robot.camera_frame()
    corner = robot.camera_setup.bounds_m[2] - 0.03, robot.camera_setup.bounds_m[3] - 0.03
    robot.rest_pusher(corner)
    moved = np.abs(robot.camera_frame().astype(int) - parked.astype(int)).max(axis=2) > 30
    assert moved.sum() > 100  # the pusher and its arm in view
    robot.rest_pusher()
    np.testing.assert_array_equal(robot.camera_frame(), parked)


def _project(h, points):
    p = np.column_stack([points, np.ones(len(points))]) @ np.asarray(h).T
    return p[:, :2] / p[:, 2:]


def test_the_how_to_opens_with_the_adapter_the_benchmark_runs():
    page = (ROOT / "docs/how-to/your-robot.md").read_text(encoding="utf-8")
    first = re.search(r"```python\n(.*?)```", page, re.S).group(1)
    assert first == (ROOT / "benchmarks/mujoco/cell_adapter.py").read_text(encoding="utf-8")


@pytest.mark.slow
def test_the_cell_benchmark_runs_on_one_object():
    from tests.scripts import run_script

    out = run_script(
        "benchmarks/mujoco/mujoco_cell.py", "--objects", "Obj3", "--camera", "320", "240",
    )  # fmt: skip
    row = re.search(r"^\| Obj3 \| low \| (\d+\.\d+) \| (\d+) \| (True|False) \| ", out, re.M)
    assert row and int(row.group(2)) >= 1
    assert "| **mean** (1 runs) |" in out
    assert "seed 0, tilt 28 deg, 320x240 camera, green channel, board at the top" in out
