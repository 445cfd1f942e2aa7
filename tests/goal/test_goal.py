"""comcore.goal.translation_push, comcore.Goal and comcore.GoalSession."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import comcore

simulators = pytest.importorskip("simulators")


def _plate():
    """A 7.5 x 5 cm plate (2.5 mm/px) in a wide frame; its centroid is (54.5, 44.5)."""
    return comcore.Mask(np.pad(np.ones((20, 30), bool), 35))


def _line_distance(action, point) -> float:
    return abs(float(comcore.geometry.signed_line_distance(np.array([point]), np.array([action]))[0, 0]))


# -- the primitive ------------------------------------------------------------------------


@pytest.mark.parametrize("direction", [0.0, math.pi / 2, math.pi])
def test_translation_push_passes_near_the_com_and_barely_turns(direction):
    mask = _plate()
    com = (50.0, 48.0)  # 4.5 px left of and 3.5 px below the centroid
    push = comcore.goal.translation_push(mask, [com], direction, 0.03, n_offsets=11)
    assert _line_distance(push.action, com) < 1.5
    assert abs(push.expected_rotation) < 0.01 and push.rotation_spread < 1e-9
    unit = np.array([math.cos(direction), math.sin(direction)])
    assert np.allclose(push.action.direction, unit)
    assert push.expected_travel > 0.02  # the plate moves along the direction


def test_translation_push_spread_grows_with_a_wide_posterior():
    mask = _plate()
    narrow = comcore.goal.translation_push(mask, [(54.0, 46.0)], 0.0, 0.03, n_offsets=9)
    coms = np.array([(54.0, y) for y in np.linspace(38.0, 54.0, 9)])
    wide = comcore.goal.translation_push(mask, coms, 0.0, 0.03, n_offsets=9)
    assert wide.rotation_spread > 0.02 > narrow.rotation_spread
    # and the line goes through the middle of the wide posterior, where its spread is least
    assert _line_distance(wide.action, (54.0, 46.0)) < 2.5


def test_translation_push_takes_an_estimate_and_a_pose():
    mask = _plate()
    est = comcore.estimate_posterior(
        mask, [(0, 44, 60, 44), (54, 0, 54, 60)], [(-0.2, 3, 0), (0.2, 0, 3)], model=None
    )
    pose = comcore.Motion(math.pi / 2, 5.0, 0.0)  # the plate turned a quarter turn
    push = comcore.goal.translation_push(mask, est, 0.0, 0.02, pose=pose, n_offsets=5)
    assert np.allclose(push.action.direction, (1.0, 0.0))
    # in the object's frame the push runs up the first mask (-y), through the estimate
    moved = comcore.apply_motion([est.com], pose.theta, pose[1:], mask.centroid)[0]
    assert _line_distance(push.action, moved) < 4.0


def test_translation_push_refuses_bad_arguments_and_mutates_nothing():
    mask = _plate()
    coms = np.array([[54.0, 44.0], [55.0, 45.0]])
    kept = coms.copy()
    comcore.goal.translation_push(mask, coms, 0.0, 0.02, n_offsets=3)
    assert np.array_equal(coms, kept)
    with pytest.raises(ValueError, match="travel 20 m is implausible"):
        comcore.goal.translation_push(mask, coms, 0.0, 20)
    with pytest.raises(ValueError, match="posterior's CoMs must lie in the mask's image"):
        comcore.goal.translation_push(mask, coms * 1000, 0.0, 0.02)
    with pytest.raises(TypeError, match="direction must be a number"):
        comcore.goal.translation_push(mask, coms, "left", 0.02)


# -- Goal ---------------------------------------------------------------------------------


def test_goal_validates():
    with pytest.raises(ValueError, match="radians are expected"):
        comcore.Goal(orientation=45)
    with pytest.raises(ValueError, match="not both"):
        comcore.Goal(position=(0.1, 0.1), displacement=(0.1, 0.0))
    with pytest.raises(ValueError, match="needs a position"):
        comcore.Goal()
    with pytest.raises(ValueError, match="position_tolerance must be > 0"):
        comcore.Goal(displacement=(0.1, 0.0), position_tolerance=0.0)
    with pytest.raises(ValueError, match="orientation_tolerance"):
        comcore.Goal(orientation=0.0, orientation_tolerance=3.0 * 57)
    with pytest.raises(ValueError, match="units"):
        comcore.Goal(displacement=(1, 0), units="cm")
    goal = comcore.Goal(position=(0.2, 0.1))
    with pytest.raises(AttributeError):
        goal.position = (0, 0)


# -- the session --------------------------------------------------------------------------


def _robot(name, friction="low", seed=1):
    pytest.importorskip("shapely")  # the simulated robot's arm
    sim = simulators.accepted_random_simulator(name, friction, rng=seed)
    return simulators.SimulatedRobot(sim, camera_margin=0.2, rng=0)


def _run(robot, session, limit=40):
    for _ in range(limit):
        if session.done:
            break
        robot.execute(session.next_push())
        session.observe(robot.camera_mask())
    return session


def _within(robot, goal, first):
    target = goal.target_px(first)
    truth = robot.pose
    ok = True
    if target is not None:
        dist = math.hypot(truth.tx - target[0], truth.ty - target[1]) * first.resolution
        ok &= dist <= goal.position_tolerance + 0.002  # the camera's pose is read to ~a px
    if goal.orientation is not None:
        ok &= abs(truth.theta - goal.orientation) <= goal.orientation_tolerance + 0.01
    return ok


@pytest.mark.parametrize("name", ["Obj8", "Obj1"])
def test_session_reaches_a_translation_goal(name):
    """Learning while pushing, from no estimate (the benchmark measures the success rate)."""
    robot = _robot(name)
    first = robot.camera_mask()
    goal = comcore.Goal(displacement=(0.1, 0.0), orientation=0.0)
    # 10 cm at 5 cm a push is 2 pushes at best; learning from no estimate takes 11 (Obj8) and
    # 14 (Obj1, with the pusher disc's contacts in the evidence) here
    session = comcore.GoalSession(first, goal, travel=0.05,
                                  max_pushes=16, rng=0)  # fmt: skip
    _run(robot, session)
    assert session.status == "reached", session.status
    assert _within(robot, goal, first)
    assert session.estimate().pushes == session.pushes
    assert len(session.pushes) >= 2  # 10 cm at 5 cm a push


def test_session_reaches_a_pose_goal_with_a_known_com():
    robot = _robot("Obj3", "high", seed=2)
    first = robot.camera_mask()
    goal = comcore.Goal(displacement=(-0.05, 0.06), orientation=math.radians(40))
    mu = robot.simulator.mu_contact
    oracle = comcore.goal.CoMHypotheses(np.array([robot.true_com_px]), np.array([mu]), np.ones(1))
    session = comcore.GoalSession(
        first, goal, travel=0.05, max_pushes=20,
        prior=oracle, learn=False, rng=0,
    )  # fmt: skip
    _run(robot, session)
    assert session.status == "reached", session.status
    assert _within(robot, goal, first)


def test_session_is_stuck_when_the_goal_needs_a_pull():
    robot = _robot("Obj3")
    first = robot.camera_mask()
    goal = comcore.Goal(displacement=(-0.06, 0.0))  # to the left, pushes only to the right
    session = comcore.GoalSession(first, goal, push_directions=[0.0], model=None, rng=0)
    assert session.status == "stuck" and session.done
    with pytest.raises(comcore.SessionError, match="stuck"):
        session.next_push()


def test_session_learns_while_pushing():
    robot = _robot("Obj13")
    first = robot.camera_mask()
    goal = comcore.Goal(displacement=(0.1, 0.0), orientation=0.0)
    session = comcore.GoalSession(first, goal, max_pushes=3, rng=0)
    before = session.estimate().posterior.credible_radius_px
    _run(robot, session)
    after = session.estimate()
    assert after.posterior.credible_radius_px < 0.7 * before
    assert any(p.outcome == "evidence" and p.log_evidence is not None for p in after.pushes)


def test_session_reads_the_frames_of_its_pushes():
    """While it learns, the goal session scores each push's path as the active session does."""
    robot = _robot("Obj13")
    first = robot.camera_mask()
    goal = comcore.Goal(displacement=(0.1, 0.0), orientation=0.0)
    plain = comcore.GoalSession(first, goal, max_pushes=2, rng=0)
    framed = comcore.GoalSession(first, goal, max_pushes=2, rng=0)
    action = framed.next_push()
    assert plain.next_push() == action
    push = robot.execute(action, frame_rate=10.0)
    after = robot.camera_mask()
    plain.observe(after)
    with pytest.raises(TypeError, match="frames must be a sequence"):
        framed.observe(after, frames="frames")  # refused, the session still waits
    framed.observe(after, frames=push.path)
    record = framed.estimate().pushes[0]
    assert len(record.path) > 0 and record.dropped_frames
    assert plain.estimate().pushes[0].path == ()
    assert framed.estimate().com != plain.estimate().com


