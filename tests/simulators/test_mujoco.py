"""simulators.MujocoRobot: MuJoCo's physics and rendered camera as the robot (needs comcore[mujoco])."""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest

# Offscreen rendering: set before mujoco is first imported (as a user must, docs/how-to/mujoco.md).
os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("EGL_PLATFORM", "surfaceless")
pytest.importorskip("shapely", reason="the simulators need shapely: pip install comcore[sim]")
pytest.importorskip("mujoco", reason="the MuJoCo robot needs mujoco: pip install comcore[mujoco]")

import comcore
import simulators

SMALL = simulators.CameraSettings(image_size=(200, 150))
#: A 10 x 6 cm plate whose CoM is off its centre (point mass and tilt).
PLATE = [(0.0, 0.0), (0.10, 0.0), (0.10, 0.06), (0.0, 0.06)]


@pytest.fixture(scope="module")
def plate():
    sim = simulators.PushSimulator.from_polygon(PLATE, com=(0.06, 0.025), mu_contact=0.5)
    robot = simulators.MujocoRobot(sim, camera=SMALL)
    yield sim, robot
    robot.close()


def test_the_scenes_centre_of_mass_is_the_trials(plate):
    sim, robot = plate
    assert np.allclose(robot.com_body, sim.com_m, atol=1e-6)  # MuJoCo's, from the pieces
    mass = float(robot.model.body_mass[robot.model.body("object").id])
    assert mass == pytest.approx(sim.mass.total_mass, rel=1e-6)


def test_point_masses_keep_the_centre_of_mass():
    sim = simulators.random_simulator("Obj12", friction="low", rng=3)
    trial = simulators.PushSimulator.from_shape(
        sim.shape, point_masses=[(*sim.shape.centroid_m, 0.8)], com=None
    )
    robot = simulators.MujocoRobot(trial, camera=SMALL)
    assert np.allclose(robot.com_body, trial.com_m, atol=1e-6)


def _push_from_start(robot, action):
    robot.place(None)
    return robot.execute(action)


def test_a_push_through_the_com_translates_without_turning(plate):
    _sim, robot = plate
    grid = robot.simulator
    through = simulators.normal_pushes_through_com(grid)
    for action in through[:2]:  # the long and the short side
        push = _push_from_start(robot, action)
        assert push.hit
        assert abs(push.motion.theta) < math.radians(1.5)
        assert math.hypot(push.motion.tx, push.motion.ty) * grid.resolution > 0.02


@pytest.mark.parametrize("side", [-1, 1])
def test_an_off_centre_push_turns_the_voting_theorems_way(plate, side):
    # Down onto the top edge, 3 cm left (right) of the CoM: the CoM is to its right (left),
    # so the object turns counter-clockwise (clockwise), as the exact engine does.
    sim, robot = plate
    grid = robot.simulator
    start = (sim.com_m[0] + side * 0.03, 0.07)
    push = _push_from_start(robot, simulators.action_from_world(grid, start, (0.0, -1.0)))
    exact = grid.push(simulators.action_from_world(grid, start, (0.0, -1.0))).motion
    assert np.sign(push.motion.theta) == -side == np.sign(exact.theta)
    assert abs(push.motion.theta) > math.radians(3)


def test_the_object_is_never_reset(plate):
    sim, robot = plate
    robot.place(None)
    grid = robot.simulator
    start = (sim.com_m[0] - 0.03, 0.07)
    before = robot.pushes
    first = robot.execute(simulators.action_from_world(grid, start, (0.0, -1.0), travel_m=0.02))
    mask = robot.camera_mask()
    action = comcore.sample_pushes(mask, 1, rng=0)[0]
    second = robot.execute(action)
    assert robot.pushes == before + 2 and first.pose != second.pose
    assert second.pose == robot.pose


def test_the_rendered_mask_is_the_polygon_under_the_homography(plate):
    sim, robot = plate
    robot.place(None)
    truth = robot.simulator.mask  # the footprint rasterised on the grid at the start
    mask = robot.camera_mask()
    assert mask.resolution == robot.resolution and mask.shape == truth.shape
    assert abs(mask.area_px - truth.area_px) < 0.04 * truth.area_px
    assert np.hypot(*np.subtract(mask.centroid, truth.centroid)) < 1.0
    # The raw (perspective) frame: the object's centroid where the homography puts it.
    frame = robot.camera_frame()
    assert frame.dtype == np.uint8 and frame.shape == (150, 200, 3)
    raw = comcore.mask_from_image(frame)
    h = robot.homography_table_to_image()
    p = h @ [*sim.shape.centroid_m, 1.0]
    assert np.hypot(*(np.asarray(raw.centroid) - p[:2] / p[2])) < 1.0


