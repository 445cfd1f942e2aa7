"""recording_from_poses and mask_from_outline: recorded pose streams to Mask, Actions, Motions."""

import numpy as np
import pytest

import comcore
from comcore.conventions import object_motion_from_camera

SQUARE = [(-0.05, -0.05), (0.05, -0.05), (0.05, 0.05), (-0.05, 0.05)]
L_SHAPE = [(-0.04, -0.05), (0.05, -0.05), (0.05, -0.01), (0.0, -0.01), (0.0, 0.06), (-0.04, 0.06)]
RADIUS = 0.00475


def world_from_object(points, pose):
    c, s = np.cos(pose[2]), np.sin(pose[2])
    p = np.asarray(points, float)
    return np.column_stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]]) + pose[:2]


def object_from_world(points, pose):
    c, s = np.cos(pose[2]), np.sin(pose[2])
    p = np.asarray(points, float) - pose[:2]
    return np.column_stack([c * p[:, 0] + s * p[:, 1], -s * p[:, 0] + c * p[:, 1]])


def straight_push(pose0, contact_obj, direction_obj, gap=0.0005, speed=0.05, n=400, rate=250.0):
    """Pusher centre (world) from touching the outline at contact_obj, along direction_obj."""
    d = np.asarray(direction_obj, float) / np.hypot(*direction_obj)
    centre0 = np.asarray(contact_obj, float) - (RADIUS + gap) * d
    t = np.arange(n) / rate
    centre = centre0[None] + speed * t[:, None] * d[None]
    world = world_from_object(centre, pose0)
    return np.column_stack([t, world, np.zeros(n)])


def test_a_known_motion_comes_back_to_1e9():
    # The object at a turned pose moves at a constant rate (linear in time: interpolation is
    # exact); the Motion must move every object pixel to where the poses put it.
    pose0 = np.array([0.7, -1.2, 2.3])
    rates = np.array([0.011, -0.023, 0.31])  # m/s, m/s, rad/s
    pusher = straight_push(pose0, (0.02, -0.05), (0.3, 1.0))
    t_obj = np.arange(-25, 400) / 237.0  # another clock, another rate (a sample at t = 0)
    obj = np.column_stack([t_obj, pose0 + np.clip(t_obj, 0, None)[:, None] * rates])
    rec = comcore.recording_from_poses(L_SHAPE, [(obj, pusher)], RADIUS, travel=0.03)
    (push,) = rec.pushes
    assert rec.skipped == () and push.line_hits
    assert push.start_time == 0.0 and push.end_time == pytest.approx(0.03 / 0.05, abs=1e-12)
    pose_end = pose0 + push.end_time * rates
    assert push.motion.theta == pytest.approx(rates[2] * push.end_time, abs=1e-12)
    px = rec.mask.pixels
    moved_obj = object_from_world(world_from_object(rec.object_from_pixels(px), pose_end), pose0)
    expected = rec.pixels_from_object(moved_obj)
    m = push.motion
    got = comcore.apply_motion(px, m.theta, (m.tx, m.ty), rec.mask.centroid)
    assert np.abs(got - expected).max() < 1e-9
    # The action: the leading point, 1 cm before its first-contact position to 3 cm after.
    d = np.array([0.3, 1.0]) / np.hypot(0.3, 1.0)
    lead0 = np.array([0.02, -0.05]) - 0.0005 * d
    ends = rec.pixels_from_object(np.array([lead0 - 0.01 * d, lead0 + 0.03 * d]))
    assert np.abs(np.array(push.action) - ends.ravel()).max() < 1e-9
    assert push.speed == pytest.approx(0.05) and push.path_deviation < 1e-12


