"""Tests of reading one push (comcore/active/_reading.py): record, evidence and the new pose."""

from __future__ import annotations

import math

import numpy as np
import pytest

import comcore
from comcore.active._choice import Candidates
from comcore.active._grid import prior_grid
from comcore.active._likelihood import Evidence, Scoring, gyration_px
from comcore.active._reading import PushContext, best_branch, object_motion, push_record, read_push
from comcore.camera._pose_tracking import PoseReading
from comcore.conventions import rotate_vectors

#: A plate, 20 x 20 px, 8 px margin: object pixels 8..27, centroid (17.5, 17.5).
PLATE = comcore.Mask(np.pad(np.ones((20, 20), bool), 8))
LEFT = (0.0, 13.0, 30.0, 13.0)  # a push from the left, 4.5 px above the centroid
RIGHT = (35.0, 22.0, 12.0, 22.0)


def _ell():
    img = np.zeros((40, 44), bool)
    img[8:30, 8:16] = True
    img[22:30, 8:34] = True
    return comcore.Mask(img)


def _context(pose=None, mask=PLATE, prior=None, likelihood=None):
    scoring = Scoring.build(likelihood or comcore.Likelihood(n_mu=2), mask, ())
    pixels, weights = prior_grid(mask, prior)
    post = scoring.posterior(pixels, weights)
    pose = comcore.Motion.identity() if pose is None else pose
    return PushContext(mask, pose, post, scoring, gyration_px(mask))


def _candidates(ctx, actions=(LEFT, RIGHT)):
    return Candidates(ctx.first, np.array(actions), comcore.PushChoice(), ctx.scoring.mus,
                      np.random.default_rng(0), pusher_radius=0.0)  # fmt: skip


def _read(ctx, index=0, mask=None, motion=None, failed=False, executed=None):
    return read_push(ctx, _candidates(ctx), index, mask, motion, failed, executed=executed)


# -- outcomes -----------------------------------------------------------------------------------


def test_a_failed_push_is_recorded_as_planned_with_no_motion_evidence_or_pose():
    pose = comcore.Motion(0.0, 2.0, 1.0)
    ctx = _context(pose)
    record, evidence, new_pose = _read(ctx, index=1, failed=True)
    assert record.outcome == "failed" and record.motion is None
    assert evidence == () and new_pose is None
    assert record.index == 1 and record.action == RIGHT and record.planned == RIGHT
    assert record.pose_before == pose
    assert record.camera_action == pytest.approx((37.0, 23.0, 14.0, 23.0))  # moved with the pose


def test_a_motion_below_the_noise_is_a_miss_without_evidence():
    ctx = _context()
    # 0.005 rad and 0.3 px (0.75 mm at 2.5 mm/px): below 0.01 rad and 1 mm
    record, evidence, pose = _read(ctx, motion=(0.005, 0.3, 0.0))
    assert record.outcome == "miss" and evidence == ()
    assert record.motion == pytest.approx((0.005, 0.3, 0.0))
    assert pose == pytest.approx((0.005, 0.3, 0.0))  # the pose follows it all the same
    record, evidence, _ = _read(ctx, motion=(0.0, 0.5, 0.0))  # 1.25 mm: it moved
    assert record.outcome == "evidence" and len(evidence) == 2


def test_a_push_with_evidence_is_scored_and_changes_nothing():
    ctx = _context()
    before = ctx.posterior.log_w.copy()
    record, (loglik, excess), pose = _read(ctx, motion=(0.1, 4.0, 0.5))
    np.testing.assert_array_equal(ctx.posterior.log_w, before)
    assert isinstance(loglik, Evidence)
    assert loglik.full.shape == excess.shape == (PLATE.area_px, 2, 1)
    assert record.outcome == "evidence" and record.action == LEFT
    assert record.motion == pytest.approx((0.1, 4.0, 0.5))  # at the first pose: as seen
    assert record.camera_motion == pytest.approx((0.1, 4.0, 0.5))
    assert record.rotation_observed and record.residual_px is None and record.symmetry == 1
    assert pose == pytest.approx((0.1, 4.0, 0.5))


def test_a_bad_motion_is_named():
    with pytest.raises(ValueError, match="motion"):
        _read(_context(), motion=(0.1, 2.0))


# -- frames -------------------------------------------------------------------------------------


def test_the_motion_is_scored_in_the_object_s_frame_whatever_the_pose():
    """The object turned by a quarter turn: the same object-frame motion, the same evidence."""
    pose = comcore.Motion(math.pi / 2, 1.0, -2.0)
    moved_ctx, first_ctx = _context(pose), _context()
    in_object = np.array([0.08, 3.0, 1.0])
    in_camera = (in_object[0], *rotate_vectors(in_object[None, 1:], pose.theta)[0])
    record, (loglik, _), new_pose = _read(moved_ctx, motion=in_camera)
    assert record.motion == pytest.approx(tuple(in_object))
    assert record.camera_motion == pytest.approx(in_camera)
    assert new_pose == pytest.approx((pose.theta + 0.08, pose.tx + in_camera[1], pose.ty + in_camera[2]))
    _, (at_first, _), _ = _read(first_ctx, motion=tuple(in_object))
    np.testing.assert_allclose(loglik.full, at_first.full, atol=1e-12)