def test_a_push_starting_inside_is_refused_and_changes_nothing(plate):
    _sim, robot = plate
    robot.place(None)
    pose, pushes = robot.world_pose, robot.pushes
    c = robot.simulator.com_px
    with pytest.raises(ValueError, match="action must start outside"):
        robot.execute((c[0], c[1], c[0] + 10, c[1]))
    with pytest.raises(ValueError, match="single action"):
        robot.execute([[0, 0, 1, 1], [0, 0, 2, 2]])
    assert robot.world_pose == pose and robot.pushes == pushes


@pytest.mark.parametrize("half", [1e12, 1e300])
def test_a_push_past_the_simulators_length_bound_is_refused_before_stepping(plate, half):
    _sim, robot = plate
    robot.place(None)
    pose, pushes, time = robot.world_pose, robot.pushes, robot.data.time
    y = robot.simulator.com_px[1]
    with pytest.raises(ValueError, match="action must be at most .* m long"):
        robot.execute((-half, y, half, y))
    assert robot.world_pose == pose and robot.pushes == pushes and robot.data.time == time


def test_an_unstable_simulation_raises_and_leaves_no_log_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # where MuJoCo writes MUJOCO_LOG.TXT unless told otherwise
    sim = simulators.PushSimulator.from_polygon(PLATE)
    robot = simulators.MujocoRobot(
        sim, settings=simulators.MujocoSettings(pusher_gain=1e30), camera=SMALL
    )
    pose = robot.world_pose
    c = robot.simulator.com_px
    with pytest.raises(RuntimeError, match="unstable during push 1.*pusher_gain"):
        robot.execute((c[0] - 30, c[1], c[0] + 10, c[1]))
    assert robot.pushes == 0 and np.allclose(robot.world_pose, pose, atol=1e-12)
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()


def test_bad_arguments_are_named():
    with pytest.raises(TypeError, match="simulator must be a simulators.PushSimulator"):
        simulators.MujocoRobot("Obj1")
    sim = simulators.PushSimulator.from_polygon(PLATE)
    with pytest.raises(TypeError, match="settings must be a simulators.MujocoSettings"):
        simulators.MujocoRobot(sim, settings={"timestep": 0.001})
    with pytest.raises(ValueError, match="contact_timeconst must be at least 2 \\* timestep"):
        simulators.MujocoSettings(timestep=0.002)
    with pytest.raises(ValueError, match="fov must be in \\(0, pi\\) radians"):
        simulators.CameraSettings(fov=45)
    with pytest.raises(ValueError, match="image_size must be \\(width, height\\)"):
        simulators.CameraSettings(image_size=(640,))
    with pytest.raises(ValueError, match="shadow_size must be in \\[64, 16384\\] texels"):
        simulators.CameraSettings(shadow_size=32)
    with pytest.raises(TypeError, match="shadow_size must be an int"):
        simulators.CameraSettings(shadow_size=1024.0)
    with pytest.raises(ValueError, match="camera_margin must be a finite number > 0"):
        simulators.MujocoRobot(sim, camera_margin=-1)
    with pytest.raises(TypeError, match="pose must be three numbers"):
        simulators.MujocoRobot(sim, camera=SMALL).place("here")


def test_the_callers_simulator_is_not_modified():
    sim = simulators.PushSimulator.from_polygon(PLATE, com=(0.04, 0.03))
    mask, margin = sim.mask.data.copy(), sim.margin
    simulators.MujocoRobot(sim, camera=SMALL, resolution=0.003)
    assert np.array_equal(sim.mask.data, mask) and sim.margin == margin


def test_the_mujoco_robot_takes_frames_at_a_rate_not_a_count(plate):
    _sim, robot = plate
    action = comcore.sample_pushes(robot.camera_mask(), 1, rng=0)[0]
    pose, pushes = robot.world_pose, robot.pushes
    with pytest.raises(ValueError, match=r"frames=3: .* no count of frames; .* give frame_rate="):
        robot.execute(action, frames=3)
    for rate, error in (
        (0, ValueError),
        (math.nan, ValueError),
        (True, TypeError),
        ("10", TypeError),
    ):
        with pytest.raises(error, match="frame_rate must be"):
            robot.execute(action, frame_rate=rate)
    with pytest.raises(
        ValueError, match=r"frame_rate must be at most one frame per time step \(1000 Hz"
    ):
        robot.execute(action, frame_rate=5000)
    assert robot.world_pose == pose and robot.pushes == pushes