def test_session_order_errors_leave_it_unchanged():
    first = _plate()
    goal = comcore.Goal(displacement=(0.03, 0.0))
    session = comcore.GoalSession(first, goal, travel=0.02, model=None, rng=0)
    with pytest.raises(comcore.SessionError, match="call next_push"):
        session.observe(motion=(0.0, 4.0, 0.0))
    push = session.next_push()
    for bad, kind in (
        ({"mask": first, "motion": (0.0, 1.0, 0.0)}, TypeError),
        ({"motion": (0.0, 1.0)}, ValueError),
        ({"mask": comcore.Mask(np.ones((5, 5), bool))}, ValueError),
        ({"out_of_view": 1}, TypeError),
    ):
        with pytest.raises(kind):
            session.observe(**bad)
        assert session.status == "waiting_observation" and session.pushes == ()
        assert session.next_push() == push and session.pose == comcore.Motion.identity()
    session.observe(motion=(0.0, 12.0, 0.0))
    assert session.status == "reached"
    with pytest.raises(comcore.SessionError, match="reached"):
        session.observe(motion=(0.0, 1.0, 0.0))


def test_session_refuses_bad_goals_and_arguments():
    first = _plate()
    with pytest.raises(TypeError, match="goal must be a comcore.Goal"):
        comcore.GoalSession(first, (0.1, 0.0, 0.0))
    with pytest.raises(ValueError, match="outside the camera's"):
        comcore.GoalSession(first, comcore.Goal(displacement=(60, 0), units="px"), model=None)
    with pytest.raises(ValueError, match="travel"):
        comcore.GoalSession(
            first, comcore.Goal(orientation=0.5), travel=5, model=None
        )
    with pytest.raises(ValueError, match="push_directions"):
        comcore.GoalSession(first, comcore.Goal(orientation=0.5), push_directions=[np.nan])


