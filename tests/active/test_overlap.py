"""Tests of the pusher's overlap check (comcore/active/_overlap.py): a pusher cannot pass
through the object, whatever its CoM."""

from __future__ import annotations

import numpy as np
import pytest

import comcore
from comcore.active._likelihood import Scoring, gyration_px
from comcore.active._overlap import overlap_and_allowance, pusher_overlap
from comcore.active._records import SessionState
from comcore.active._stop import offline_status, stop_reason

SQUARE = comcore.Mask(np.pad(np.ones((30, 30), bool), 8))  # 30 x 30 px, outline x, y = 7.5, 37.5
DEEP = (22.0, 42.3, 22.0, 25.5)  # up into the bottom edge, 12 px past it


def _record(action, motion, **kw):
    return comcore.PushRecord(action=action, motion=motion, outcome="evidence", **kw)


def _overlap(record, likelihood=None, radius=0.004):
    scoring = Scoring.build(likelihood or comcore.Likelihood(), SQUARE, (), pusher_radius=radius)
    return overlap_and_allowance(SQUARE, scoring, record, gyration_px(SQUARE))


# -- the fuzz finding: a turn in place reported for every push --------------------------------


@pytest.mark.parametrize("motion", [(0.1, 0.0, 0.0), (0.1, 3.0, 0.0)])
def test_a_turn_in_place_after_a_deep_push_is_inconsistent_not_ok(motion):
    est = comcore.estimate_active(
        SQUARE, lambda a: motion, stop=comcore.StopRule(max_pushes=8, target_radius=0.01), rng=0
    )
    assert est.status == "inconsistent"
    state = est.posterior.history[-1]
    assert not state.consistent
    assert state.contradiction.startswith("pushes[0]: the pusher's centre ends ")
    assert "px inside the object" in state.contradiction


def test_the_replay_of_a_contradicting_session_is_inconsistent_too():
    est = comcore.estimate_active(
        SQUARE, lambda a: (0.1, 0.0, 0.0), stop=comcore.StopRule(max_pushes=8), rng=0
    )
    again = comcore.estimate_posterior(SQUARE, pushes=est.pushes)
    assert again.status == "inconsistent"
    assert again.posterior.history[-1].contradiction == est.posterior.history[-1].contradiction


def test_estimate_posterior_names_the_push_that_contradicts():
    actions = [(22.0, 46.0, 22.0, 30.0), (46.0, 22.0, 30.0, 22.0), (22.0, 0.0, 22.0, 15.0)]
    moved = [(0.0, 0.0, -8.0), (0.0, -8.0, 0.0), (0.0, 0.0, 7.0)]  # each as far as pushed
    est = comcore.estimate_posterior(SQUARE, actions, moved)
    assert est.posterior.history[-1].contradiction is None
    short = [moved[0], (0.0, -2.0, 0.0), moved[2]]  # push 1 moved 2 px, pushed 8 px deep
    est = comcore.estimate_posterior(SQUARE, actions, short)
    assert est.status == "inconsistent"
    assert est.posterior.history[-1].contradiction.startswith("pushes[1]: ")
    assert [s.contradiction is None for s in est.posterior.history] == [True, True, False, False]


def test_the_voting_theorem_alone_reads_senses_and_checks_no_sizes():
    est = comcore.estimate_active(
        SQUARE, lambda a: (0.1, 0.0, 0.0), model=None, stop=comcore.StopRule(max_pushes=3), rng=0
    )
    assert len(est.pushes) == 3
    assert all(s.contradiction is None for s in est.posterior.history)


# -- what is checked, and what the noise allows ------------------------------------------------


def test_the_depth_is_the_discs_centres_in_the_object_moved_back():
    depth, allowed = _overlap(_record(DEEP, (0.0, 0.0, 0.0)))
    # the disc's centre 1.6 px behind the leading point at y = 25.5; the edge at y = 37.5
    assert depth == pytest.approx(37.5 - 27.1, abs=0.1)
    clear, _ = _overlap(_record(DEEP, (0.0, 0.0, -13.0)))  # moved up as far as pushed
    assert clear < 0 < allowed < depth


