"""SimulatedRobot: never reset, seeded noise, camera frame, engine option, bad input."""

import numpy as np
import pytest

pytest.importorskip("shapely")
pytest.importorskip("trimesh")

from scipy import ndimage

import comcore
import simulators
from simulators import SimulatedRobot
from simulators._robot import perturb_actions


@pytest.fixture(scope="module")
def sim():
    return simulators.random_simulator("Obj3", friction="high", rng=1)


def _two_pushes(robot):
    first = robot.camera_mask()
    a1 = comcore.sample_pushes(first, 1, rng=0)[0]
    robot.execute(a1)
    a2 = comcore.sample_pushes(robot.camera_mask(), 1, rng=1)[0]
    robot.execute(a2)
    return a1, a2


def test_two_pushes_compound_without_reset(sim):
    robot = SimulatedRobot(sim, rng=0)
    a1, a2 = _two_pushes(robot)
    world = robot.simulator
    after_one = world.push(a1).pose
    assert np.allclose(robot.world_pose, world.push(a2, pose=after_one).pose)
    assert not np.allclose(robot.world_pose, world.push(a2).pose, atol=1e-4)


def test_pose_maps_the_first_mask_onto_the_current_one(sim):
    robot = SimulatedRobot(sim, rng=0)
    first = robot.camera_mask()
    _two_pushes(robot)
    pose = robot.pose
    moved = comcore.apply_motion(first.pixels, pose.theta, (pose.tx, pose.ty), first.centroid)
    assert np.allclose(moved.mean(axis=0), robot.camera_mask().centroid, atol=0.3)
    com = comcore.apply_motion(robot.true_com_px, pose.theta, (pose.tx, pose.ty), first.centroid)
    assert np.allclose(com, robot.com_in_camera)


def test_push_motion_is_about_the_centroid_before_it(sim):
    robot = SimulatedRobot(sim, rng=0)
    _two_pushes(robot)
    before = robot.simulator.mask_at(robot.history[0].result.pose)
    m = robot.history[1].motion
    moved = comcore.apply_motion(before.pixels, m.theta, (m.tx, m.ty), before.centroid)
    assert np.allclose(moved.mean(axis=0), robot.camera_mask().centroid, atol=0.3)


def test_camera_sees_the_margin_around_the_turning_object():
    sim = simulators.random_simulator("Obj19", friction="low", rng=0)  # a 31 x 10 cm bar
    robot = SimulatedRobot(sim, camera_margin=0.05)
    centre = robot.camera_mask().centroid
    radius = np.max(np.linalg.norm(sim.shape.vertices_m - sim.shape.centroid_m, axis=1))
    reach_px = (radius + 0.05) / robot.resolution
    h, w = robot.image_shape
    assert min(centre[0], centre[1], w - 1 - centre[0], h - 1 - centre[1]) >= reach_px - 1.5
    assert robot.true_com_px == robot.simulator.com_px


def test_seeded_determinism(sim):
    runs = []
    for seed in (3, 3, 4):
        robot = SimulatedRobot(sim, pusher_error=0.003, angle_error=0.02, mask_noise=0.3, rng=seed)
        _two_pushes(robot)
        runs.append((np.array([p.executed for p in robot.history]), robot.camera_mask().data))
    assert np.array_equal(runs[0][0], runs[1][0]) and np.array_equal(runs[0][1], runs[1][1])
    assert not np.array_equal(runs[0][0], runs[2][0])


def test_pusher_error_is_across_the_push_with_the_given_std(sim):
    std = 0.003
    robot = SimulatedRobot(sim, pusher_error=std, rng=5)
    n = 300  # pushes in free space, beside the object: they miss and leave it where it is
    commanded = np.column_stack(
        [np.full(n, 2.0), np.linspace(2, 40, n), np.full(n, 2.0), np.full(n, 60.0)]
    )
    across, along = [], []
    for act in commanded:
        push = robot.execute(act)
        assert not push.hit
        d = np.asarray(push.executed) - act
        across.append(-d[0])  # the path runs +y; its left-hand normal (CCW on screen) is -x
        along.append(d[1])
        assert np.allclose(d[:2], d[2:])  # the whole path is shifted, not turned
    across_m = np.array(across) * robot.resolution
    assert np.allclose(along, 0.0)
    assert abs(across_m.mean()) < 3 * std / np.sqrt(n)
    assert 0.85 * std < across_m.std() < 1.15 * std
    assert robot.pose == comcore.Motion.identity()