def test_object_motion_is_the_reading_s_pose_change_in_the_object_s_frame():
    reading = PoseReading(comcore.Motion(0.3, 5.0, 0.0), False, float("nan"))
    np.testing.assert_allclose(object_motion(comcore.Motion.identity(), reading), [0.3, 5.0, 0.0])
    at = comcore.Motion(0.1, 5.0, 0.0)
    later = PoseReading(comcore.Motion(0.1 + 0.2, 5.0 + 3.0, 4.0), False, float("nan"))
    m = object_motion(at, later)
    assert m[0] == pytest.approx(0.2)
    assert np.hypot(m[1], m[2]) == pytest.approx(5.0)  # a turn of the frame keeps its length
    np.testing.assert_allclose(rotate_vectors(m[None, 1:], at.theta)[0], [3.0, 4.0], atol=1e-12)


def test_a_mask_is_registered_against_the_first_and_its_residual_recorded():
    ell = _ell()
    ctx = _context(mask=ell)
    shifted = comcore.Mask(np.roll(ell.data, 3, axis=1))  # 3 px to the right
    cands = _candidates(ctx, [(0.0, 12.0, 20.0, 12.0)])
    record, evidence, pose = read_push(ctx, cands, 0, shifted, None, False, executed=None)
    assert record.outcome == "evidence" and len(evidence) == 2
    assert pose.theta == pytest.approx(0.0, abs=0.01) and pose.tx == pytest.approx(3.0, abs=0.1)
    assert record.residual_px is not None and 0 <= record.residual_px < 1.5
    with pytest.raises(ValueError, match="mask must have the first mask's shape"):
        read_push(ctx, cands, 0, comcore.Mask(np.pad(ell.data, 1)), None, False, executed=None)


def test_push_record_keeps_the_registration_s_word():
    base = {"index": 4, "planned": LEFT, "camera_action": LEFT, "pose_before": comcore.Motion.identity()}
    seen = PoseReading(comcore.Motion(0.2, 3.0, 0.0), False, 0.4, 4)
    record = push_record(base, comcore.Motion.identity(), LEFT, seen, "evidence")
    assert record.residual_px == 0.4 and record.symmetry == 4 and record.rotation_observed
    blind = PoseReading(comcore.Motion(0.0, 3.0, 0.0), True, float("nan"))
    record = push_record(base, comcore.Motion.identity(), LEFT, blind, "evidence")
    assert record.residual_px is None and not record.rotation_observed
    assert record.index == 4 and record.motion == pytest.approx((0.0, 3.0, 0.0))


# -- executed paths -------------------------------------------------------------------------------


def test_a_push_executed_off_its_plan_is_scored_where_it_went():
    ctx = _context()
    executed = (0.0, 16.0, 30.0, 16.0)  # 3 px below the plan
    record, (went, _), _ = _read(ctx, motion=(0.1, 4.0, 0.0), executed=executed)
    assert record.action == pytest.approx(executed) and record.planned == LEFT
    _, (planned, _), _ = _read(ctx, motion=(0.1, 4.0, 0.0))
    cands = _candidates(ctx, [executed])
    _, (there, _), _ = read_push(ctx, cands, 0, None, (0.1, 4.0, 0.0), False, executed=None)
    np.testing.assert_allclose(went.full, there.full)
    assert not np.allclose(went.full, planned.full)


def test_an_executed_path_that_misses_the_object_is_refused_unless_the_push_missed():
    ctx = _context()
    off = (0.0, 2.0, 30.0, 2.0)  # above the plate
    with pytest.raises(ValueError, match=r"executed \[0.0, 2.0, 30.0, 2.0\] misses the object"):
        _read(ctx, motion=(0.1, 4.0, 0.0), executed=off)
    record, evidence, _ = _read(ctx, motion=(0.0, 0.0, 0.0), executed=off)
    assert record.outcome == "miss" and evidence == () and record.action == LEFT  # as planned
    with pytest.raises(ValueError, match="executed .* starts inside the object"):
        _read(ctx, motion=(0.1, 4.0, 0.0), executed=(17.0, 17.0, 30.0, 17.0))


# -- symmetric outlines ---------------------------------------------------------------------------


def test_of_a_symmetric_outline_s_readings_the_one_the_posterior_explains_best_is_kept():
    """A square read as turned by 0.7 rad may have turned by 0.7 - pi/2 the other way."""
    ctx = _context()
    cands = _candidates(ctx)
    # the CoM known to lie on one side of the push LEFT: the side that one sense says
    _, (loglik, _), _ = _read(ctx, motion=(-0.3, 0.0, 0.0))
    side = loglik.full[:, 0, 0] > np.median(loglik.full[:, 0, 0])
    prior = np.zeros(PLATE.shape)
    prior[ctx.posterior.pixels[side, 1].astype(int), ctx.posterior.pixels[side, 0].astype(int)] = 1
    sure = _context(prior=prior)
    near = PoseReading(comcore.Motion(0.7, 2.0, 0.0), False, 0.3, 4)
    far = near._replace(pose=comcore.Motion(0.7 - math.pi / 2, 2.0, 0.0))
    for branches in ([near, far], [far, near]):
        branch, loglik, excess = best_branch(sure, branches, cands.actions[0], cands.lines[0])
        assert branch.pose.theta == pytest.approx(0.7 - math.pi / 2)
        assert loglik.full.shape == excess.shape
