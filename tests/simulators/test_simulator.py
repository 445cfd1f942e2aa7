"""PushSimulator: construction, camera frames, results, random trials, pickling."""

import pickle

import numpy as np
import pytest

pytest.importorskip("shapely")
pytest.importorskip("trimesh")

import comcore
import simulators
from simulators import PushSimulator

RECT = [(0, 0), (0.08, 0), (0.08, 0.06), (0, 0.06)]


def test_api_names():
    assert simulators.BENCHMARK_OBJECTS == tuple(f"Obj{i}" for i in range(1, 21))
    assert simulators.FRICTION_CLASSES == {"low": (0.1, 0.3), "high": (0.5, 0.9)}


def test_camera_frames_are_inverse_and_y_flips():
    sim = PushSimulator.from_polygon(RECT, com=(0.03, 0.04))
    pts = np.array([[0.0, 0.0], [0.08, 0.06], [0.03, 0.04]])
    px = sim.to_pixels(pts)
    assert np.allclose(sim.to_world(px), pts)
    # world y up is pixel y down: the top-right corner has the smaller row
    assert px[1, 1] < px[0, 1] and px[1, 0] > px[0, 0]
    assert np.allclose(px[2], sim.com_px)
    assert sim.com_m == pytest.approx((0.03, 0.04))
    # the mask shows the footprint with the margin all round
    assert sim.mask.area_px == pytest.approx(0.08 * 0.06 / 0.0025**2, rel=0.03)
    rows, cols = np.nonzero(sim.mask.data)
    margin_px = sim.margin / sim.resolution
    assert rows.min() >= margin_px - 1 and cols.min() >= margin_px - 1
    assert sim.mask.shape[0] - rows.max() >= margin_px - 1


def test_resolution_changes_the_pixels_not_the_physics():
    coarse = PushSimulator.from_polygon(RECT, resolution=0.005)
    fine = PushSimulator.from_polygon(RECT, resolution=0.0025)
    start, end = np.array([[-0.01, 0.02], [0.03, 0.02]])
    a = coarse.push(np.concatenate(coarse.to_pixels([start, end])))
    b = fine.push(np.concatenate(fine.to_pixels([start, end])))
    assert np.allclose(a.pose, b.pose, atol=1e-9)


def test_push_result_fields():
    sim = PushSimulator.from_polygon(RECT)
    cx, cy = sim.com_px
    res = sim.push(comcore.Action(cx - 30, cy + 4, cx - 10, cy + 4), record=True)
    assert isinstance(res.motion, comcore.Motion)
    assert res.contact_px[0] == pytest.approx(sim.to_pixels([(0.0, 0.0)])[0, 0], abs=1e-6)
    assert res.normal_px == pytest.approx((1.0, 0.0), abs=1e-9)
    assert res.trajectory.shape[1] == 3 and np.allclose(res.trajectory[0], sim.initial_pose)
    assert np.allclose(res.trajectory[-1], res.pose)
    assert res.travel_px.shape == (len(res.trajectory),)
    assert res.travel_px[-1] == pytest.approx(20.0)  # the action's length, pixels
    assert sim.push(comcore.Action(cx - 30, cy + 4, cx - 10, cy + 4)).travel_px is None


def test_push_motions_matches_push_and_handles_empty():
    sim = simulators.random_simulator("Obj2", rng=3)
    actions = comcore.sample_pushes(sim.mask, 6, cone=0.2, rng=0)
    motions = sim.push_motions(actions)
    assert motions.shape == (6, 3)
    assert np.allclose(motions[2], sim.push(actions[2]).motion, atol=1e-9)
    assert sim.push_motions(np.zeros((0, 4))).shape == (0, 3)


def test_random_simulator_draws_reproducible_trials():
    a = simulators.random_simulator("Obj10", friction="high", rng=11)
    b = simulators.random_simulator("Obj10", friction="high", rng=11)
    c = simulators.random_simulator("Obj10", friction="high", rng=12)
    assert a.com_m == b.com_m and a.mu_contact == b.mu_contact
    assert a.com_m != c.com_m
    assert 0.5 <= a.mu_contact <= 0.9