def test_perturb_actions_turns_about_the_start():
    out = perturb_actions([[1.0, 1.0, 11.0, 1.0]], [0.0], [np.pi / 2])
    assert np.allclose(out, [[1.0, 1.0, 1.0, -9.0]])  # CCW on screen: +x turns to -y


def test_mask_noise_flips_only_the_outline(sim):
    robot = SimulatedRobot(sim, mask_noise=0.5, rng=0)
    exact = robot.simulator.mask.data
    noisy = robot.camera_mask().data
    band = ndimage.binary_dilation(exact) & ~ndimage.binary_erosion(exact, border_value=0)
    changed = exact ^ noisy
    assert changed.any() and not (changed & ~band).any()
    assert 0.3 < changed.sum() / band.sum() < 0.7


class _Draws:
    """A stand-in generator whose ``random`` draws are given (0: flip, 1: keep)."""

    def __init__(self, draws):
        self.draws = draws

    def random(self, shape):
        assert shape == self.draws.shape
        return self.draws


def test_noisy_mask_keeps_a_diagonal_touching_pixel_as_mask_from_image_does():
    # A 5 x 5 square; its corner pixel (2, 2) flips off and the outside pixel (1, 2) above
    # it flips on: (1, 2) then touches the square only at a corner, through (2, 3).
    data = np.zeros((9, 9), bool)
    data[2:7, 2:7] = True
    draws = np.ones(data.shape)
    draws[2, 2] = draws[1, 2] = 0.0
    out = simulators.noisy_mask(comcore.Mask(data), 0.5, _Draws(draws)).data
    expected = data.copy()
    expected[2, 2], expected[1, 2] = False, True
    assert np.array_equal(out, expected)  # 8-connected: the pixel is the object's
    four, _ = ndimage.label(expected)  # 4-connected, it would be a component of its own
    assert four[1, 2] != four[4, 4]
    assert np.array_equal(comcore.geometry.largest_component(expected), out)


def test_exact_camera_mask_is_the_simulators(sim):
    robot = SimulatedRobot(sim, camera_margin=None)
    assert np.array_equal(robot.camera_mask().data, sim.mask.data)


def test_object_leaving_the_view_raises(sim):
    robot = SimulatedRobot(sim, camera_margin=0.013)
    first = robot.camera_mask()
    centre = np.array(first.centroid)
    x0 = float(first.pixels[:, 0].min()) - 4
    robot.execute((x0, centre[1], x0 + 40.0, centre[1]))  # 10 cm to the right
    with pytest.raises(ValueError, match="left the camera's view"):
        robot.camera_mask()


@pytest.mark.parametrize("end", [0.9, -0.9])
def test_the_view_holds_a_bar_turned_about_a_com_near_its_end(end):
    # Obj8 is a 23.5 cm bar; a CoM near one end swings the other end around it (a
    # no-reset benchmark trial left the view that way). Turned any way about its
    # CoM and carried almost camera_margin any way, the object stays in view.
    bar = simulators.random_simulator("Obj8", friction="high", rng=0)
    x_min, _, x_max, _ = bar.shape.bounds_m
    com = np.asarray(bar.shape.centroid_m) + np.array([end * (x_max - x_min) / 2 * 0.9, 0.0])
    margin = 0.05
    robot = SimulatedRobot(bar.with_com(com), camera_margin=margin, rng=0)
    x, y, _ = robot.simulator.initial_pose
    for heading in np.linspace(0.0, 2 * np.pi, 8, endpoint=False):
        dx, dy = 0.9 * margin * np.cos(heading), 0.9 * margin * np.sin(heading)
        for angle in np.linspace(0.0, 2 * np.pi, 12, endpoint=False):
            robot.place((x + dx, y + dy, angle))
            robot.camera_mask()  # raises if the object touches the border


