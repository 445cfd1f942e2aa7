"""Tests of comcore.ActiveSession (comcore/active/_session.py, _choice.py, _pose_tracking.py)."""

from __future__ import annotations

import numpy as np
import pytest

import comcore
import comcore.bench
import comcore.camera._pose_tracking as pose_module
from comcore.camera._pose_tracking import compose, moved_mask
from tests.records import actions_of, motions_of, outcomes_of

TRUE_COM = (52.0, 60.0)  # object frame (first mask), off the centroid (59.5, 56.5)


def _mask(pad=45):
    return comcore.Mask(np.pad(np.ones((24, 30), bool), pad))


class World:
    """A toy robot that never resets the object: it turns 0.1 rad in the Voting
    Theorem's sense and slides 6 px along the push (object frame), from wherever
    it is. Motions are reported in the camera frame about the current centroid."""

    def __init__(self, mask, com=TRUE_COM, slide=6.0):
        self.mask, self.com, self.slide = mask, np.asarray(com), slide
        self.pose = comcore.Motion.identity()
        self.c0 = np.asarray(mask.centroid)

    def to_object(self, action):
        ends = np.asarray(action, float).reshape(2, 2) - (self.pose.tx, self.pose.ty)
        return comcore.apply_motion(ends, -self.pose.theta, (0.0, 0.0), self.c0).reshape(4)

    def object_motion(self, action_obj):
        c = comcore.geometry.contacts(self.mask, action_obj)
        if not c.hit[0]:
            return np.zeros(3)
        a = comcore.Action(*action_obj)
        s = comcore.vt.predicted_sense(self.com, c.point[0], c.normal[0], a.direction, 0.3)
        return np.array([0.1 * s, *(self.slide * np.asarray(a.direction))])

    def execute(self, action):
        m = self.object_motion(self.to_object(action))
        t = comcore.conventions.rotate_vectors(m[1:], self.pose.theta)
        camera = comcore.Motion(m[0], t[0], t[1])
        self.pose = compose(self.pose, camera)
        return camera

    def camera_mask(self):
        return moved_mask(self.mask, self.pose)


def _run(session, world, steps=100):
    offered = []
    for _ in range(steps):
        if session.done:
            break
        action = session.next_push()
        offered.append((action, world.camera_mask()))
        session.observe(motion=world.execute(action))
    return offered


def test_estimate_active_is_the_session_with_resets():
    mask = _mask(10)
    world = World(mask, com=(12.0, 20.0), slide=0.0)
    est = comcore.estimate_active(
        mask, lambda a: world.object_motion(np.asarray(a)), rng=4, model=None
    )
    session = comcore.ActiveSession(mask, rng=4, model=None)
    while not session.done:
        motion = world.object_motion(np.asarray(session.next_push()))
        session.observe(motion=motion)
        session.reset_pose()
    again = session.estimate()
    assert again.used == est.used and again.status == est.status
    np.testing.assert_array_equal(again.posterior.image, est.posterior.image)


def test_without_resets_the_pose_follows_the_object_and_the_com_is_found():
    mask = _mask()
    world = World(mask)
    session = comcore.ActiveSession(mask, rng=0, model=None, stop=comcore.StopRule(max_pushes=8, target_radius=1e-4))
    _run(session, world)
    assert session.status == "budget" and len(session.actions) == 8
    np.testing.assert_allclose(session.pose, world.pose, atol=1e-12)
    assert abs(session.pose.theta) > 0.1 and np.hypot(session.pose.tx, session.pose.ty) > 5
    est = session.estimate()
    assert est.error_px(TRUE_COM) < 2.5
    moved = comcore.apply_motion(est.com, *world.pose[:1], world.pose[1:], mask.centroid)
    np.testing.assert_allclose(session.com_in_camera(), moved, atol=1e-9)


def test_offered_pushes_hit_the_object_where_it_is_now():
    mask = _mask()
    world = World(mask)
    session = comcore.ActiveSession(mask, rng=1, model=None, stop=comcore.StopRule(max_pushes=8, target_radius=1e-4))
    for action, seen in _run(session, world):
        c = comcore.geometry.contacts(seen, action)
        assert c.hit[0] and not c.starts_inside[0]
    made = actions_of(session.estimate())
    assert len(np.unique(made, axis=0)) == 8  # never repeated (object frame)


