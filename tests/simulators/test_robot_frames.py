"""SimulatedRobot.execute(frame_rate=...): the frames a video camera takes during a push."""

import importlib.util
import math

import numpy as np
import pytest

pytest.importorskip("shapely")
pytest.importorskip("trimesh")

import comcore
import simulators
from simulators import SimulatedRobot

NO_PYMUNK = importlib.util.find_spec("pymunk") is None
ENGINES = [
    "quasistatic",
    pytest.param("pymunk", marks=pytest.mark.skipif(NO_PYMUNK, reason="pymunk")),
]
#: A 10 x 6 cm plate whose CoM is off its centre.
PLATE = [(0.0, 0.0), (0.10, 0.0), (0.10, 0.06), (0.0, 0.06)]


@pytest.fixture(scope="module")
def sim():
    return simulators.random_simulator("Obj3", friction="high", rng=1)


def _push(sim, engine, rate=10.0, **options):
    robot = SimulatedRobot(sim, engine=engine, rng=0, **options)
    action = comcore.sample_pushes(robot.camera_mask(), 1, rng=0)[0]
    return robot, robot.execute(action, frame_rate=rate)


def _interpolated(trajectory, travel, at):
    """The pose at travel ``at``, by numpy's interp per column (not the robot's own code)."""
    keep = np.concatenate([np.diff(travel) > 0, [True]])  # pymunk's settling row repeats
    return tuple(float(np.interp(at, travel[keep], trajectory[keep, k])) for k in range(3))


@pytest.mark.parametrize("engine", ENGINES)
def test_frames_come_at_the_rate_until_the_push_ends(sim, engine):
    robot, push = _push(sim, engine, rate=8.0, speed=0.025)
    ex = np.asarray(push.executed)
    duration = math.hypot(*(ex[2:] - ex[:2])) * robot.resolution / robot.speed
    times = np.array(push.path_times)
    assert len(push.path) == len(times) == len(push.path_poses) > 5
    np.testing.assert_allclose(times, np.arange(1, len(times) + 1) / 8.0, rtol=0, atol=1e-12)
    assert times[-1] < duration <= times[-1] + 1 / 8.0
    assert all(
        isinstance(f, comcore.PushFrame) and isinstance(f.view, comcore.Mask) for f in push.path
    )


@pytest.mark.parametrize("engine", ENGINES)
def test_the_pusher_moves_along_the_executed_path_at_the_robots_speed(sim, engine):
    robot, push = _push(sim, engine, pusher_error=0.003, angle_error=0.05)
    ex = np.asarray(push.executed)
    assert not np.allclose(ex, push.commanded)  # the arm missed its commanded path
    unit = (ex[2:] - ex[:2]) / math.hypot(*(ex[2:] - ex[:2]))
    for frame, t in zip(push.path, push.path_times):
        expected = ex[:2] + (robot.speed * t / robot.resolution) * unit
        np.testing.assert_allclose(frame.pusher, expected, rtol=0, atol=1e-9)


@pytest.mark.parametrize("engine", ENGINES)
def test_each_frame_is_the_mask_at_the_pose_where_the_pusher_then_is(sim, engine):
    robot, push = _push(sim, engine)
    result, world = push.result, robot.simulator
    before_contact = 0
    for frame, t in zip(push.path, push.path_times):
        travel = robot.speed * t / robot.resolution
        pose = _interpolated(result.trajectory, result.travel_px, travel)
        assert np.array_equal(frame.view.data, world.mask_at(pose).data)
        before_contact += travel < result.travel_px[0]
    assert before_contact >= 2  # the standoff: frames of the object not yet touched
    assert np.array_equal(push.path[0].view.data, world.mask_at(result.trajectory[0]).data)