def test_session_lost_when_the_object_leaves_the_view():
    first = _plate()
    session = comcore.GoalSession(first, comcore.Goal(orientation=0.3), model=None, rng=0)
    session.next_push()
    edge = np.zeros(first.shape, bool)
    edge[:20, :30] = True  # touches the border
    session.observe(comcore.Mask(edge))
    assert session.status == "lost" and session.done
    other = comcore.GoalSession(first, comcore.Goal(orientation=0.3), model=None, rng=0)
    other.next_push()
    other.observe(out_of_view=True)
    assert other.status == "lost"


def test_session_takes_an_estimate_or_an_active_session_as_prior_and_mutates_nothing():
    first = _plate()
    image = first.data.copy()
    active = comcore.ActiveSession(first, model=None, rng=0)
    goal = comcore.Goal(displacement=(0.02, 0.0))
    for learn in (False, True):
        # an ActiveSession is taken as its estimate now (its CoM and friction posteriors)
        a = comcore.GoalSession(first, goal, prior=active, model=None, learn=learn, rng=0)
        b = comcore.GoalSession(first, goal, prior=active.estimate(), model=None, learn=learn)
        assert a.next_push() == b.next_push()
    assert np.array_equal(first.data, image)
    assert active.status == "waiting_push" and active.pushes == ()


def test_a_learning_session_starts_from_the_estimates_friction_posterior_too():
    """What an estimate learnt of the friction is kept, not reset to the flat prior."""
    mask = _plate()
    com = (22.0, 15.0)
    actions = comcore.sample_pushes(mask, 8, cone=0.3, rng=2)
    d = comcore.geometry.signed_line_distance([com], actions)[0]
    motions = [(0.05 * np.sign(v), 0.0, 0.0) for v in d]
    est = comcore.estimate_posterior(mask, actions, motions, model=None)
    # senses tell little of the friction: say the estimate learnt it was low
    mu_post = np.array([0.7, 0.2, 0.05, 0.03, 0.01, 0.01])
    est = dataclasses.replace(est, posterior=dataclasses.replace(est.posterior, mu_posterior=mu_post))
    goal = comcore.Goal(displacement=(0.02, 0.0))
    learning = comcore.GoalSession(mask, goal, prior=est, model=None, rng=0)
    np.testing.assert_allclose(learning._posterior.mu_marginal, mu_post, atol=1e-5)
    # its CoM prior is the estimate's posterior image
    image = np.zeros(mask.shape)
    px = learning._posterior.pixels.astype(int)
    image[px[:, 1], px[:, 0]] = learning._posterior.weights.sum(axis=(1, 2))
    np.testing.assert_allclose(image, est.posterior.image / est.posterior.image.sum(),
                               atol=1e-9)  # fmt: skip
    # other friction values than the estimate's: the friction starts flat
    other = comcore.GoalSession(mask, goal, prior=est, model=None, rng=0,
                                likelihood=comcore.Likelihood(n_mu=4))  # fmt: skip
    np.testing.assert_allclose(other._posterior.mu_marginal, 0.25, atol=1e-12)
    # a malformed friction posterior is refused, naming it
    bad = dataclasses.replace(est.posterior, mu_posterior=[0.5, -0.5])
    bad = dataclasses.replace(est, posterior=bad)
    with pytest.raises(ValueError, match=r"posterior.mu_posterior must be non-negative"):
        comcore.GoalSession(mask, goal, prior=bad, model=None, rng=0)