def test_frames_and_signs_on_a_hand_made_push():
    # A 10 cm square at world (1, 2) turned a quarter turn: its +x axis is world +y. The pusher
    # meets its +x face 3 cm along the object's +y (world x = 0.97) and moves along the
    # object's -x (world -y). The force -x at (0.05, 0.03) has the moment +0.03: the object
    # turns counter-clockwise seen from above, and moves along its own -x.
    t = np.arange(300) / 250.0
    pusher = np.column_stack([t, np.full(300, 0.97), 2.05 + RADIUS - 0.05 * t, 0 * t])
    moving = np.clip(t - 0.02, 0.0, None)
    obj = np.column_stack([t, 1.0 + 0 * t, 2.0 - 0.02 * moving, np.pi / 2 + 0.4 * moving])
    rec = comcore.recording_from_poses(SQUARE, [(obj, pusher)], RADIUS, com=(0.0, 0.0))
    (push,) = rec.pushes
    # Mask frame: x0 = -0.05 - 0.02 + 0.00125; the +x face is on the right of the picture, the
    # object's +y is up the screen (smaller rows); the push goes left along row 15.5.
    assert rec.mask.shape == (56, 56) and rec.com == (27.5, 27.5)
    assert np.allclose(push.action, (51.5, 15.5, 35.5, 15.5), atol=1e-9)
    assert push.motion.theta > 0.2 and push.motion.tx < -1.0 and abs(push.motion.ty) < 2.0
    # The Voting Theorem, from the true CoM, predicts the sense observed (for every friction).
    c = comcore.geometry.contacts(rec.mask, [push.action])
    for mu in (0.0, 0.3, np.inf):
        sense = comcore.vt.predicted_sense(
            rec.com, c.point[0], c.normal[0], push.action.direction, mu
        )
        assert sense == 1 == push.motion.sense
    # The same push with the object mirrored in time (turning clockwise) reads negative.
    obj_cw = obj.copy()
    obj_cw[:, 3] = np.pi / 2 - 0.4 * moving
    assert (
        comcore.recording_from_poses(SQUARE, [(obj_cw, pusher)], RADIUS).pushes[0].motion.sense
        == -1
    )


def test_out_of_order_and_repeated_samples_are_sorted():
    pose0 = np.array([0.0, 0.0, 0.4])
    pusher = straight_push(pose0, (0.05, 0.01), (-1.0, 0.0))
    t = np.linspace(0.0, 1.6, 400)
    obj = np.column_stack([t, 0.01 * t, -0.002 * t, 0.4 + 0.2 * t])
    shuffled = obj.copy()
    shuffled[[10, 11, 12, 200]] = shuffled[[12, 10, 200, 11]]  # steps back in time
    shuffled = np.vstack([shuffled, shuffled[50:51]])  # a repeated sample
    a = comcore.recording_from_poses(SQUARE, [(obj, pusher)], RADIUS).pushes[0]
    b = comcore.recording_from_poses(SQUARE, [(shuffled, pusher[::-1])], RADIUS).pushes[0]
    assert a == b


def test_yaw_across_pi_is_unwrapped():
    pose0 = np.array([0.0, 0.0, np.pi - 0.05])
    pusher = straight_push(pose0, (0.05, 0.02), (-1.0, 0.0))
    t = pusher[:, 0]
    yaw = np.angle(np.exp(1j * (pose0[2] + 0.3 * t)))  # wraps to -pi
    obj = np.column_stack([t, 0 * t, 0 * t, yaw])
    push = comcore.recording_from_poses(SQUARE, [(obj, pusher)], RADIUS).pushes[0]
    assert push.motion.theta == pytest.approx(0.3 * push.end_time, abs=1e-9)