@pytest.mark.parametrize("engine", ENGINES)
def test_the_frames_poses_move_from_the_pose_before_to_the_pose_after(engine):
    # Along +x onto the plate's left edge, 1.5 cm above its CoM: it slides and turns one way.
    plate = simulators.PushSimulator.from_polygon(PLATE, com=(0.055, 0.03), mu_contact=0.5)
    robot = SimulatedRobot(plate, engine=engine, rng=0)
    start = (plate.com_m[0] - 0.06, plate.com_m[1] + 0.015)
    world = robot.simulator
    push = robot.execute(simulators.action_from_world(world, start, (1.0, 0.0)), frame_rate=20)
    poses = np.array([comcore.Motion.identity(), *push.path_poses, push.pose])
    assert np.all(np.diff(poses[:, 1]) >= 0)  # +x: the object only moves forward
    turns = np.diff(poses[:, 0])
    assert np.all(turns <= 1e-9) or np.all(turns >= -1e-9)
    assert abs(push.pose.theta) > math.radians(3)
    # the last frame a frame's travel (1 mm) before the end: close to the pose after (pymunk's
    # object moves in jerks of up to two steps' worth, and on a little as it settles)
    step_px = robot.speed / 20 / robot.resolution
    jerks = 1.5 if engine == "quasistatic" else 4.0
    assert math.hypot(*(poses[-1, 1:] - poses[-2, 1:])) < jerks * step_px
    assert abs(poses[-1, 0] - poses[-2, 0]) < math.radians(jerks)


def test_the_frames_are_drawn_afresh_with_mask_noise(sim):
    robot, push = _push(sim, "quasistatic", mask_noise=0.4)
    still = [f.view.data for f, t in zip(push.path, push.path_times)
             if robot.speed * t / robot.resolution < push.result.travel_px[0]]  # fmt: skip
    assert len(still) >= 2  # the object had not moved yet: only the noise differs
    exact = robot.simulator.mask_at(push.result.trajectory[0]).data
    assert not np.array_equal(still[0], still[1])
    assert not any(np.array_equal(s, exact) for s in still)


@pytest.mark.parametrize("rate", [0, -10.0, math.nan, math.inf, True, "10"])
def test_a_bad_frame_rate_is_refused_and_changes_nothing(sim, rate):
    robot = SimulatedRobot(sim, rng=0)
    action = comcore.sample_pushes(robot.camera_mask(), 1, rng=0)[0]
    error = TypeError if isinstance(rate, (bool, str)) else ValueError
    with pytest.raises(error, match="frame_rate must be"):
        robot.execute(action, frame_rate=rate)
    assert robot.pushes == 0 and robot.world_pose == robot.simulator.initial_pose


def test_frames_and_frame_rate_together_are_refused(sim):
    robot = SimulatedRobot(sim, rng=0)
    action = comcore.sample_pushes(robot.camera_mask(), 1, rng=0)[0]
    with pytest.raises(
        TypeError, match=r"frames \(a count, got 4\) or frame_rate \(Hz\), not both"
    ):
        robot.execute(action, frames=4, frame_rate=10.0)
    with pytest.raises(ValueError, match="MAX_FRAMES_PER_PUSH"):
        robot.execute(action, frame_rate=1e6)  # kHz typed as Hz: a million masks
    assert robot.pushes == 0
    with pytest.raises(ValueError, match="speed must be a finite number > 0"):
        SimulatedRobot(sim, speed=0.0)
    plain = robot.execute(action)
    assert plain.path == plain.path_times == plain.path_poses == ()


def test_a_frame_out_of_view_is_refused_and_leaves_the_robot_as_it_was():
    plate = simulators.PushSimulator.from_polygon(PLATE)
    robot = SimulatedRobot(plate, camera_margin=0.005, rng=0)
    start = (plate.com_m[0] - 0.06, plate.com_m[1])  # 5 cm along +x: out of a 5 mm margin
    action = simulators.action_from_world(robot.simulator, start, (1.0, 0.0), travel_m=0.05)
    with pytest.raises(ValueError, match=r"left the camera's view .* at t = .* s during push 1"):
        robot.execute(action, frame_rate=10)
    assert robot.pushes == 0 and robot.world_pose == robot.simulator.initial_pose
