"""Tests of the frames of a push (comcore/active/_path.py, _path_term.py, observe(frames=))."""

from __future__ import annotations

import numpy as np
import pytest

import comcore
from comcore._types import PathPoint, PushRecord
from comcore.active._motion_term import STUDENT_DOF, _conditional_t, path_log_likelihood
from comcore.active._path import MAX_PATH_FRAMES, PushPath, check_frames

simulators = pytest.importorskip("simulators")
pytest.importorskip("shapely")


def _robot(obj="Obj3", friction="high", seed=1, **options):
    sim = simulators.random_simulator(obj, friction=friction, rng=seed)
    return sim, simulators.SimulatedRobot(sim, rng=seed, **options)


def _session(first, sim, **options):
    return comcore.ActiveSession(first, pusher_radius=sim.pusher_radius, rng=0, **options)


def test_conditional_t_is_the_multivariate_t_of_the_path_given_its_end():
    """The eigen-decomposed form equals the Schur complement of the joint covariance."""
    rng = np.random.default_rng(0)
    f = np.array([0.2, 0.45, 0.7, 1.0])
    wander, a, b = 0.4, 2.3, 0.35
    cov = np.outer(f, f) + wander**2 * np.minimum.outer(f, f)
    lam, vecs = np.linalg.eigh(cov)
    res = rng.normal(size=(len(f), 2))
    got = _conditional_t(res[None], np.array([a]), b, lam, vecs, 1 + wander**2)[0]
    sigma = a * cov + b * np.eye(len(f))
    s_ii, s_ik, s_kk = sigma[:-1, :-1], sigma[:-1, -1], sigma[-1, -1]
    cond = s_ii - np.outer(s_ik, s_ik) / s_kk
    quad, logdet = 0.0, 0.0
    for c in range(2):
        r = res[:-1, c] - s_ik / s_kk * res[-1, c]
        quad += r @ np.linalg.solve(cond, r)
        logdet += np.linalg.slogdet(cond)[1]
    dims = 2 * (len(f) - 1)
    want = -0.5 * (STUDENT_DOF + dims) * np.log1p(quad / STUDENT_DOF) - 0.5 * logdet
    assert got == pytest.approx(want, rel=1e-10)
    # one scale for every residual path (as a session scores a push): the same density
    scalar = _conditional_t(np.stack([res, res]), a, b, lam, vecs, 1 + wander**2)
    assert scalar == pytest.approx([want, want], rel=1e-10)


def test_a_path_shaped_as_predicted_scores_above_one_that_is_not():
    """Same end residual: the path the model predicts beats a bent one."""
    f = np.array([0.25, 0.5, 0.75])
    pred_end = np.array([0.3, 10.0, 2.0])
    pred_path = f[:, None] * pred_end
    offset = np.zeros((1, 1, 1, 2))
    straight = tuple(PathPoint(0.0, comcore.Motion(*(k * pred_end))) for k in f)
    bent = tuple(
        PathPoint(0.0, comcore.Motion(*(k * pred_end + [0.05 * (k < 0.6), 0, 0]))) for k in f
    )

    def score(points):
        path = PushPath(points, f, (0.005, 0.2))
        scales = (np.array(0.05), np.array(1.0))
        predicted = pred_end[None, None, None], pred_path[None, None, None]
        return float(
            path_log_likelihood(path, pred_end, *predicted, offset, scales, wander=0.3)[0, 0, 0]
        )

    assert score(straight) > score(bent) + 1.0


def test_frames_are_checked_by_name():
    with pytest.raises(TypeError, match="frames must be a sequence"):
        check_frames("frames")
    with pytest.raises(TypeError, match=r"frames\[0\] must be a comcore.PushFrame"):
        check_frames([3.0])
    with pytest.raises(ValueError, match=r"frames\[0\] must be a pair"):
        check_frames([((1.0, 2.0), comcore.Motion(0.0), 3)])
    with pytest.raises(TypeError, match=r"frames\[1\].view must be a comcore.Mask"):
        check_frames([((1.0, 2.0), comcore.Motion(0.0)), ((1.0, 2.0), "mask")])
    with pytest.raises(ValueError, match=r"frames\[0\].pusher"):
        check_frames([((1.0, np.nan), comcore.Motion(0.0))])


@pytest.fixture(scope="module")
def first_push():
    """A session's first push on Obj3 and the robot's frames of it at 10 Hz."""
    sim, robot = _robot()
    first = robot.camera_mask()
    session = _session(first, sim)
    action = session.next_push()
    push = robot.execute(action, frame_rate=10.0)
    return sim, first, action, push, robot.camera_mask()