def test_random_trials_cover_the_footprint_well_inside():
    import shapely

    shape = simulators.load_object("Obj4")
    poly = shape.polygon()
    rng = np.random.default_rng(0)
    coms, mus = [], []
    for _ in range(40):
        sim = simulators.random_simulator(shape, friction="low", rng=rng)
        coms.append(sim.com_m)
        mus.append(sim.mu_contact)
    coms = np.array(coms)
    assert shapely.contains_xy(poly, coms[:, 0], coms[:, 1]).all()
    depth = shapely.distance(poly.exterior, shapely.points(coms))
    assert depth.min() > 0.003
    assert np.ptp(coms[:, 0]) > 0.5 * np.ptp(shape.vertices_m[:, 0])
    assert min(mus) >= 0.1 and max(mus) <= 0.3 and np.ptp(mus) > 0.1


def test_random_simulator_bad_arguments():
    with pytest.raises(ValueError, match="friction must be one of"):
        simulators.random_simulator("Obj1", friction="medium")
    with pytest.raises(TypeError, match="shape_or_name"):
        simulators.random_simulator(42)


@pytest.mark.parametrize(("rng", "error"), [(-1, ValueError), ("a", TypeError)])
def test_random_trials_name_a_bad_rng(rng, error):
    # numpy's own message ("expected non-negative integer") did not name rng.
    with pytest.raises(error, match="rng must be None, a non-negative int seed"):
        simulators.random_simulator("Obj1", rng=rng)
    with pytest.raises(error, match="rng must be None, a non-negative int seed"):
        simulators.random_com(simulators.load_object("Obj1"), rng=rng)


def test_a_pusher_smaller_than_the_step_still_pushes():
    # A 0.1 mm pusher with the 1 mm step used to jump through the outline: the motion of
    # (0, 14.5, 30, 14.5) was (0, 0, 0), and so is that of this shorter push with that step.
    action = (0, 14.5, 14, 14.5)
    small = PushSimulator.from_polygon(RECT, pusher_radius=1e-4)
    assert small.step_m == 5e-5
    motion = np.array(small.push(action).motion)
    finer = PushSimulator.from_polygon(
        RECT, pusher_radius=1e-4, settings=simulators.EngineSettings(step_m=2.5e-5)
    )
    reference = np.array(finer.push(action).motion)
    # converged: within 1e-3 px and 1e-4 rad of a step half as long
    np.testing.assert_allclose(motion[1:], reference[1:], atol=1e-3)
    assert abs(motion[0] - reference[0]) < 1e-4
    assert motion[0] < -0.05 and motion[1] > 5  # it turns and moves, the right way


def test_the_default_pusher_keeps_the_default_step():
    sim = PushSimulator.from_polygon(RECT)
    assert sim.step_m == simulators.EngineSettings().step_m == 0.001


@pytest.mark.parametrize(
    ("radius", "action", "match"),
    [
        (0.004, (0, 14.5, 1e12, 14.5), r"at most 100 m long .*action\(s\) \[[01]\] run 2.5e\+09 m"),
        (1e-9, (0, 14.5, 30, 14.5), r"at most 5e-05 m long .*pusher_radius"),
    ],
)
def test_absurdly_long_pushes_are_refused(radius, action, match):
    # a 1e12 px path used to run (for days) instead of failing
    sim = PushSimulator.from_polygon(RECT, pusher_radius=radius)
    with pytest.raises(ValueError, match=match):
        sim.push(action)
    with pytest.raises(ValueError, match=match.replace("[01]", "1")):
        sim.push_motions([(0, 14.5, 30, 14.5), action])


def test_constructor_validation():
    shape = simulators.ObjectShape(RECT)
    mass = simulators.MassDistribution.on_shape(shape)
    with pytest.raises(ValueError, match="mu_contact"):
        PushSimulator(shape, mass, mu_contact=-0.1)
    with pytest.raises(ValueError, match="resolution"):
        PushSimulator(shape, mass, resolution=0.0)
    with pytest.raises(TypeError, match="ObjectShape"):
        PushSimulator(RECT, mass)
    with pytest.raises(ValueError, match="engine must be one of"):
        simulators.EngineSettings(engine="bullet")