def test_sessions_are_reproducible():
    pushes = []
    for _ in range(2):
        robot = _robot("Obj3")
        first = robot.camera_mask()
        goal = comcore.Goal(displacement=(0.05, 0.03), orientation=0.2)
        session = comcore.GoalSession(first, goal, max_pushes=3, rng=0)
        _run(robot, session)
        pushes.append([p.camera_action for p in session.pushes])
    assert pushes[0] == pushes[1]


def test_the_budget_and_the_push_length_are_keywords_of_their_own():
    first = _plate()
    goal = comcore.Goal(displacement=(0.03, 0.0))
    session = comcore.GoalSession(first, goal, max_pushes=1, travel=0.02, model=None, rng=0)
    push = session.next_push()
    assert np.hypot(push.ex - push.sx, push.ey - push.sy) * first.resolution < 0.02 + 0.02
    session.observe(motion=(0.0, 1.0, 0.0))  # 2.5 mm of the 3 cm asked: the budget is spent
    assert session.status == "budget"
    with pytest.raises(ValueError, match="max_pushes must be >= 1, got 0"):
        comcore.GoalSession(first, goal, max_pushes=0, model=None)
    with pytest.raises(ValueError, match="travel 0.001 m is under two pixels of the mask"):
        comcore.GoalSession(first, goal, travel=0.001, model=None)
    for group in ({"stop": comcore.StopRule()}, {"choice": comcore.PushChoice()}):
        with pytest.raises(TypeError, match="unexpected keyword argument"):
            comcore.GoalSession(first, goal, model=None, **group)


# -- the frame, the units, the metric pose --------------------------------------------------


def test_goal_states_its_frame_where_it_is_introduced():
    """+y is down the screen (the pixel frame), relative to the first mask: said in the docstring."""
    doc = " ".join(comcore.Goal.__doc__.split())
    assert "+y down the screen" in doc and "relative to the first mask" in doc
    assert "not a robot's or a table's y-up world frame" in doc


def test_a_goal_down_the_screen_is_pushed_down_the_image():
    first = _plate()
    session = comcore.GoalSession(first, comcore.Goal(displacement=(0.0, 0.02)), model=None, rng=0)
    push = session.next_push()
    assert push.ey > push.sy  # +y: larger rows, down the image
    session.observe(motion=(0.0, 0.0, 8.0))  # 8 px = 2 cm down the screen
    assert session.status == "reached"


def _wide_plate():
    """The 7.5 x 5 cm plate in an 80 x 82 cm view: millimetres and pixels both fit in it."""
    return comcore.Mask(np.pad(np.ones((20, 30), bool), 150))


@pytest.mark.parametrize(
    ("first", "goal", "likelier"),
    [
        # 100 (meant as mm) on a 7.5 cm plate: 10 cm reads as a goal, 25 cm (px) less so
        (_wide_plate(), comcore.Goal(displacement=(100, 0)), "millimetres"),
        # in the small view only the millimetres put the object in view
        (_plate(), comcore.Goal(displacement=(100, 0)), "millimetres"),
        (_plate(), comcore.Goal(position=(150, 120)), "millimetres"),
        # 8 on a 7.5 cm plate: 2 cm (px) reads as a goal, 8 mm less so
        (_wide_plate(), comcore.Goal(displacement=(8, 0)), "pixels"),
        (_wide_plate(), comcore.Goal(displacement=(30, -40)), "pixels"),
    ],
)
def test_a_goal_out_of_view_hints_at_the_likelier_unit_first(first, goal, likelier):
    with pytest.raises(ValueError, match="outside the camera's") as info:
        comcore.GoalSession(first, goal, model=None)
    message = str(info.value)
    field = "displacement" if goal.displacement is not None else "position"
    numbers = ", ".join(f"{v / 1000:g}" for v in getattr(goal, field))
    mm, px = f"millimetres, {field}=({numbers}) in metres", "pixels, units='px'"
    first_hint, second_hint = (mm, px) if likelier == "millimetres" else (px, mm)
    assert message.endswith(f": did you mean {first_hint}? Or {second_hint}?"), message