def test_motions_are_scored_in_the_object_frame():
    """The posterior of a no-reset run equals the one of the same pushes with resets."""
    mask = _mask()
    world = World(mask)
    session = comcore.ActiveSession(mask, rng=2, model=None, stop=comcore.StopRule(max_pushes=5, target_radius=1e-4))
    _run(session, world)
    est = session.estimate()
    reset = comcore.ActiveSession(
        mask, candidates=actions_of(est), model=None, stop=comcore.StopRule(max_pushes=5, min_information=0.0))
    while not reset.done:
        reset.observe(motion=World(mask).object_motion(np.asarray(reset.next_push())))
        reset.reset_pose()
    assert len(reset.estimate().used) == 5
    np.testing.assert_allclose(
        reset.estimate().posterior.image, est.posterior.image, atol=1e-12
    )


def test_a_push_that_does_not_move_the_object_is_a_miss():
    """No reset, a push misses the moved object: zero motion is no evidence."""
    mask = _mask(10)
    session = comcore.ActiveSession(mask, rng=0, model=None, stop=comcore.StopRule(max_pushes=3))
    before = session.history[-1].entropy_bits
    first = session.next_push()
    session.observe(motion=(0.0, 0.0, 0.0))
    assert session.history[-1].entropy_bits == pytest.approx(before, abs=1e-12)
    assert outcomes_of(session.estimate()) == ("miss",)
    assert session.next_push() != first  # not repeated


def test_a_failed_push_is_no_evidence_and_not_counted():
    mask = _mask(10)
    session = comcore.ActiveSession(mask, rng=0, model=None, stop=comcore.StopRule(max_pushes=1))
    first = session.next_push()
    session.observe(failed=True)
    assert session.status == "waiting_push" and session.next_push() != first
    session.observe(motion=(0.1, 1.0, 0.0))
    est = session.estimate()
    failed = [p for p in est.pushes if p.outcome == "failed"]
    assert est.status == "budget" and len(est.used) == 1 and len(failed) == 1
    assert failed[0].motion is None and failed[0].log_evidence is None


@pytest.mark.parametrize(
    ("call", "error", "match"),
    [
        (lambda s, m: s.observe(motion=(0.1, 0, 0)), comcore.SessionError, "next_push"),
        (lambda s, m: s.observe(m, motion=(0.1, 0, 0)), TypeError, "exactly one of"),
        (lambda s, m: s.observe(), TypeError, "exactly one of"),
        (lambda s, m: s.observe(failed="yes"), TypeError, "failed must be a bool"),
        (lambda s, m: s.observe(motion=(np.nan, 0, 0)), ValueError, "motion must be finite"),
        (lambda s, m: s.observe(np.ones((3, 3), bool)), TypeError, "mask must be"),
        (
            lambda s, m: s.observe(comcore.Mask(np.pad(m.data, 1))),
            ValueError,
            "mask must have the first mask's shape",
        ),
        (
            lambda s, m: s.observe(comcore.Mask(m.data, resolution=0.001)),
            ValueError,
            "mask must have the first mask's resolution",
        ),
    ],
)
def test_bad_observations_are_named_and_change_nothing(call, error, match):
    mask = _mask(10)
    session = comcore.ActiveSession(mask, rng=0, model=None)
    first = session.next_push()
    if error is comcore.SessionError:  # observe twice for one push
        session.observe(motion=(0.1, 1.0, 0.0))
        twin = comcore.ActiveSession(mask, rng=0, model=None)
        twin.next_push()
        twin.observe(motion=(0.1, 1.0, 0.0))
        first = twin.next_push()
    est = session.estimate()
    with pytest.raises(error, match=match):
        call(session, mask)
    assert session.next_push() == first
    np.testing.assert_array_equal(session.estimate().posterior.image, est.posterior.image)