def test_the_frames_are_scored_and_recorded(first_push):
    sim, first, action, push, after = first_push
    plain, framed = _session(first, sim), _session(first, sim)
    assert plain.next_push() == framed.next_push() == action
    plain.observe(after)
    framed.observe(after, frames=push.path)
    record = framed.estimate().pushes[0]
    assert 0 < len(record.path) <= MAX_PATH_FRAMES
    kept = len(record.path) + len(record.dropped_frames)
    assert kept == len(push.path)
    reasons = {why for _, why in record.dropped_frames}
    assert reasons <= {"before_contact", "at_end", "thinned", "jump"}
    # the same end pose: the path changes the posterior, not the pose or the record's motion
    assert record.motion == plain.estimate().pushes[0].motion
    assert framed.pose == plain.pose
    assert framed.history[-1].entropy_bits != plain.history[-1].entropy_bits
    # each kept frame's pose is the robot's (the first push: object frame = camera frame),
    # to the registration's error, and its travel is the pusher's along the push
    dropped = {i for i, _ in record.dropped_frames}
    kept_index = [i for i in range(len(push.path)) if i not in dropped]
    start = np.asarray(action[:2])
    direction = np.subtract(action[2:], start) / np.hypot(*np.subtract(action[2:], start))
    for i, point in zip(kept_index, record.path):
        truth = push.path_poses[i]
        assert point.motion.theta == pytest.approx(truth.theta, abs=0.03)  # 2.5 mm pixels
        assert np.hypot(point.motion.tx - truth.tx, point.motion.ty - truth.ty) < 1.0
        travel = float(np.dot(np.subtract(push.path[i].pusher, start), direction))
        assert point.travel == pytest.approx(travel, abs=1e-6)


def test_no_frames_and_an_empty_list_leave_the_session_as_before(first_push):
    sim, first, _, _, after = first_push
    a, b = _session(first, sim), _session(first, sim)
    a.next_push(), b.next_push()
    a.observe(after)
    b.observe(after, frames=[])
    assert a.history[-1] == b.history[-1]
    assert a.estimate().com == b.estimate().com


def test_a_frame_off_the_path_or_out_of_order_is_refused_and_changes_nothing(first_push):
    sim, first, _, push, after = first_push
    session = _session(first, sim)
    session.next_push()
    shifted = [comcore.PushFrame((p[0] + 40.0, p[1] + 40.0), v) for p, v in push.path]
    with pytest.raises(ValueError, match=r"frames\[0\].pusher .* off the push's path"):
        session.observe(after, frames=shifted)
    backwards = list(reversed(push.path))
    with pytest.raises(ValueError, match="in the order they were taken"):
        session.observe(after, frames=backwards)
    assert session.status == "waiting_observation"
    session.observe(after, frames=push.path)  # still waiting: the same push is read
    assert len(session.actions) == 1


def test_a_frame_that_jumps_or_cannot_be_registered_is_dropped_with_its_reason(first_push):
    sim, first, _, push, after = first_push
    frames = list(push.path)
    clean = _session(first, sim)
    clean.next_push()
    clean.observe(after, frames=frames)
    dropped = {i for i, _ in clean.estimate().pushes[0].dropped_frames}
    read = [i for i in range(len(frames)) if i not in dropped]  # the frames it registers
    assert len(read) >= 4
    jump, foreign = read[1], read[-2]
    view = frames[jump].view
    frames[jump] = comcore.PushFrame(frames[jump].pusher, _shifted(view, 12))
    other = comcore.Mask(np.zeros(first.shape, bool) | _disc(first.shape), first.resolution)
    frames[foreign] = comcore.PushFrame(frames[foreign].pusher, other)
    session = _session(first, sim)
    session.next_push()
    session.observe(after, frames=frames)
    dropped = dict(session.estimate().pushes[0].dropped_frames)
    assert dropped[jump] == "jump"
    assert dropped[foreign].startswith("registration: ")


def _shifted(mask, px):
    return comcore.Mask(np.roll(mask.data, px, axis=1), mask.resolution)


def _disc(shape):
    rows, cols = np.indices(shape)
    return (rows - shape[0] / 2) ** 2 + (cols - shape[1] / 2) ** 2 < 15**2


def test_estimate_posterior_replays_a_session_with_frames(first_push):
    sim, first, _, push, after = first_push
    session = _session(first, sim, likelihood=comcore.Likelihood(model_weight=1.0))
    session.next_push()
    session.observe(after, frames=push.path)
    est = session.estimate()
    lik = comcore.Likelihood(model_weight=1.0, systematic_error=0.0)
    replay = comcore.estimate_posterior(
        first, pushes=est.pushes, likelihood=lik, bootstrap=0, pusher_radius=sim.pusher_radius
    )
    assert replay.com == pytest.approx(est.com, abs=1e-9)
    without = [r.__class__(**{**r.__dict__, "path": ()}) for r in est.pushes]
    plain = comcore.estimate_posterior(
        first, pushes=without, likelihood=lik, bootstrap=0, pusher_radius=sim.pusher_radius
    )
    assert plain.com != pytest.approx(est.com, abs=1e-6)


