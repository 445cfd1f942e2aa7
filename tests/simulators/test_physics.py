"""Fidelity of the simulator: its acceptance tests against the Voting Theorem and the physics."""

import math

import numpy as np
import pytest

pytest.importorskip("shapely")
pytest.importorskip("trimesh")

import comcore
import simulators
from simulators import MassDistribution, ObjectShape, PushSimulator

RECT = [(-0.04, -0.025), (0.04, -0.025), (0.04, 0.025), (-0.04, 0.025)]


@pytest.mark.parametrize("name", ["Obj1", "Obj5", "Obj11", "Obj13", "Obj8"])
def test_normal_push_through_com_does_not_rotate(name):
    for seed in range(3):
        sim = simulators.random_simulator(name, friction=("low", "high")[seed % 2], rng=seed)
        pushes = simulators.normal_pushes_through_com(sim)
        assert len(pushes) >= 1
        motions = sim.push_motions(pushes)
        assert np.degrees(np.abs(motions[:, 0])).max() < 0.5
        # and it translates the object by the pusher's 3 cm (12 px) along the push
        travel = np.hypot(motions[:, 1], motions[:, 2])
        assert travel == pytest.approx(12.0, abs=0.05)


@pytest.mark.parametrize("lever", [0.0075, 0.015])
def test_instantaneous_motion_matches_a_brute_force_limit_surface(lever):
    # Uniform 8 x 5 cm box, sticking normal push on its left edge `lever` above the
    # CoM: the rotation per metre of push minimises the frictional power of a
    # 200 x 200 grid of support points (no smoothing, solved independently).
    from scipy.optimize import minimize_scalar

    g = (np.arange(200) + 0.5) / 200
    x, y = np.meshgrid(-0.04 + 0.08 * g, -0.025 + 0.05 * g)
    c = np.array([-0.04, lever])

    def power(w):
        return np.hypot(1 - w * (y - c[1]), w * (x - c[0])).sum()

    exact = minimize_scalar(power, bounds=(-100, 100), method="bounded").x
    sim = PushSimulator.from_polygon(RECT, mu_contact=0.9)
    cx, cy = sim.com_px
    k = lever / sim.resolution
    res = sim.push((cx - 25, cy - k, cx - 16 + 0.4, cy - k), record=True)  # 1 mm of push
    omega = (res.trajectory[-1, 2] - res.trajectory[0, 2]) / 0.001
    assert omega == pytest.approx(exact, rel=0.01)


def _vt_agreement(names, cone, n=40):
    total = initial_ok = final_ok = 0
    for k, name in enumerate(names):
        for friction in ("low", "high"):
            sim = simulators.random_simulator(name, friction=friction, rng=k)
            actions = comcore.sample_pushes(sim.mask, n, cone=cone, rng=100 + k)
            com = np.asarray(sim.com_px)
            far = np.abs(comcore.geometry.signed_line_distance([com], actions)[0]) > 2.0
            for action, res in zip(actions[far], sim.push_many(actions[far], record=True)):
                if res.contact_px is None:
                    continue
                push_dir = action[2:] - action[:2]
                vt = comcore.vt.predicted_sense(
                    com, res.contact_px, res.normal_px, push_dir, sim.mu_contact
                )
                early = res.trajectory[min(3, len(res.trajectory) - 1), 2] - res.trajectory[0, 2]
                total += 1
                initial_ok += vt == np.sign(early)
                final_ok += vt == np.sign(res.motion.theta)
    return total, initial_ok / total, final_ok / total


@pytest.mark.slow
@pytest.mark.parametrize("cone", [0.0, 0.5])
def test_rotation_sense_agrees_with_the_voting_theorem(cone):
    # The Voting Theorem predicts the instantaneous sense at the real contact (the
    # disc's, which is off the action's line for oblique pushes on curved outlines).
    names = ["Obj1", "Obj5", "Obj7", "Obj12", "Obj16", "Obj19"]
    total, initial, final = _vt_agreement(names, cone)
    assert total >= 350
    # The acceptance bar, on the returned Motion (what estimators see): the sense of
    # the whole 3 cm push agrees on at least 99 % of pushes (it can reverse when the
    # pusher slides onto another edge of a concave outline, but rarely) ...
    assert final >= 0.99
    # ... and so does the initial sense (first 3 steps).
    assert initial >= 0.99


def test_mirror_symmetry():
    sim = PushSimulator.from_polygon(RECT, mu_contact=0.4)
    cx, cy = sim.com_px
    actions = np.array([(cx - 30, cy - 5, cx - 8, cy - 7), (cx - 4, cy - 30, cx + 3, cy - 9)])
    mirrored = actions.copy()
    mirrored[:, [1, 3]] = 2 * cy - actions[:, [1, 3]]  # mirror about the row of the CoM
    start = np.asarray(sim.initial_pose)
    for a, b in zip(sim.push_many(actions), sim.push_many(mirrored)):
        da, db = np.asarray(a.pose) - start, np.asarray(b.pose) - start
        assert abs(da[2]) > 0.02
        assert db[2] == pytest.approx(-da[2], abs=1e-9)
        assert db[0] == pytest.approx(da[0], abs=1e-9)
        assert db[1] == pytest.approx(-da[1], abs=1e-9)