def test_observe_before_the_first_push_and_after_the_end():
    mask = _mask(10)
    session = comcore.ActiveSession(mask, rng=0, model=None, stop=comcore.StopRule(max_pushes=1))
    with pytest.raises(comcore.SessionError, match="call next_push"):
        session.observe(motion=(0.1, 0, 0))
    session.next_push()
    session.observe(motion=(0.1, 1.0, 0.0))
    assert session.done
    with pytest.raises(comcore.SessionError, match="done"):
        session.next_push()
    with pytest.raises(comcore.SessionError, match="done"):
        session.observe(motion=(0.1, 1.0, 0.0))


def test_same_seed_same_pushes():
    mask = _mask()
    runs = []
    for _ in range(2):
        session = comcore.ActiveSession(mask, rng=7, model=None, stop=comcore.StopRule(max_pushes=4, target_radius=1e-4))
        _run(session, World(mask))
        runs.append(session.actions)
    np.testing.assert_array_equal(runs[0], runs[1])


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"max_pushes": -1}, ValueError, "max_pushes must be >= 0"),
        ({"min_pushes": -1}, ValueError, "min_pushes must be >= 0"),
        ({"min_pushes": 1.5}, TypeError, "min_pushes must be an int"),
        ({"rng": -1}, ValueError, "rng must be"),
        ({"rng": "a"}, TypeError, "rng must be"),
        ({"max_push": 3}, TypeError, r"unknown option\(s\) \['max_push'\]"),
    ],
)
def test_bad_arguments_are_named(kwargs, error, match):
    own = {k: v for k, v in kwargs.items() if k == "rng"}
    with pytest.raises(error, match=match):
        grouped = comcore.bench.option_groups(**{k: v for k, v in kwargs.items() if k not in own})
        comcore.ActiveSession(_mask(10), **own, **grouped)


def test_candidates_outside_the_image_are_not_offered():
    mask = _mask(10)
    inside = (0.0, 20.0, 25.0, 20.0)
    outside = (-30.0, 25.0, 25.0, 25.0)  # hits the object but starts off the image
    session = comcore.ActiveSession(mask, candidates=[outside, inside], model=None, stop=comcore.StopRule(max_pushes=5))
    assert tuple(session.next_push()) == inside
    session.observe(motion=(0.1, 1.0, 0.0))
    assert session.status == "exhausted"


def test_the_moved_mask_is_the_first_mask_moved():
    mask = comcore.Mask(np.pad(np.ones((6, 14), bool), 12))
    pose = comcore.Motion(0.5, 3.0, -2.0)
    moved = moved_mask(mask, pose)
    expected = comcore.apply_motion(mask.pixels, pose.theta, pose[1:], mask.centroid)
    inside = moved.data[np.round(expected[:, 1]).astype(int), np.round(expected[:, 0]).astype(int)]
    assert inside.mean() > 0.97
    assert abs(moved.area_px - mask.area_px) <= 0.05 * mask.area_px


def test_object_motion_from_camera_undoes_the_pose():
    """A rotated camera view of a push gives the object's own motion back."""
    from comcore.conventions import object_motion_from_camera

    own = np.array([0.2, 3.0, -1.0])
    for theta in (0.0, 0.7, -2.0):
        seen = np.r_[own[0], comcore.conventions.rotate_vectors(own[1:], theta)]
        np.testing.assert_allclose(object_motion_from_camera(seen, theta), own, atol=1e-12)


# -- observing masks (comcore.measure_motion) ------------------------------------------


class StandIn:
    """Stands in for comcore.measure_motion: the world's true pose of each mask it made."""

    def __init__(self, world, ambiguous=False):
        self.world, self.ambiguous, self.calls = world, ambiguous, []
        self.poses = {}

    def mask(self):
        m = self.world.camera_mask()
        self.poses[id(m)] = self.world.pose
        return m

    def __call__(self, first, mask, previous, guess=None):
        from comcore.camera._pose_tracking import PoseReading

        self.calls.append((first, mask))
        pose = self.poses[id(mask)]
        if self.ambiguous:
            pose = comcore.Motion(previous.theta, pose.tx, pose.ty)
        return PoseReading(pose, self.ambiguous, 0.3)