def test_pymunk_engine_plays_the_robot(sim):
    robot = SimulatedRobot(sim, engine="pymunk", rng=0)
    assert robot.simulator.settings.engine == "pymunk"
    exact = SimulatedRobot(sim, rng=0)
    action = comcore.sample_pushes(robot.camera_mask(), 1, rng=0)[0]
    a, b = robot.execute(action).motion, exact.execute(action).motion
    assert a != b and abs(a.theta - b.theta) < 0.3 and abs(a.tx - b.tx) < 3


def test_bad_input(sim):
    with pytest.raises(TypeError, match="simulator"):
        SimulatedRobot("Obj3")
    with pytest.raises(ValueError, match="pusher_error"):
        SimulatedRobot(sim, pusher_error=-0.001)
    with pytest.raises(ValueError, match="mask_noise"):
        SimulatedRobot(sim, mask_noise=1.0)
    with pytest.raises(TypeError, match="engine"):
        SimulatedRobot(sim, engine=3)
    with pytest.raises(ValueError, match="engine"):
        SimulatedRobot(sim, engine="box2d")
    with pytest.raises(ValueError, match="rng"):
        SimulatedRobot(sim, rng=-1)
    robot = SimulatedRobot(sim, rng=0)
    with pytest.raises(ValueError, match="action"):
        robot.execute((1.0, 2.0, 3.0))
    with pytest.raises(ValueError, match="action"):
        robot.execute((1.0, 2.0, 1.0, 2.0))
    centre = robot.camera_mask().centroid
    with pytest.raises(ValueError, match="start outside"):
        robot.execute((*centre, centre[0] + 10, centre[1]))
    assert robot.pushes == 0 and robot.pose == comcore.Motion.identity()


def test_place_puts_the_object_back_without_a_push(sim):
    robot = SimulatedRobot(sim, rng=0)
    first = robot.camera_mask()
    _two_pushes(robot)
    robot.place()
    assert robot.pushes == 2 and np.array_equal(robot.camera_mask().data, first.data)
    with pytest.raises(ValueError, match="pose"):
        robot.place((0.0, float("nan"), 0.0))


def test_a_start_inside_the_object_is_moved_back_along_the_push(sim):
    shapely = pytest.importorskip("shapely")
    from simulators._robot import RETREAT_STEP_M, retreat_starts

    robot = SimulatedRobot(sim, rng=0)
    world = robot.simulator
    centre = np.array(robot.camera_mask().centroid)
    starts = np.array([centre, centre - np.array([200.0, 0.0])])  # inside; far outside
    out = retreat_starts(world, world.initial_pose, starts, np.array([[1.0, 0.0], [1.0, 0.0]]))
    outline = shapely.Polygon(world.outline_at())
    w = world.to_world(out)
    assert not shapely.contains_xy(outline, w[:, 0], w[:, 1]).any()
    assert out[0, 1] == centre[1] and out[0, 0] < centre[0]  # moved back along the push
    step = RETREAT_STEP_M / world.resolution
    back = world.to_world(out[0] + np.array([step, 0.0]))[0]
    assert shapely.contains_xy(outline, *back)  # one step less would be inside: the nearest
    assert np.array_equal(out[1], starts[1])


def test_frames_follow_the_push_and_end_at_its_pose(sim):
    robot = SimulatedRobot(sim, rng=0)
    action = comcore.sample_pushes(robot.camera_mask(), 1, rng=0)[0]
    push = robot.execute(action, frames=5)
    assert len(push.frames) == 5
    assert np.array_equal(push.frames[-1].data, robot.camera_mask().data)
    assert len({f.data.tobytes() for f in push.frames}) == 5  # the object moved between frames
    with pytest.raises(ValueError, match="frames"):
        robot.execute(action, frames=-1)