def test_path_wander_none_scores_the_end_alone(first_push):
    sim, first, _, push, after = first_push
    lik = comcore.Likelihood(path_wander=None)
    a, b = _session(first, sim, likelihood=lik), _session(first, sim, likelihood=lik)
    a.next_push(), b.next_push()
    a.observe(after)
    b.observe(after, frames=push.path)
    # the same up to the path the pusher took, fitted through the frames (here the planned)
    assert b.history[-1].com == pytest.approx(a.history[-1].com, abs=1e-9)
    assert b.history[-1].entropy_bits == pytest.approx(a.history[-1].entropy_bits, abs=1e-9)
    assert len(b.estimate().pushes[0].path) > 0


def test_a_record_path_must_not_go_back():
    with pytest.raises(ValueError, match="travel must not decrease"):
        PushRecord(
            action=(0, 0, 10, 0), motion=(0.0, 1.0, 0.0), outcome="evidence",
            path=[(5.0, (0.0, 0.5, 0.0)), (3.0, (0.0, 0.2, 0.0))],
        )  # fmt: skip
    with pytest.raises(ValueError, match="path_wander"):
        comcore.Likelihood(path_wander=-1.0)


def test_push_path_fractions_lie_inside_the_push():
    points = (PathPoint(4.0, comcore.Motion(0.0)), PathPoint(9.0, comcore.Motion(0.1)))
    path = PushPath.of((0.0, 0.0, 12.0, 0.0), points, 2.0, (0.01, 0.2))
    assert path.fractions == pytest.approx([0.2, 0.7])


def test_estimate_posterior_takes_a_recordings_frames(first_push):
    """Frames as motions in the mask's frame give the session's path back, and are checked."""
    sim, first, _, push, after = first_push
    session = _session(first, sim)
    session.next_push()
    session.observe(after, frames=push.path)
    record = session.estimate().pushes[0]
    start = np.asarray(record.action[:2])
    direction = np.subtract(record.action[2:], start) / np.hypot(
        *np.subtract(record.action[2:], start)
    )
    frames = [comcore.PushFrame(tuple(start + p.travel * direction), p.motion) for p in record.path]
    lik = comcore.Likelihood(systematic_error=0.0)
    options = dict(likelihood=lik, bootstrap=0, pusher_radius=sim.pusher_radius, theta_units="rad")
    from_frames = comcore.estimate_posterior(
        first, [record.action], [record.motion], frames=[frames], **options
    )
    # motions carry no registration residual: the record's path without its residuals
    untracked = tuple(p._replace(residual_px=None) for p in record.path)
    replay = record.__class__(**{**record.__dict__, "path": untracked, "residual_px": None})
    from_record = comcore.estimate_posterior(first, pushes=[replay], **options)
    got = from_frames.pushes[0].path
    assert [p.motion for p in got] == [p.motion for p in untracked]
    assert [p.travel for p in got] == pytest.approx([p.travel for p in untracked], abs=1e-9)
    assert from_frames.com == pytest.approx(from_record.com, abs=1e-6)
    with pytest.raises(ValueError, match="one entry per push"):
        comcore.estimate_posterior(first, [record.action], [record.motion], frames=[], **options)
    bad = [comcore.PushFrame((p[0] + 50, p[1]), v) for p, v in frames]
    with pytest.raises(ValueError, match=r"frames\[0\]: frames\[0\].pusher"):
        comcore.estimate_posterior(
            first, [record.action], [record.motion], frames=[bad], **options
        )


def test_the_pushers_positions_in_the_frames_give_the_path_it_took():
    """A pusher off its commanded path (4 mm std, 1 px here): the frames show where it went."""
    sim, robot = _robot(pusher_error=0.004, seed=4)
    first = robot.camera_mask()
    session = _session(first, sim)
    action = session.next_push()
    push = robot.execute(action, frame_rate=10.0)
    session.observe(robot.camera_mask(), frames=push.path)
    record = session.estimate().pushes[0]
    executed = np.asarray(push.executed, float)
    scored = np.asarray(record.action, float)  # object frame = camera frame at the first push
    direction = (executed[2:] - executed[:2]) / np.hypot(*(executed[2:] - executed[:2]))
    across = [float(np.cross(np.r_[direction, 0], np.r_[p - executed[:2], 0])[2])
              for p in (scored[:2], scored[2:])]  # fmt: skip
    planned_off = abs(float(np.cross(np.r_[direction, 0], np.r_[action[:2] - executed[:2], 0])[2]))
    assert planned_off > 0.5  # the robot did miss its path by more than a pixel
    assert max(abs(a) for a in across) < 0.05