def test_a_point_pusher_is_its_leading_point():
    depth, _ = _overlap(_record(DEEP, (0.0, 0.0, 0.0)), radius=0.0)
    assert depth == pytest.approx(37.5 - 25.5, abs=0.1)


def test_misses_and_failed_pushes_are_not_checked():
    model = comcore.LimitSurfaceModel(pusher_radius=0.004)
    scoring = Scoring.build(comcore.Likelihood(), SQUARE, (model,), pusher_radius=0.004)
    for outcome, motion in (("miss", (0.0, 0.0, 0.0)), ("failed", None)):
        record = comcore.PushRecord(action=DEEP, motion=motion, outcome=outcome)
        assert pusher_overlap(SQUARE, scoring, record, gyration_px(SQUARE)) is None
    session = comcore.ActiveSession(SQUARE, rng=0)
    session.next_push()
    session.observe(failed=True)
    session.next_push()
    session.observe(motion=(0.0, 0.0, 0.0))  # a miss: no evidence
    assert session.pushes[1].outcome == "miss"
    assert session.history[-1].contradiction is None and session.consistent


def test_the_pushers_error_is_in_the_allowance():
    # planned 4 px inside the top edge, 8 px past the right edge, and the object did not move:
    # a pusher on its planned line went through it, one 14 mm above (under 5 standard
    # deviations of a 3 mm pusher error) passed beside
    graze = _record((46.0, 11.5, 30.0, 11.5), (0.0, 0.0, 0.0))
    exact = comcore.Likelihood(pusher_error=0.0)
    loose = comcore.Likelihood(pusher_error=0.003)
    depth, allowed_exact = _overlap(graze, exact)
    _, allowed_loose = _overlap(graze, loose)
    assert allowed_exact < depth < allowed_loose


def test_the_tracking_noise_and_the_registration_residual_are_in_the_allowance():
    record = _record(DEEP, (0.0, 0.0, 0.0))
    _, base = _overlap(record)
    _, noisy = _overlap(record, comcore.Likelihood(motion_noise=(0.0087, 0.003)))
    _, residual = _overlap(_record(DEEP, (0.0, 0.0, 0.0), residual_px=2.0))
    assert base < noisy and base < residual


def test_an_unobserved_rotation_is_checked_at_every_turn():
    # the pusher's centre 5 px from the centroid: inside the square however it turned
    deep = _overlap(_record(DEEP, (0.0, 0.0, 0.0), rotation_observed=False))
    assert deep[0] > deep[1]
    # 5.5 px into a corner, along the diagonal: an eighth of a turn brings the edge there
    corner = (46.0, 46.0, 32.0, 32.0)
    seen = _overlap(_record(corner, (0.0, 0.0, 0.0)))
    unseen = _overlap(_record(corner, (0.0, 0.0, 0.0), rotation_observed=False))
    assert seen[0] > seen[1]
    assert unseen[0] < unseen[1]


# -- the stop rule -------------------------------------------------------------------------------


def test_a_contradiction_is_inconsistent_whatever_the_excess():
    rule = comcore.StopRule(max_pushes=8)
    state = SessionState((0.0, 0.0), 0.0, 0.5, 0.0, -3.0, 8, 8, contradiction="pushes[0]: ...")
    assert not state.consistent
    assert stop_reason(rule, state, 0.0025) == "inconsistent"
    assert offline_status(state) == "inconsistent"
    assert stop_reason(rule, state._replace(contradiction=None), 0.0025) == "ok"
    # a session goes on to its stop as with an excess, and stops inconsistent then
    assert stop_reason(rule, state._replace(n_pushes=1, credible_radius_px=10.0), 0.0025) is None