def test_pickles_without_its_engine():
    sim = simulators.random_simulator("Obj3", rng=0)
    action = comcore.sample_pushes(sim.mask, 1, rng=0)[0]
    before = sim.push(action).motion
    clone = pickle.loads(pickle.dumps(sim))
    assert clone.push(action).motion == before


def test_with_com_moves_the_com_and_keeps_the_shape():
    sim = simulators.random_simulator("Obj6", rng=1)
    other = sim.with_com((0.01, 0.005), mu_contact=0.8)
    assert other.com_m == pytest.approx((0.01, 0.005), abs=1e-9)
    assert other.mu_contact == 0.8
    assert np.array_equal(other.mask.data, sim.mask.data)


@pytest.mark.parametrize(
    ("points", "message"),
    [
        ([[0.01, 0.02, 0.03]], r"shape \(n, 2\), got \(1, 3\)"),
        ([0.01, 0.02, 0.03], r"shape \(n, 2\)"),
        ([[0.01, np.nan]], "finite"),
        ([[np.inf, 0.0], [0.0, 0.0]], r"finite, got NaN or inf in row\(s\) \[0\]"),
    ],
)
def test_camera_frames_reject_bad_points(points, message):
    sim = PushSimulator.from_polygon(RECT)
    with pytest.raises(ValueError, match=f"points_m must .*{message}"):
        sim.to_pixels(points)
    with pytest.raises(ValueError, match=f"points_px must .*{message}"):
        sim.to_world(points)


def test_camera_frames_accept_one_point():
    sim = PushSimulator.from_polygon(RECT)
    assert sim.to_pixels((0.03, 0.04)).shape == (1, 2)
    assert np.allclose(sim.to_world(sim.to_pixels((0.03, 0.04)))[0], (0.03, 0.04))


def _mask_over_the_whole_image(sim, pose):
    shapely = pytest.importorskip("shapely")
    h, w = sim.image_shape
    rows, cols = np.mgrid[0:h, 0:w]
    centres = sim.to_world(np.column_stack([cols.ravel(), rows.ravel()]))
    poly = shapely.Polygon(sim.outline_at(pose))
    return shapely.contains_xy(poly, centres[:, 0], centres[:, 1]).reshape(h, w)


def test_mask_at_tests_only_the_outlines_box_and_gives_every_pixel():
    sim = simulators.random_simulator("Obj12", friction="high", rng=1)
    rng = np.random.default_rng(0)
    x0, y0, _ = sim.initial_pose
    h, w = sim.image_shape
    for _ in range(40):  # some poses partly out of the image, and turned any way
        dx, dy = rng.uniform(-0.5, 0.5, 2) * (w, h) * sim.resolution
        pose = (x0 + dx, y0 + dy, rng.uniform(-7, 7))
        try:
            mask = sim.mask_at(pose).data
        except ValueError:
            mask = np.zeros((h, w), bool)
        assert np.array_equal(mask, _mask_over_the_whole_image(sim, pose))


def test_too_coarse_a_resolution_says_so():
    sim = PushSimulator.from_polygon(RECT, resolution=1.0)
    with pytest.raises(ValueError, match=r"resolution 1 m per pixel is too coarse .*8 x 6 cm"):
        _ = sim.mask
    # an object pushed out of the image is a different error
    fine = PushSimulator.from_polygon(RECT)
    with pytest.raises(ValueError, match="outside the camera image"):
        fine.mask_at((1.0, 1.0, 0.0))