def test_frames_during_a_push_register_to_the_true_poses(plate):
    sim, robot = plate
    robot.place(None)
    first = robot.camera_mask()
    grid = robot.simulator
    start = (sim.com_m[0] - 0.02, 0.07)  # down onto the top edge, left of the CoM: it turns
    action = simulators.action_from_world(grid, start, (0.0, -1.0), travel_m=0.015)
    push = robot.execute(action, frame_rate=10)
    speed, times = robot.settings.speed, np.array(push.path_times)
    length = 0.025  # the standoff (1 cm) and the travel: the pusher's set point's path
    assert len(push.path) == len(push.path_poses) == 24  # 0.1 s ... 2.4 s of the 2.5 s push
    np.testing.assert_allclose(times, 0.1 * np.arange(1, 25), rtol=0, atol=1e-9)
    assert times[-1] < length / speed
    start_px, end_px = np.asarray(action[:2]), np.asarray(action[2:])
    unit = (end_px - start_px) / np.hypot(*(end_px - start_px))
    for frame, t, pose in zip(push.path, times, push.path_poses):
        offset = np.asarray(frame.pusher) - start_px
        across = offset[0] * unit[1] - offset[1] * unit[0]
        along = offset @ unit * grid.resolution
        assert abs(across) < 0.5  # on the path, the servo a fraction of a millimetre behind
        assert speed * t - 0.002 < along <= speed * t + 1e-4
        seen = comcore.measure_motion(first, frame.view).motion
        assert abs(seen.theta - pose.theta) < math.radians(1.5)
        assert math.hypot(seen.tx - pose.tx, seen.ty - pose.ty) < 1.5
    poses = np.array(push.path_poses)
    assert abs(poses[-1, 0]) > math.radians(2)  # it turned, and the frames saw it turn
    assert abs(push.pose.theta - poses[-1, 0]) < math.radians(1.5)


def test_frames_leave_the_physics_alone_and_a_refused_frame_undoes_the_push(plate, monkeypatch):
    sim, robot = plate
    robot.place(None)
    grid = robot.simulator
    start = (sim.com_m[0] - 0.02, 0.065)
    action = simulators.action_from_world(grid, start, (0.0, -1.0), 0.005, 0.005)
    state, pushes, pose = robot._state(), robot.pushes, robot.world_pose
    plain = robot.execute(action)
    robot._restore(state)
    assert robot.world_pose == pose
    framed = robot.execute(action, frame_rate=10)
    assert framed.world_pose == plain.world_pose and framed.path and not plain.path
    robot._restore(state)
    calls = []

    def refuses_the_third(image, **options):
        calls.append(options)
        if len(calls) == 3:
            raise comcore.ImageError("no object: a test")
        return mask_from_image(image, **options)

    mask_from_image = comcore.mask_from_image
    monkeypatch.setattr(comcore, "mask_from_image", refuses_the_third)
    with pytest.raises(
        comcore.ImageError, match=r"the frame at t = 0\.15 s of push \d+: no object"
    ):
        robot.execute(action, frame_rate=20)
    assert calls[0] == {"resolution": robot.resolution, "object": "bright"}
    assert robot.world_pose == pose and robot.pushes == pushes + 2


def test_comcore_bench_runs_active_robot_on_mujoco(tmp_path):
    """``--conditions mujoco``: the session on MuJoCo's physics and rendered frames."""
    from comcore.bench import CONDITIONS, parse_condition
    from comcore.cli import main

    assert "mujoco" not in CONDITIONS  # not among "all": it needs an extra
    assert parse_condition("mujoco").robot_engine == "mujoco"
    with pytest.raises(ValueError, match="MuJoCo robot takes no"):
        parse_condition("mujoco(pusher_error=0.003)").robot(
            simulators.PushSimulator.from_polygon(PLATE), None
        )
    args = ["bench", "--objects", "Obj1", "--trials", "1", "--friction", "low",
            "--estimators", "active-robot", "--conditions", "mujoco", "--workers", "1",
            "--out", str(tmp_path), "--no-figures", "--no-progress"]  # fmt: skip
    assert main(args) == 0
    rows = [json.loads(line) for line in (tmp_path / "conditions.jsonl").read_text().splitlines()]
    (row,) = rows
    assert row["condition"] == "mujoco" and row["status"] in ("ok", "budget")
    assert row["error_cm"] < 1.5 and row["pushes_used"] >= 1