def test_a_goal_in_pixels_out_of_view_gets_no_unit_hint():
    with pytest.raises(ValueError, match=r"outside the camera's 100 x 90 px view: pixels beyond"):
        comcore.GoalSession(_plate(), comcore.Goal(displacement=(60, 0), units="px"), model=None)


def test_pose_m_is_the_pose_with_its_translation_in_metres():
    first = _plate()  # 2.5 mm a pixel
    goal = comcore.Goal(displacement=(0.05, 0.0))
    session = comcore.GoalSession(first, goal, travel=0.02, model=None, rng=0)
    assert session.pose_m == (0.0, 0.0, 0.0)
    session.next_push()
    session.observe(motion=(0.1, 8.0, -2.0))
    assert session.pose == comcore.Motion(0.1, 8.0, -2.0)
    assert isinstance(session.pose_m, comcore.goal.MetricPose)
    np.testing.assert_allclose(session.pose_m, (0.1, 0.02, -0.005))
    assert session.pose_m._fields == ("theta", "tx", "ty")


# -- the bound on the turn on the way ---------------------------------------------------------


def test_goal_max_turn_validates():
    assert comcore.Goal(displacement=(0.1, 0.0)).max_turn is None
    assert comcore.Goal(displacement=(0.1, 0.0), max_turn=0.5).max_turn == 0.5
    with pytest.raises(ValueError, match=r"max_turn must be in \(0, 2 pi\] radians, got 30 \(degrees"):
        comcore.Goal(displacement=(0.1, 0.0), max_turn=30)
    with pytest.raises(ValueError, match="max_turn must be in"):
        comcore.Goal(displacement=(0.1, 0.0), max_turn=0.0)
    assert comcore.Goal(orientation=-1.0).turn_band(0.2) == (-1.0, 0.2)
    assert comcore.Goal(displacement=(0.1, 0.0)).turn_band(0.2) == (0.2, 0.2)


def _big_plate_oracle():
    mask = comcore.Mask(np.pad(np.ones((20, 30), bool), 60))
    com = (50.0, 48.0)  # 4.5 px left of and 3.5 px below the centroid
    return mask, comcore.goal.CoMHypotheses(np.array([com]), np.array([0.3]), np.ones(1))


@pytest.mark.parametrize("displacement", [(0.1, 0.0), (0.0, 0.1), (0.07, 0.07)])
def test_max_turn_keeps_the_planned_turn_within_the_bound(displacement):
    """The orientation free: unbounded, the known-CoM planner turns the plate 30-75 degrees."""
    mask, oracle = _big_plate_oracle()
    bound = math.radians(5)
    plans = {}
    for max_turn in (None, bound):
        goal = comcore.Goal(displacement=displacement, max_turn=max_turn)
        session = comcore.GoalSession(mask, goal, prior=oracle, learn=False, model=None, rng=0)
        assert session.status == "waiting_push"
        plans[max_turn] = session._plan.expected_pose.theta  # one particle: its prediction
    assert abs(plans[None]) > 4 * bound
    assert abs(plans[bound]) <= bound + 1e-9


@pytest.mark.parametrize(("displacement", "turned"), [((0.0, 0.1), -20.0), ((0.1, 0.0), 40.0)])
def test_max_turn_past_the_bound_allows_no_push_that_turns_further(displacement, turned):
    """A push turned the plate past the bound (mispredicted): the next may not turn it further."""
    mask, oracle = _big_plate_oracle()
    plans = {}
    for max_turn in (None, math.radians(5)):
        goal = comcore.Goal(displacement=displacement, max_turn=max_turn)
        session = comcore.GoalSession(mask, goal, prior=oracle, learn=False, model=None, rng=0)
        session.next_push()
        session.observe(motion=(math.radians(turned), 0.0, 4.0))
        assert session.status == "waiting_push"
        plans[max_turn] = math.degrees(session._plan.expected_pose.theta)
    assert abs(plans[None]) > abs(turned) + 10  # unbounded, it would turn the plate further
    assert abs(plans[math.radians(5)]) <= abs(turned) + 1e-6