def test_unusable_pushes_are_reported_not_dropped():
    pose0 = np.array([0.0, 0.0, 0.0])
    still = lambda t: np.column_stack([t, 0 * t, 0 * t, 0 * t])  # noqa: E731
    good = straight_push(pose0, (0.05, 0.0), (-1.0, 0.0))
    inside = straight_push(pose0, (0.05, 0.0), (-1.0, 0.0), gap=-0.004)
    far = good.copy()
    far[:, 2] += 0.2  # passes 15 cm above the square
    short = straight_push(pose0, (0.05, 0.0), (-1.0, 0.0), n=100)  # 2 cm of travel
    pushes = [(still(good[:, 0]), p) for p in (good, inside, far, short)]
    pushes.append((still(good[:100, 0]), good))  # the object's poses stop after 0.4 s
    names = ["good", "inside", "far", "short", "untracked"]
    rec = comcore.recording_from_poses(SQUARE, pushes, RADIUS, names=names)
    assert [p.name for p in rec.pushes] == ["good"]
    reasons = [(s.index, s.name, s.reason) for s in rec.skipped]
    assert reasons == [
        (1, "inside", "starts_inside"),
        (2, "far", "misses"),
        (3, "short", "short"),
        (4, "untracked", "no_object_pose"),
    ]
    assert "overlaps the outline by 4.00 mm" in rec.skipped[0].detail
    assert "less than the window's 30.0 mm" in rec.skipped[2].detail
    report = rec.report()
    assert (
        report.splitlines()[0] == "1 pushes kept, 4 skipped" and "skipped 2 far: misses" in report
    )


def test_a_grazing_push_is_kept_with_its_leading_line_missing():
    # 75 deg to the bottom face's normal, the leading line passing 3 mm beyond the corner.
    d = np.array([np.sin(np.deg2rad(75)), np.cos(np.deg2rad(75))])  # right and up
    corner = np.array([0.05, -0.05])
    across = np.array([d[1], -d[0]])  # away from the square
    lead_line = corner + 0.003 * across
    # the disc's centre is RADIUS below the face when its side lands on it
    centre_y = -0.05 - RADIUS
    centre_x = (
        lead_line[0] + (centre_y - RADIUS * d[1] - lead_line[1]) * d[0] / d[1] - RADIUS * d[0]
    )
    t = np.arange(400) / 250.0
    centre = np.array([centre_x, centre_y]) - 0.001 * d + 0.05 * t[:, None] * d
    pusher = np.column_stack([t, centre, 0 * t])
    obj = np.column_stack([t, 0 * t, 0 * t, 0.1 * np.clip(t - 0.05, 0, None)])
    rec = comcore.recording_from_poses(SQUARE, [(obj, pusher)], RADIUS)
    (push,) = rec.pushes
    assert not push.line_hits and rec.line_hits.tolist() == [False]
    assert comcore.geometry.disc_contacts(rec.mask, rec.actions, RADIUS).hit.all()
    assert not comcore.geometry.contacts(rec.mask, rec.actions).hit.any()
    assert "grazing 0" in rec.report()


def test_arrays_and_conversions():
    pose0 = np.zeros(3)
    pusher = straight_push(pose0, (0.05, 0.0), (-1.0, 0.0))
    obj = np.column_stack([pusher[:, 0], 0 * pusher[:, :3]])
    rec = comcore.recording_from_poses(SQUARE, [(obj, pusher)] * 2, RADIUS)
    assert rec.actions.shape == (2, 4) and rec.motions.shape == (2, 3) and rec.com is None
    pts = np.array([[0.01, -0.02], [0.0, 0.0]])
    assert np.allclose(rec.object_from_pixels(rec.pixels_from_object(pts)), pts)
    assert np.allclose(rec.motions, 0.0)


def test_invalid_inputs_are_named():
    t = np.linspace(0, 1, 10)
    obj = np.column_stack([t, 0 * t, 0 * t, 0 * t])
    with pytest.raises(ValueError, match=r"pushes\[0\] object poses must have shape \(n, 4\)"):
        comcore.recording_from_poses(SQUARE, [(obj[:, :3], obj)], RADIUS)
    with pytest.raises(ValueError, match=r"pushes\[0\] pusher poses must be finite"):
        bad = obj.copy()
        bad[3, 1] = np.nan
        comcore.recording_from_poses(SQUARE, [(obj, bad)], RADIUS)
    with pytest.raises(ValueError, match="two or more distinct times"):
        comcore.recording_from_poses(SQUARE, [(obj[:1], obj)], RADIUS)
    with pytest.raises(TypeError, match=r"pushes\[0\] must be a pair"):
        comcore.recording_from_poses(SQUARE, [(obj,)], RADIUS)
    with pytest.raises(TypeError, match="sequence of"):
        comcore.recording_from_poses(SQUARE, 3, RADIUS)
    with pytest.raises(ValueError, match="names must hold one name per push"):
        comcore.recording_from_poses(SQUARE, [(obj, obj)], RADIUS, names=["a", "b"])
    with pytest.raises(ValueError, match="travel must be a finite number > 0"):
        comcore.recording_from_poses(SQUARE, [(obj, obj)], RADIUS, travel=0)
    with pytest.raises(ValueError, match="pusher_radius must be a finite number >= 0"):
        comcore.recording_from_poses(SQUARE, [(obj, obj)], -0.001)
    with pytest.raises(ValueError, match="outline must have a non-zero area"):
        comcore.recording_from_poses([(0, 0), (1, 1), (2, 2)], [(obj, obj)], RADIUS)