def test_a_smaller_shadow_map_is_the_scenes_and_the_mask_keeps_its_object(plate):
    """CameraSettings(shadow_size=...) sets MuJoCo's shadow map; the object's mask stays
    within the segmentation's edge pixels of the default's."""
    sim, robot = plate
    robot.place(None)
    coarse = simulators.MujocoRobot(
        sim, camera=simulators.CameraSettings(image_size=SMALL.image_size, shadow_size=512)
    )
    try:
        assert int(robot.model.vis.quality.shadowsize) == 4096
        assert int(coarse.model.vis.quality.shadowsize) == 512
        sharp, soft = robot.camera_mask(), coarse.camera_mask()
        differ = int(np.count_nonzero(sharp.data ^ soft.data))
        assert differ < 0.05 * sharp.area_px
        assert np.hypot(*np.subtract(sharp.centroid, soft.centroid)) < 0.5
    finally:
        coarse.close()


def test_a_tilted_cells_frame_comes_with_its_camera_model_and_the_objects_outline():
    camera = simulators.CameraSettings((160, 120), tilt=0.5, table="wood", arm=True)
    sim = simulators.PushSimulator.from_polygon(PLATE, com=(0.06, 0.025))
    robot = simulators.MujocoRobot(sim, camera=camera)
    cell = robot.cell_frame()
    assert cell.image.dtype == np.uint8 and cell.image.shape == (120, 160, 3)
    # The homography is the camera model's: K [r1 r2 t] for the plane z = 0.
    fx, fy, cx, cy = cell.intrinsics
    k = np.array([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]])
    r, c = cell.camera_rotation, cell.camera_position
    model = k @ np.column_stack([r.T[:, 0], r.T[:, 1], -r.T @ c])
    np.testing.assert_allclose(model / model[2, 2], cell.table_to_image / cell.table_to_image[2, 2])
    # Looking down at about the tilt asked for, and the scale changes across the frame.
    assert math.degrees(math.acos(-r[2, 2])) == pytest.approx(math.degrees(0.5), abs=1e-6)
    near, far = (
        _metres_per_pixel(cell.table_to_image, 110.0),
        _metres_per_pixel(cell.table_to_image, 10.0),
    )
    assert far > 1.2 * near
    # The rendered object is where the top face's homography puts its outline (the frame
    # rectified on the top face's plane: the object's colour inside the outline only).
    outline_px = _project(cell.top_to_image, cell.outline_m)
    inside = comcore.geometry.rasterise_polygon(outline_px, cell.image.shape[:2])
    rgb = cell.image.astype(float)
    yellow = (rgb[..., 0] > 180) & (rgb[..., 2] < 0.55 * rgb[..., 0])
    assert (yellow & inside).sum() >= 0.9 * inside.sum()
    assert (yellow & ~inside).sum() <= 0.1 * inside.sum()
    robot.close()


def _project(h, points_m):
    p = np.column_stack([points_m, np.ones(len(points_m))]) @ np.asarray(h).T
    return p[:, :2] / p[:, 2:]


def _metres_per_pixel(h, row):
    """Table metres one image pixel spans along x at the middle column of ``row``."""
    inv = np.linalg.inv(h)
    a, b = _project(inv, np.array([[79.5, row], [80.5, row]]))
    return float(np.hypot(*(b - a)))


def test_the_cells_table_texture_and_arm_are_drawn_and_the_defaults_are_the_plain_scene():
    sim = simulators.PushSimulator.from_polygon(PLATE, com=(0.06, 0.025))
    frames = {}
    for table, arm in (("plain", False), ("stripes", False), ("stripes", True)):
        camera = simulators.CameraSettings((160, 120), table=table, arm=arm)
        robot = simulators.MujocoRobot(sim, camera=camera)
        c = robot.simulator.com_px
        robot.execute((c[0] - 40, c[1], c[0] - 25, c[1]), retract=False)  # pusher in view
        frames[table, arm] = robot.camera_frame().astype(float)
        robot.close()
    strip = (slice(0, 20), slice(0, 160))  # a band of table away from the object
    assert frames["stripes", False][strip].std() > 5 * frames["plain", False][strip].std()
    arm = np.abs(frames["stripes", True] - frames["stripes", False]).max(axis=2) > 30
    assert arm.sum() > 100  # the arm's link, reaching out of the frame
    assert arm[:10].any()  # to the image's far (top) edge
    default = simulators.CameraSettings()
    assert (default.tilt, default.table, default.arm) == (0.0, "plain", False)


@pytest.mark.parametrize(
    ("options", "error", "match"),
    [
        ({"tilt": 30}, ValueError, r"tilt must be in \[0, 1\] radians .*degrees given"),
        ({"tilt": -0.1}, ValueError, "tilt"),
        ({"table": "oak"}, ValueError, r"table must be one of \('plain', 'wood', 'stripes'\)"),
        ({"arm": "yes"}, TypeError, "arm must be True or False"),
    ],
)
def test_bad_cell_settings_are_named(options, error, match):
    with pytest.raises(error, match=match):
        simulators.CameraSettings(**options)