def test_determinism():
    sims = [simulators.random_simulator("Obj12", friction="high", rng=7) for _ in range(2)]
    actions = comcore.sample_pushes(sims[0].mask, 30, cone=0.4, rng=3)
    first = sims[0].push_motions(actions)
    assert np.array_equal(first, sims[1].push_motions(actions))
    assert np.array_equal(first, sims[0].push_motions(actions))
    # A push's result does not depend on the batch it is in, nor on its order.
    assert np.allclose(first[::-1], sims[0].push_motions(actions[::-1]), rtol=0, atol=1e-9)
    single = np.array([sims[0].push(a).motion for a in actions[:5]])
    assert np.allclose(first[:5], single, rtol=0, atol=1e-9)


def test_rotation_grows_with_lever_arm():
    sim = PushSimulator.from_polygon(RECT, mu_contact=0.3)
    cx, cy = sim.com_px
    offsets = np.arange(0, 9)  # pixels above the CoM: the object turns clockwise on screen
    actions = np.array([(cx - 25, cy - k, cx - 4, cy - k) for k in offsets], float)
    theta = sim.push_motions(actions)[:, 0]
    assert abs(theta[0]) < 1e-9
    assert np.all(theta[1:] < 0)
    assert np.all(np.diff(np.abs(theta)) > 0)


@pytest.mark.parametrize("angle", [0.4, 1.3, 2.9, -2.0])
def test_friction_does_not_depend_on_orientation(angle):
    base = simulators.random_simulator("Obj13", friction="low", rng=5)
    com = np.asarray(base.com_m)
    c, s = math.cos(angle), math.sin(angle)
    rot = np.array([[c, -s], [s, c]])
    shape = ObjectShape((base.shape.vertices_m - com) @ rot.T + com)
    mass = MassDistribution(
        (base.mass.points_m - com) @ rot.T + com, base.mass.masses, base.mass.cell_size_m
    )
    turned = PushSimulator(shape, mass, mu_contact=base.mu_contact)
    import shapely

    outline = base.shape.polygon()
    rng = np.random.default_rng(0)
    pushes = 0
    while pushes < 4:
        target = base.outline_at()[rng.integers(len(base.shape.vertices_m))] * 0.8 + com * 0.2
        direction = rng.normal(size=2)
        start = target - 0.06 * direction / np.linalg.norm(direction)
        if shapely.contains_xy(outline, *start):
            continue  # the simulator refuses a push that starts inside the object
        pushes += 1
        a = base.push(simulators.action_from_world(base, start, direction, travel_m=0.06))
        b = turned.push(
            simulators.action_from_world(turned, (start - com) @ rot.T + com, rot @ direction, 0.06)
        )
        da = np.asarray(a.pose) - base.initial_pose
        db = np.asarray(b.pose) - turned.initial_pose
        assert abs(da[2]) > 0.02
        assert db[2] == pytest.approx(da[2], rel=0.02)
        assert np.linalg.norm(db[:2] - rot @ da[:2]) <= 0.02 * np.linalg.norm(da[:2])


def _disc_overlap(sim, pose, centre):
    """How deep (metres) the pusher's disc is inside the object's outline at pose."""
    import shapely

    poly = shapely.Polygon(sim.outline_at(pose))
    point = shapely.Point(*centre)
    depth = sim.pusher_radius - poly.exterior.distance(point)
    return sim.pusher_radius + poly.exterior.distance(point) if poly.contains(point) else depth


def test_no_tunnelling_and_no_motion_on_a_miss():
    sim = simulators.random_simulator("Obj9", friction="high", rng=2)  # a U: concave
    actions = comcore.sample_pushes(sim.mask, 40, cone=0.6, rng=1)
    for action, res in zip(actions, sim.push_many(actions, record=True)):
        ends = sim.to_world(action.reshape(2, 2))
        d = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
        centre_end = ends[1] - sim.pusher_radius * d
        travel = np.linalg.norm(ends[1] - ends[0])
        moved = np.linalg.norm(np.asarray(res.pose[:2]) - sim.com_m)
        assert moved <= travel
        assert _disc_overlap(sim, res.pose, centre_end) <= 0.002 * sim.pusher_radius
    # A pusher that passes beside the object leaves it exactly where it was.
    x0, _y0, _x1, y1 = sim.shape.bounds_m
    miss = simulators.action_from_world(
        sim, (x0 - 0.02, y1 + sim.pusher_radius + 0.001), (1.0, 0.0), 0.2
    )
    res = sim.push(miss)
    assert res.contact_px is None
    assert tuple(res.motion) == (0.0, 0.0, 0.0) and res.pose == sim.initial_pose