def test_inputs_are_not_mutated():
    pusher = straight_push(np.zeros(3), (0.05, 0.0), (-1.0, 0.0))
    obj = np.column_stack([pusher[::-1, 0], 0 * pusher[:, :3]])
    before = (pusher.copy(), obj.copy())
    comcore.recording_from_poses(SQUARE, [(obj, pusher)], RADIUS)
    assert np.array_equal(pusher, before[0]) and np.array_equal(obj, before[1])


@pytest.mark.parametrize("resolution", [0.0025, 0.001])
def test_mask_from_outline_is_the_simulators_mask(resolution):
    pytest.importorskip("shapely")  # the simulators need comcore[sim]
    simulators = pytest.importorskip("simulators")
    sim = simulators.PushSimulator.from_polygon(L_SHAPE, resolution=resolution)
    mask = comcore.mask_from_outline(L_SHAPE, resolution)
    assert np.array_equal(mask.data, sim.mask.data)
    # and the frames agree: the same object points land on the same pixels
    pts = np.array([[0.01, -0.03], [-0.02, 0.05]])
    pusher = straight_push(np.zeros(3), (0.05, -0.03), (-1.0, 0.0))
    obj = np.column_stack([pusher[:, 0], 0 * pusher[:, :3]])
    rec = comcore.recording_from_poses(L_SHAPE, [(obj, pusher)], RADIUS, resolution=resolution)
    assert np.allclose(rec.pixels_from_object(pts), sim.to_pixels(pts - 0.0) + 0.0)


def test_mask_from_outline_either_orientation_and_errors():
    a = comcore.mask_from_outline(L_SHAPE)
    b = comcore.mask_from_outline([*L_SHAPE[::-1], L_SHAPE[-1]])  # clockwise, closed
    assert np.array_equal(a.data, b.data)
    with pytest.raises(ValueError, match="too coarse"):
        comcore.mask_from_outline([(0, 0), (0.001, 0), (0.001, 0.001)], 0.01, 0.0)
    with pytest.raises(ValueError, match="margin must be a finite number >= 0"):
        comcore.mask_from_outline(SQUARE, margin=-1.0)