def test_observed_masks_are_measured_against_the_first_mask(monkeypatch):
    mask = _mask()
    world = World(mask)
    stand_in = StandIn(world)
    monkeypatch.setattr(pose_module, "measure_pose", stand_in)
    session = comcore.ActiveSession(mask, rng=0, model=None, stop=comcore.StopRule(max_pushes=4, target_radius=1e-4))
    while not session.done:
        world.execute(session.next_push())
        session.observe(stand_in.mask())
    assert len(stand_in.calls) == 4 and all(first is mask for first, _ in stand_in.calls)
    np.testing.assert_allclose(session.pose, world.pose, atol=1e-12)


def test_an_ambiguous_rotation_gives_no_sense_evidence(monkeypatch):
    mask = _mask()
    world = World(mask)
    stand_in = StandIn(world, ambiguous=True)
    monkeypatch.setattr(pose_module, "measure_pose", stand_in)
    session = comcore.ActiveSession(mask, rng=0, model=None, stop=comcore.StopRule(max_pushes=2))
    before = session.history[-1].entropy_bits
    world.execute(session.next_push())
    session.observe(stand_in.mask())
    assert session.history[-1].entropy_bits == pytest.approx(before, abs=1e-12)  # no model
    assert session.pose.theta == 0.0


# -- evidence in the status --------------------------------------------------------------


def test_a_robot_no_com_explains_is_reported_inconsistent():
    """Always +0.1 rad and no translation: with a model no CoM explains it."""
    from tests.active.test_blocking import ToyModel, _ell, _robot

    mask = _ell()
    est = comcore.estimate_active(mask, lambda a: comcore.Motion(0.1, 0.0, 0.0), model=ToyModel())
    assert est.status == "inconsistent" and not est.ok
    assert est.posterior.excess_nats > 30
    honest = comcore.estimate_active(mask, _robot(mask, (30.0, 24.0), 0.4), model=ToyModel(), rng=0)
    assert honest.status != "inconsistent" and honest.posterior.excess_nats < 0


def test_the_evidence_falls_with_surprising_pushes():
    from tests.active.test_blocking import ToyModel, _ell, _robot

    mask = _ell()
    kwargs = {"model": ToyModel(), "rng": 1, "stop": comcore.StopRule(max_pushes=4, target_radius=1e-4)}
    kwargs["likelihood"] = comcore.Likelihood(model_weight=1.0)  # the untempered evidence
    honest = comcore.estimate_active(mask, _robot(mask, (30.0, 24.0), 0.4), **kwargs)
    liar = comcore.estimate_active(mask, lambda a: comcore.Motion(0.1, 0.0, 0.0), **kwargs)
    assert liar.posterior.log_evidence < honest.posterior.log_evidence - 20


def test_without_a_reset_a_push_that_misses_carries_no_evidence():
    """The session believes the object is 30 px off where it is: its pushes miss."""
    mask = _mask(45)
    world = World(mask)
    session = comcore.ActiveSession(mask, rng=0, model=None, stop=comcore.StopRule(max_pushes=4, target_radius=1e-4))
    session.reset_pose(comcore.Motion(0.0, 30.0, 0.0))
    while not session.done:
        session.observe(motion=world.execute(session.next_push()))
    est = session.estimate()
    assert "miss" in outcomes_of(est)
    entropies = [h.entropy_bits for h in est.posterior.history]
    for k, outcome in enumerate(outcomes_of(est)):
        if outcome == "miss":
            assert entropies[k + 1] == pytest.approx(entropies[k], abs=1e-12)
    assert est.status == "budget"


def test_observed_masks_are_registered_with_measure_motion():
    mask = _mask()
    world = World(mask)
    session = comcore.ActiveSession(mask, rng=0, model=None, stop=comcore.StopRule(max_pushes=6, target_radius=1e-4))
    while not session.done:
        world.execute(session.next_push())
        session.observe(world.camera_mask())
    assert abs(session.pose.theta - world.pose.theta) < 0.01
    assert np.hypot(session.pose.tx - world.pose.tx, session.pose.ty - world.pose.ty) < 0.5
    assert session.estimate().error_px(TRUE_COM) < 2.5