@pytest.mark.parametrize("observe", ["motion", "mask"])
def test_a_session_without_resets_replays_for_calibration(sim, observe):
    """A session that never reset the object: its Estimate, replayed, gives its own posterior.

    That is what :func:`comcore.calibrate_model_weight` scores, so calibration objects
    can be pushed on the robot as it works. Read from masks, each registration's
    residual widens its push's tracking error; the replay takes it from the extras
    (and the rotations the camera could not see: the disc's test below).
    """
    robot = SimulatedRobot(sim, rng=3)
    first = robot.camera_mask()
    likelihood = comcore.Likelihood(model_weight=0.6)
    settings = {"pusher_radius": sim.pusher_radius, "stop": comcore.StopRule(max_pushes=3)}
    session = comcore.ActiveSession(first, rng=3, likelihood=likelihood, **settings)
    while not session.done:
        push = robot.execute(session.next_push())
        if observe == "motion":
            session.observe(motion=push.motion)
        else:
            session.observe(robot.camera_mask())
    est = session.estimate()
    assert robot.pushes == 3 and [p.outcome for p in est.pushes] == ["evidence"] * 3
    # the later pushes started where the earlier ones left the object, not at its first pose
    camera = np.array([p.camera_action for p in est.pushes])
    assert np.abs(camera - np.array([p.action for p in est.pushes])).max() > 5.0
    measured = np.array([p.residual_px is not None for p in est.pushes])
    assert measured.all() if observe == "mask" else not measured.any()
    model = comcore.LimitSurfaceModel(pusher_radius=sim.pusher_radius)
    # the session's floor for the systematic error (0), not estimate_posterior's own (1.5 mm),
    # and the session's region (the posterior's own, not the bagged one)
    as_session = comcore.Likelihood(model_weight=0.6, systematic_error=0.0)
    again = comcore.estimate_posterior(
        first, pushes=est.pushes, model=model, likelihood=as_session, bootstrap=0
    )
    np.testing.assert_allclose(again.com, est.com, rtol=0, atol=1e-6)
    assert again.posterior.credible_radius_px == pytest.approx(est.posterior.credible_radius_px)
    truth = robot.true_com_px
    cal = comcore.calibrate_model_weight([(first, est, truth)], model=model, powers=(0.6,))
    assert cal.coverage.tolist() == [float(est.region_holds(truth))]
    assert cal.error_m[0] == pytest.approx(est.error_px(truth) * first.resolution)


def test_a_disc_session_replays_its_unseen_rotations():
    """A disc's turns cannot be seen: the session scores them as unknown, and so does its replay.

    Without ``rotation_observed`` the replay would score the rotation the session kept
    (the previous one, unmoved) as observed: another posterior.
    """
    angles = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    disc = simulators.PushSimulator.from_polygon(
        np.column_stack([0.03 * np.cos(angles), 0.03 * np.sin(angles)]), com=(0.012, 0.004)
    )
    robot = SimulatedRobot(disc, rng=0)
    first = robot.camera_mask()
    likelihood = comcore.Likelihood(model_weight=0.6)
    options = {"pusher_radius": disc.pusher_radius, "stop": comcore.StopRule(max_pushes=3)}
    session = comcore.ActiveSession(first, rng=0, likelihood=likelihood, **options)
    while not session.done:
        robot.execute(session.next_push())
        session.observe(robot.camera_mask())
    est = session.estimate()
    assert not any(p.rotation_observed for p in est.pushes)
    model = comcore.LimitSurfaceModel(pusher_radius=disc.pusher_radius)
    acts, moves = [p.action for p in est.pushes], [p.motion for p in est.pushes]
    replays = {
        True: comcore.estimate_posterior(first, pushes=est.pushes, model=model,
                                         likelihood=likelihood),
        False: comcore.estimate_posterior(first, acts, moves, model=model, likelihood=likelihood),
    }  # fmt: skip
    np.testing.assert_allclose(replays[True].com, est.com, rtol=0, atol=1e-6)
    assert np.hypot(*np.subtract(replays[False].com, est.com)) > 0.1