@pytest.mark.parametrize("start_pose", [(0.0, 0.0, 0.0), (0.013, -0.021, 0.7)])
def test_a_simulated_push_comes_back_as_the_simulators_own_motion(start_pose):
    # The exact simulator pushes an L-shaped plate (its CoM at the origin of its frame) from a
    # start pose; its trajectory, written as pose streams, must give back the simulator's own
    # motion (seen from the object's frame at the start) and the same push line.
    pytest.importorskip("shapely")  # the simulators need comcore[sim]
    simulators = pytest.importorskip("simulators")
    poly = np.array(L_SHAPE)
    area = 0.5 * np.sum(poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1])
    cross = poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1]
    centroid = ((poly + np.roll(poly, -1, axis=0)) * cross[:, None]).sum(axis=0) / (6 * area)
    outline = poly - centroid
    sim = simulators.PushSimulator.from_polygon(outline, mu_contact=0.3, pusher_radius=RADIUS)
    assert np.allclose(sim.com_m, 0.0, atol=1e-12)
    # up the bottom face (y = -0.05 - cy), 2 cm right of the CoM: a flat face, no vertex
    face_y = -0.05 - centroid[1]
    lead_world = np.array([[0.02, face_y - 0.01], [0.02, face_y + 0.03]])
    pose = np.array(start_pose)
    c, s = np.cos(pose[2]), np.sin(pose[2])
    rot = np.array([[c, -s], [s, c]])
    in_pose = lead_world @ rot.T + pose[:2]  # the same push on the plate at its start pose
    action = sim.to_pixels(in_pose).ravel()
    result = sim.push(action, pose=(*pose,), record=True)
    traj = result.trajectory  # the pose before contact, then one per (uniform) step
    d = rot @ np.array([0.0, 1.0])
    contact_lead = pose[:2] + rot @ np.array([0.02, face_y])
    steps = len(traj) - 1
    travel = 0.03  # the leading point runs from the face to 3 cm past it
    t = np.arange(len(traj)) * (travel / steps) / 0.05  # at 5 cm/s
    centre = (contact_lead - RADIUS * d)[None] + 0.05 * t[:, None] * d[None]
    pusher = np.column_stack([t, centre, 0 * t])
    obj = np.column_stack([t, traj])
    rec = comcore.recording_from_poses(
        outline, [(obj, pusher)], RADIUS, travel=travel * (1 - 1e-12), com=(0.0, 0.0)
    )
    assert np.array_equal(rec.mask.data, sim.mask.data)
    (push,) = rec.pushes
    expected = object_motion_from_camera(result.motion, pose[2])
    assert push.motion.theta > 0.02  # right of the CoM, pushed up: counter-clockwise
    assert np.abs(np.array(push.motion) - expected).max() < 1e-9
    # the recorded action is the simulator's push line, in the plate's frame
    line = sim.to_pixels(lead_world)
    assert np.allclose(np.array(push.action)[[0, 2]], line[0, 0], atol=1e-9)
    assert np.allclose(push.action.direction, (0.0, -1.0), atol=1e-12)


def test_frames_at_a_rate_are_the_streams_poses_during_the_window():
    """frame_rate: the poses within the window, each as the window's own motion would be."""
    pose0 = np.array([0.7, -1.2, 2.3])
    rates = np.array([0.011, -0.023, 0.31])
    pusher = straight_push(pose0, (0.02, -0.05), (0.3, 1.0))
    t_obj = np.arange(-25, 400) / 237.0
    obj = np.column_stack([t_obj, pose0 + np.clip(t_obj, 0, None)[:, None] * rates])
    plain = comcore.recording_from_poses(L_SHAPE, [(obj, pusher)], RADIUS, travel=0.03)
    rec = comcore.recording_from_poses(
        L_SHAPE, [(obj, pusher)], RADIUS, travel=0.03, frame_rate=20.0
    )
    (push,) = rec.pushes
    assert plain.pushes[0].frames == ()
    assert push._replace(frames=()) == plain.pushes[0]
    assert len(push.frames) == 11  # 0.05 s apart over the window's 0.6 s, strictly inside
    start = np.asarray(push.action[:2])
    direction = np.subtract(push.action[2:], start) / np.hypot(*np.subtract(push.action[2:], start))
    for k, frame in enumerate(push.frames, start=1):
        t = 0.05 * k
        assert frame.view.theta == pytest.approx(rates[2] * t, abs=1e-12)
        along = np.subtract(frame.pusher, start)
        assert abs(along[0] * direction[1] - along[1] * direction[0]) < 1e-9  # on the action
        travel_m = along @ direction * rec.mask.resolution
        assert travel_m == pytest.approx(0.01 + 0.05 * t, abs=1e-9)  # standoff + speed * t
    frames = [p.frames for p in rec.pushes]
    est = comcore.estimate_posterior(
        rec.mask, rec.actions, rec.motions, frames=frames, pusher_radius=RADIUS, bootstrap=0,
        theta_units="rad",
    )  # fmt: skip
    assert len(est.pushes[0].path) > 0
    with pytest.raises(ValueError, match="frame_rate must be"):
        comcore.recording_from_poses(L_SHAPE, [(obj, pusher)], RADIUS, frame_rate=0.0)