def test_a_mask_of_an_object_leaving_the_view_is_refused_and_changes_nothing():
    mask = _mask(10)
    session = comcore.ActiveSession(mask, rng=0, model=None)
    first = session.next_push()
    half_out = np.roll(mask.data, -25, axis=1)  # the object slid half out of the view
    half_out[:, -25:] = False
    with pytest.raises(ValueError, match="mask cannot be registered"):
        session.observe(comcore.Mask(half_out))
    assert session.next_push() == first and session.status == "waiting_observation"


def test_the_registration_residual_widens_the_tracking_noise():
    from comcore.active._likelihood import tracking_noise

    assert tracking_noise((0.01, 0.2), float("nan"), 10.0) == (0.01, 0.2)
    theta, px = tracking_noise((0.01, 0.2), 0.5, 10.0)
    assert theta == pytest.approx(np.hypot(0.01, 0.05)) and px == pytest.approx(np.hypot(0.2, 0.5))


# -- the push as executed ----------------------------------------------------------------


def test_object_from_camera_undo_camera_from_object():
    from comcore.camera._pose_tracking import camera_from_object, object_from_camera

    actions = np.array([[0.0, 50.0, 40.0, 52.0], [60.0, 0.0, 58.0, 30.0]])
    pose, centroid = comcore.Motion(0.4, 7.0, -3.0), (59.5, 56.5)
    camera = camera_from_object(actions, pose, centroid)
    assert np.abs(camera - actions).max() > 5
    np.testing.assert_allclose(object_from_camera(camera, pose, centroid), actions, atol=1e-12)


def _executed_run(observe_executed, shift_px=0.0):
    """A World session whose robot pushes ``shift_px`` beside each planned path."""
    mask = _mask()
    world = World(mask)
    session = comcore.ActiveSession(mask, rng=0, model=None, stop=comcore.StopRule(max_pushes=4, target_radius=1e-4))
    while not session.done:
        planned = np.asarray(session.next_push(), float)
        d = (planned[2:] - planned[:2]) / np.hypot(*(planned[2:] - planned[:2]))
        real = planned + shift_px * np.tile([-d[1], d[0]], 2)
        motion = world.execute(real)
        session.observe(motion=motion, **({"executed": real} if observe_executed else {}))
    return session.estimate(), world


def test_a_push_executed_as_planned_is_scored_as_planned():
    told, _ = _executed_run(observe_executed=True)
    plain, _ = _executed_run(observe_executed=False)
    np.testing.assert_allclose(told.posterior.image, plain.posterior.image, atol=1e-12)


def test_a_push_executed_off_its_path_is_scored_where_it_went():
    """Pushed 4 px beside every plan: told, the session finds the CoM; not told, it errs."""
    told, _ = _executed_run(observe_executed=True, shift_px=4.0)
    blind, _ = _executed_run(observe_executed=False, shift_px=4.0)
    assert told.error_px(TRUE_COM) < 2.5 < blind.error_px(TRUE_COM)
    # the pushes the posterior used are the executed ones, in the object's frame
    first = np.asarray(actions_of(told)[0])
    planned = np.asarray(told.pushes[0].camera_action)
    assert told.pushes[0].planned == tuple(planned)  # the first push: camera and object frames agree
    d = (planned[2:] - planned[:2]) / np.hypot(*(planned[2:] - planned[:2]))
    np.testing.assert_allclose(first, planned + 4.0 * np.tile([-d[1], d[0]], 2), atol=1e-9)


@pytest.mark.parametrize(
    ("executed", "failed", "error", "match"),
    [
        ((0.0, 1.0, 2.0), False, ValueError, "executed must"),
        ([(0, 50, 40, 52), (0, 50, 40, 52)], False, ValueError, "executed must be a single"),
        ((24.5, 21.5, 40.0, 21.5), False, ValueError, "executed .* starts inside the object"),
        ((0.0, 5.0, 10.0, 5.0), False, ValueError, "executed .* misses the object"),
        ((0.0, 20.0, 40.0, 22.0), True, TypeError, r"failed=True\) takes no executed"),
    ],
)
def test_a_bad_executed_push_is_named_and_changes_nothing(executed, failed, error, match):
    mask = _mask(10)
    session = comcore.ActiveSession(mask, rng=0, model=None)
    first = session.next_push()
    est = session.estimate()
    kwargs = {"failed": True} if failed else {"motion": (0.1, 3.0, 0.0)}
    with pytest.raises(error, match=match):
        session.observe(executed=executed, **kwargs)
    assert session.next_push() == first and session.status == "waiting_observation"
    np.testing.assert_array_equal(session.estimate().posterior.image, est.posterior.image)