def test_push_starting_inside_the_object_is_refused():
    sim = PushSimulator.from_polygon(RECT)
    cx, cy = sim.com_px
    inside = (cx - 5, cy, cx + 5, cy)
    with pytest.raises(
        ValueError, match=r"action must start outside the object; action\(s\) \[0\]"
    ):
        sim.push(inside)
    outside = (cx - 30, cy, cx - 10, cy)
    with pytest.raises(ValueError, match=r"actions must start outside .*\[1\] start inside"):
        sim.push_many([outside, inside])
    with pytest.raises(ValueError, match=r"\[1\] start inside"):
        sim.push_motions([outside, inside])
    # comcore refuses the same action
    assert comcore.geometry.contacts(sim.mask, [inside]).starts_inside[0]
    # the start is judged at the start pose: after a push the object has moved away
    moved = sim.push(outside)
    assert moved.motion.tx > 5
    start = sim.to_pixels(sim.outline_at(moved.pose).mean(axis=0))[0]
    with pytest.raises(ValueError, match="start inside"):
        sim.push((*start, start[0] + 5, start[1]), pose=moved.pose)
    left_edge = cx - 0.04 / sim.resolution  # of the 8 cm box, CoM at its centre
    later = (left_edge + 0.5 * moved.motion.tx, cy, cx + 5, cy)
    with pytest.raises(ValueError, match="start inside"):
        sim.push(later)  # inside at the initial pose ...
    assert sim.push(later, pose=moved.pose).motion.tx > 0  # ... outside once it has moved


def test_action_from_world_maps_a_world_push_to_pixels():
    sim = PushSimulator.from_polygon([(0, 0), (0.04, 0), (0.04, 0.02), (0, 0.02)])
    action = simulators.action_from_world(sim, (0.02, 0.03), (0.0, -2.0), travel_m=0.02)
    start, end = action[:2], action[2:]
    np.testing.assert_allclose(sim.to_world(np.array([start, end])), [[0.02, 0.03], [0.02, 0.0]])
    assert end[1] > start[1]  # down the world is down the screen: pixel y grows
    assert comcore.geometry.contacts(sim.mask, [action]).hit[0]


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (((0.0, 0.0), (0.0, 0.0)), "direction must not be zero"),
        (((np.nan, 0.0), (1.0, 0.0)), "start_m"),
        (((0.0, 0.0), (1.0, 0.0, 0.0)), "direction"),
        (((0.0, 0.0), (1.0, 0.0), -0.02), "travel_m \\+ standoff_m"),
    ],
)
def test_action_from_world_rejects_bad_input(args, match):
    sim = PushSimulator.from_polygon([(0, 0), (0.04, 0), (0.04, 0.02), (0, 0.02)])
    with pytest.raises(ValueError, match=match):
        simulators.action_from_world(sim, *args)


@pytest.mark.parametrize(
    ("call", "error", "match"),
    [
        (lambda s: s.with_com((0.04, 0.03, 0.0)), ValueError, "com_m must be two finite numbers"),
        (lambda s: s.with_com([]), ValueError, "com_m must be two finite numbers"),
        (lambda s: s.with_com("centre"), TypeError, "com_m must be two finite numbers"),
        (lambda s: s.mask_at((0.04, 0.03)), ValueError, r"pose must be three .* shape \(2,\)"),
        (lambda s: s.outline_at((0.04, 0.03, np.nan)), ValueError, "pose must be three finite"),
        (
            lambda s: s.push((0, 19.5, 19.5, 19.5), pose=[[0.04, 0.03, 0.0]]),
            ValueError,
            r"pose must be three finite numbers .* shape \(1, 3\)",
        ),
        (lambda s: s.push((0, 19.5, 19.5, 19.5), pose="origin"), TypeError, "pose must be"),
        (
            lambda s: simulators.ObjectShape(np.array(RECT, float), uniform_com_m=[[0.04, 0.03]]),
            ValueError,
            "uniform_com_m must be two finite numbers",
        ),
    ],
)
def test_poses_and_coms_of_the_wrong_shape_are_refused_by_name(call, error, match):
    sim = PushSimulator.from_polygon(RECT)
    with pytest.raises(error, match=match):
        call(sim)


@pytest.mark.parametrize("fraction", [7239, 1.0, -0.1, float("nan")])
def test_random_com_names_a_bad_depth_fraction(fraction):
    with pytest.raises(ValueError, match="depth_fraction must be in"):
        simulators.random_com(simulators.load_object("Obj1"), rng=0, depth_fraction=fraction)