def test_max_turn_bounds_the_follow_ups_too():
    mask, oracle = _big_plate_oracle()
    from comcore.goal._costs import PlanningContext, follow_ups
    from comcore.goal._translation import planning_model

    goal = comcore.Goal(displacement=(0.0, 0.1))
    poses = (np.zeros(1), np.zeros(1), np.zeros(1))
    directions = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    args = (mask, goal, goal.target_px(mask), planning_model(0.004), 20.0, 0.004)
    free = follow_ups(PlanningContext(*args), poses, oracle, directions, None)
    turn = (0.0, 0.0, math.radians(0.01))
    bounded = follow_ups(PlanningContext(*args, turn=turn), poses, oracle, directions, None)
    assert np.isfinite(free).all() and (bounded >= free).all() and (bounded > free).any()


# -- learning pushes where no push passes the planner's rules -------------------------------


def _too_wide():
    """A goal no push passes on the plate's uniform prior: 3 cm right, held within 0.5 degrees.

    Only pushes to the right are allowed: every one may turn the plate by more than the
    tolerance either way, so none is expected to help, nor has a quarter's chance to.
    """
    goal = comcore.Goal(displacement=(0.03, 0.0), orientation=0.0,
                        orientation_tolerance=math.radians(0.5))  # fmt: skip
    return _plate(), goal, {"model": None, "rng": 0, "push_directions": [0.0]}


def test_a_wide_posterior_makes_a_learning_push_where_it_said_stuck():
    first, goal, options = _too_wide()
    before = comcore.GoalSession(first, goal, learning_pushes=0, **options)
    assert before.status == "stuck"  # as every session said before learning pushes
    assert comcore.GoalSession(first, goal, learn=False, **options).status == "stuck"
    session = comcore.GoalSession(first, goal, **options)
    assert session.status == "waiting_push" and session.next_push_kind == "learn"
    push = session.next_push()
    assert push.ex > push.sx and abs(push.ey - push.sy) < 1e-6  # the allowed direction only
    # safe for the goal: on average at most LEARNING_SLACK tolerances (1 cm) farther from it
    expected = session._plan.expected_pose
    target = goal.target_px(first)
    farther = math.hypot(expected.tx - target[0], expected.ty - target[1]) - math.hypot(*target)
    assert farther * first.resolution <= comcore.goal._planner.LEARNING_SLACK * 0.01 + 1e-9
    radius = session.estimate().posterior.credible_radius_px
    session.observe(motion=(0.05, 3.0, 0.0))
    assert session.push_kinds == ("learn",) and len(session.pushes) == 1
    assert session.pushes[0].outcome == "evidence"
    assert session.estimate().posterior.credible_radius_px < 0.8 * radius  # it taught it
    assert session.status == "waiting_push" and session.next_push_kind in ("goal", "probe")
    session.next_push()
    session.observe(motion=(0.0, 3.0, 0.0))
    assert session.push_kinds[1] in ("goal", "probe")


def test_learning_pushes_keep_to_their_budget(monkeypatch):
    """No push ever passes the planner's rules: ``learning_pushes`` in a row, then stuck."""
    from comcore.goal import _session as goal_session

    first, goal, options = _too_wide()
    options = {**options, "push_directions": None}
    monkeypatch.setattr(goal_session, "plan_push", lambda *args, **kwargs: None)
    for budget in (0, 1, 3):
        session = comcore.GoalSession(first, goal, learning_pushes=budget, **options)
        pushed = []
        while not session.done:
            pushed.append(session.next_push())
            session.observe(motion=(0.05 * (-1) ** len(pushed), 2.0, 0.0))
        assert session.status == "stuck"
        assert session.push_kinds == ("learn",) * budget
        assert len(set(pushed)) == budget  # none made twice, as an ActiveSession's
    # the session's budget comes first
    session = comcore.GoalSession(first, goal, max_pushes=1, **options)
    session.next_push()
    session.observe(motion=(0.05, 2.0, 0.0))
    assert session.status == "budget" and session.push_kinds == ("learn",)


def test_learning_pushes_option_is_checked():
    first, goal, options = _too_wide()
    with pytest.raises(ValueError, match="learning_pushes must be >= 0, got -1"):
        comcore.GoalSession(first, goal, learning_pushes=-1, **options)
    for bad in (1.5, True, "3"):
        with pytest.raises(TypeError, match="learning_pushes must be an int"):
            comcore.GoalSession(first, goal, learning_pushes=bad, **options)