def _beside(action, shift_px):
    planned = np.asarray(action, float)
    d = (planned[2:] - planned[:2]) / np.hypot(*(planned[2:] - planned[:2]))
    return planned + shift_px * np.tile([-d[1], d[0]], 2)


def test_estimate_active_scores_the_path_its_push_returns():
    """push() may return (motion, executed): scored as the session scores observe(executed=)."""
    mask, world = _mask(), World(_mask())  # World's pose stays the identity: a reset robot
    options = {"rng": 0, "stop": comcore.StopRule(max_pushes=4, target_radius=1e-4), "model": None}

    def push(action):  # 4 px beside every plan, and it says where it went
        real = _beside(action, 4.0)
        return comcore.Motion(*world.object_motion(real)), real

    told = comcore.estimate_active(mask, push, **options)
    blind = comcore.estimate_active(mask, lambda a: push(a)[0], **options)
    assert told.error_px(TRUE_COM) < 2.5 < blind.error_px(TRUE_COM)
    session = comcore.ActiveSession(mask, **options)
    while not session.done:
        motion, real = push(session.next_push())
        session.observe(motion=motion, executed=real)
        session.reset_pose()  # the same as observe(..., reset=True)
    np.testing.assert_array_equal(told.posterior.image, session.estimate().posterior.image)
    assert [p.action for p in told.pushes] == [p.action for p in session.estimate().pushes]


def test_estimate_active_names_a_bad_executed_path_as_the_push_failing():
    mask = _mask(10)
    with pytest.raises(comcore.PushFailedError, match="push 0 .* executed .* misses") as info:
        comcore.estimate_active(
            mask, lambda a: ((0.1, 3.0, 0.0), (0.0, 5.0, 10.0, 5.0)), model=None, rng=0
        )
    assert info.value.index == 0 and info.value.partial.posterior.image.sum() > 0
    with pytest.raises(comcore.PushFailedError, match="push result's motion"):
        comcore.estimate_active(mask, lambda a: ((0.1, 3.0), tuple(a)), model=None, rng=0)


def test_an_executed_start_just_inside_the_outline_is_moved_back_along_its_line():
    """The session's pose is measured; a pusher that met the outline may seem to start in it."""
    mask = _mask(10)  # object pixels at columns 10-39: the outline at x = 9.5
    session = comcore.ActiveSession(mask, rng=0, model=None)
    session.next_push()
    session.observe(motion=(0.1, 3.0, 0.0), executed=(10.2, 21.5, 40.0, 21.5))
    start = actions_of(session.estimate())[0]
    assert start[0] < 9.5 and start[1:].tolist() == [21.5, 40.0, 21.5]


def test_an_executed_push_that_missed_is_a_miss_and_replays():
    mask = _mask(10)
    session = comcore.ActiveSession(mask, rng=0, model=None)
    session.next_push()
    session.observe(motion=(0.0, 0.0, 0.0), executed=(0.0, 5.0, 10.0, 5.0))  # above the object
    est = session.estimate()
    assert outcomes_of(est) == ("miss",)
    again = comcore.estimate_posterior(mask, actions_of(est), motions_of(est))
    assert again.status == "no_evidence"


@pytest.mark.parametrize("min_pushes", [0, 1, 2, 3])
def test_a_small_region_stops_ok_only_after_min_pushes_with_evidence(min_pushes):
    """A prior already tighter than the target: ``ok`` waits for ``min_pushes`` pushes."""
    mask = _mask()
    prior = np.zeros(mask.shape)
    prior[58:62, 50:54] = 1.0  # 4 x 4 px about the true CoM: radius 2.3 px at the start
    session = comcore.ActiveSession(
        mask, rng=0, model=None, prior=prior, stop=comcore.StopRule(target_radius=0.05, min_pushes=min_pushes))
    assert session.history[0].credible_radius_px * mask.resolution < 0.05
    _run(session, World(mask))
    assert session.status == "ok" and len(session.actions) == min_pushes