def test_motion_convention_on_a_drawn_example():
    # A 8 cm x 5 cm box, pushed to the right (+x on screen) on its left edge 6 px
    # above the CoM (smaller row): it turns clockwise on screen (theta < 0) and
    # moves right.
    sim = PushSimulator.from_polygon(RECT, mu_contact=0.5, margin=0.05)
    cx, cy = sim.com_px
    res = sim.push((cx - 24, cy - 6, cx - 4, cy - 6))
    theta, tx, ty = res.motion
    assert theta < -0.05 and tx > 5
    # The Motion moves every point of the object, in pixels, to where it ends up.
    before = sim.to_pixels(sim.outline_at())
    after = sim.to_pixels(sim.outline_at(res.pose))
    moved = comcore.apply_motion(before, theta, (tx, ty), sim.mask.centroid)
    assert np.allclose(moved, after, atol=1e-9)
    # and the mask seen at the final pose has its centroid where the Motion says
    final = sim.mask_at(res.pose)
    assert final.area_px == pytest.approx(sim.mask.area_px, rel=0.02)
    assert np.allclose(final.centroid, np.add(sim.mask.centroid, (tx, ty)), atol=0.2)


def test_sequences_through_pose():
    sim = PushSimulator.from_polygon(RECT)
    cx, cy = sim.com_px
    first = sim.push((cx - 24, cy, cx - 4, cy))
    second = sim.push((cx - 4 - 4, cy, cx + 8, cy), pose=first.pose)
    assert second.motion.tx == pytest.approx(12.0, abs=0.05)
    assert second.pose[0] - sim.com_m[0] == pytest.approx(0.06, abs=1e-4)


def test_pusher_starting_in_a_notch_is_lowered_farther_back():
    # The action starts inside the U's notch, on top of the object's right arm
    # for a disc of 4 mm radius: the pusher comes in along the same line instead.
    u = [(0, 0), (0.06, 0), (0.06, 0.06), (0.036, 0.06), (0.036, 0.02), (0.024, 0.02),
         (0.024, 0.06), (0, 0.06)]  # fmt: skip
    sim = PushSimulator.from_polygon(u)
    action = simulators.action_from_world(
        sim, (0.0335, 0.045), (0.0, -1.0), travel_m=0.01, standoff_m=0.0
    )
    res = sim.push(action)
    assert res.contact_px is not None and res.motion.ty > 0


#: A 6 x 4 cm plate with a 2 mm wide notch in its top edge, narrower than the 4 mm pusher.
NOTCHED = [(0, 0), (0.06, 0), (0.06, 0.04), (0.031, 0.04), (0.031, 0.025), (0.029, 0.025),
           (0.029, 0.04), (0, 0.04)]  # fmt: skip


@pytest.mark.parametrize("engine", ["quasistatic", "pymunk"])
def test_the_pushers_travel_is_recorded_with_the_trajectory(engine):
    if engine == "pymunk":
        pytest.importorskip("pymunk")
    shapely = pytest.importorskip("shapely")
    sim = PushSimulator.from_polygon(NOTCHED, settings=simulators.EngineSettings(engine=engine))
    outline = shapely.Polygon(sim.outline_at())
    on_edge = simulators.action_from_world(sim, (0.045, 0.05), (0.0, -1.0))
    in_notch = simulators.action_from_world(sim, (0.03, 0.035), (0.0, -1.0), 0.02, 0.0)
    for action, blocked in ((on_edge, False), (in_notch, True)):
        res = sim.push(action, record=True)
        travel = res.travel_px
        assert travel.shape == (len(res.trajectory),)
        assert np.all(np.diff(travel) >= 0)
        length = math.hypot(action[2] - action[0], action[3] - action[1])
        assert travel[-1] == pytest.approx(length, abs=1e-9)
        # row 0: the travel at the first contact, where the disc trailing the leading
        # point touches the outline; in the notch it came from farther back than the start
        d = np.subtract(action[2:], action[:2]) / length
        centre = sim.to_world(
            np.asarray(action[:2]) + (travel[0] - sim.pusher_radius / sim.resolution) * d
        )[0]
        gap = shapely.distance(outline, shapely.Point(*centre)) - sim.pusher_radius
        assert abs(gap) < 1e-9
        assert (travel[0] < 0) == blocked
    miss = sim.push((0, 0, 0, 5), record=True)
    assert miss.travel_px.tolist() == [0.0] and len(miss.trajectory) == 1


def test_bad_actions():
    sim = PushSimulator.from_polygon(RECT)
    with pytest.raises(ValueError, match="single action"):
        sim.push([(0, 0, 1, 0), (0, 0, 0, 1)])
    with pytest.raises(ValueError, match="non-zero length"):
        sim.push((3, 3, 3, 3))
    with pytest.raises(ValueError, match="pose"):
        sim.push((0, 0, 1, 0), pose=(0.0, 0.0))
