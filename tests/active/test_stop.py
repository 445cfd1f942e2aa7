"""Tests of the stop rule (comcore/active/_stop.py): when a session stops, and its status."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy import stats

import comcore
from comcore.active._likelihood import consistency_threshold
from comcore.active._records import SessionState
from comcore.active._stop import (
    SENSE_ALPHA,
    STATUSES,
    choice_status,
    offline_status,
    sense_check,
    stop_index,
    stop_reason,
)
from comcore.vt._voting import SenseTally

RESOLUTION = 0.0025  # m/px: the default target radius of 6 mm is 2.4 px


def _state(radius_px=10.0, n_pushes=0, n_evidence=None, excess=0.0):
    n_evidence = n_pushes if n_evidence is None else n_evidence
    return SessionState((0.0, 0.0), 5.0, radius_px, 0.0, excess, n_pushes, n_evidence)


def _inconsistent(**kw):
    state = _state(**kw)
    return state._replace(excess_nats=consistency_threshold(state.n_evidence) + 1.0)


# -- stop_reason -----------------------------------------------------------------------------


@settings(max_examples=100)
@given(
    radius_px=st.floats(0.0, 20.0),
    n_pushes=st.integers(0, 12),
    misses=st.integers(0, 12),
    max_pushes=st.integers(0, 10),
    min_pushes=st.integers(0, 10),
    target_px=st.floats(0.6, 10.0),
)
def test_the_rule_stops_ok_at_the_target_after_min_pushes_else_budget(
    radius_px, n_pushes, misses, max_pushes, min_pushes, target_px
):
    assume(abs(radius_px - target_px) > 1e-9)  # not at the edge, where metres round
    n_evidence = max(n_pushes - misses, 0)
    rule = comcore.StopRule(
        max_pushes=max_pushes, min_pushes=min_pushes, target_radius=target_px * RESOLUTION
    )
    state = _state(radius_px, n_pushes, n_evidence)
    reason = stop_reason(rule, state, RESOLUTION)
    if radius_px < target_px and n_evidence >= min_pushes:
        assert reason == "ok"
    elif n_pushes >= max_pushes:
        assert reason == "budget"
    else:
        assert reason is None
    # never "ok" before min_pushes pushes with evidence, nor with a region above the target
    if reason == "ok":
        assert n_evidence >= min_pushes and radius_px <= target_px
    # the public face is the same rule
    assert rule.reason(state, RESOLUTION) == reason


def test_a_small_region_waits_for_min_pushes_with_evidence_misses_do_not_count():
    rule = comcore.StopRule(min_pushes=3, max_pushes=10)
    tiny = 0.1  # px: far below 6 mm
    assert stop_reason(rule, _state(tiny, n_pushes=5, n_evidence=2), RESOLUTION) is None
    assert stop_reason(rule, _state(tiny, n_pushes=3, n_evidence=3), RESOLUTION) == "ok"


def test_the_target_is_in_metres_and_compared_in_pixels_of_the_resolution():
    rule = comcore.StopRule(target_radius=0.005, min_pushes=0)
    state = _state(radius_px=4.0, n_pushes=1)  # 4 px: 1 cm at 2.5 mm/px, 4 mm at 1 mm/px
    assert stop_reason(rule, state, 0.0025) is None
    assert stop_reason(rule, state, 0.001) == "ok"
    # exactly at the target: "at most target_radius" stops
    assert stop_reason(rule, _state(radius_px=5.0, n_pushes=1), 0.001) == "ok"


def test_ok_comes_before_budget_when_both_hold():
    rule = comcore.StopRule(max_pushes=2, min_pushes=2)
    assert stop_reason(rule, _state(0.5, n_pushes=2), RESOLUTION) == "ok"
    assert stop_reason(rule, _state(50.0, n_pushes=2), RESOLUTION) == "budget"
    assert stop_reason(rule, _state(50.0, n_pushes=3), RESOLUTION) == "budget"


def test_a_zero_budget_stops_at_the_prior_and_a_tight_prior_may_stop_ok():
    prior = _state(50.0, n_pushes=0)
    assert stop_reason(comcore.StopRule(max_pushes=0), prior, RESOLUTION) == "budget"
    tight = _state(0.5, n_pushes=0)
    assert stop_reason(comcore.StopRule(min_pushes=0), tight, RESOLUTION) == "ok"
    assert stop_reason(comcore.StopRule(min_pushes=1), tight, RESOLUTION) is None


@pytest.mark.parametrize(("radius_px", "n_pushes"), [(0.5, 3), (50.0, 5)])
def test_an_inconsistent_state_stops_inconsistent_instead(radius_px, n_pushes):
    rule = comcore.StopRule(max_pushes=5)
    state = _inconsistent(radius_px=radius_px, n_pushes=n_pushes)
    assert not state.consistent
    assert stop_reason(rule, state, RESOLUTION) == "inconsistent"
    # ... but only when it stops: a session that goes on is not stopped by it
    assert stop_reason(rule, _inconsistent(radius_px=50.0, n_pushes=2), RESOLUTION) is None


# -- choice_status -------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("gain", "expected"),
    [(None, "exhausted"), (0.0, "uninformative"), (1e-3, "uninformative"),
     (float("nan"), "uninformative"), (2e-3, None), (0.8, None)],
)  # fmt: skip
def test_the_choice_goes_on_only_with_a_gain_above_min_information(gain, expected):
    rule = comcore.StopRule(min_information=1e-3)
    assert choice_status(rule, _state(n_pushes=1), gain) == expected
    bad = choice_status(rule, _inconsistent(n_pushes=1), gain)
    assert bad == (None if expected is None else "inconsistent")


# -- offline_status and the senses' check ----------------------------------------------------


def _tally(n_pushes, n_against, n_pixels=2):
    """Pushes all saying the CoM is at pixel 0 except ``n_against`` saying pixel 1."""
    tally = SenseTally((n_pixels, 1))
    distances = np.array([[5.0], [-5.0]])
    for i in range(n_pushes):
        tally.add(distances, -1 if i < n_against else +1, 0.05, 1.0)
    return tally


def test_offline_status_needs_evidence_and_consistent_senses():
    assert offline_status(_state(n_pushes=3, n_evidence=0)) == "no_evidence"
    assert offline_status(_state(n_pushes=3)) == "ok"
    assert offline_status(_inconsistent(n_pushes=3)) == "inconsistent"
    good, bad = sense_check(_tally(20, 0), 0), sense_check(_tally(20, 0), 1)
    assert offline_status(_state(n_pushes=20), good) == "ok"
    assert offline_status(_state(n_pushes=20), bad) == "inconsistent"
    # no evidence comes first, whatever the senses
    assert offline_status(_state(n_pushes=20, n_evidence=0), bad) == "no_evidence"


def test_sense_check_counts_what_the_hypotheses_leave_unexplained():
    check = sense_check(_tally(12, 3), 0)
    assert check.n_pushes == 12
    assert check.fewest_unexplained == 3  # pixel 0 leaves the 3 against it, pixel 1 the other 9
    assert check.unexplained_at_estimate == 3
    assert sense_check(_tally(12, 3), 1).unexplained_at_estimate == 9
    assert 12 * 0.05 < check.expected < 12 * 0.1  # flip_prob plus the line's edge, per push


def test_the_p_value_is_the_binomial_tail_for_equal_probabilities():
    for n, against in ((40, 0), (40, 5), (40, 12), (7, 2)):
        check = sense_check(_tally(n, against), 0)
        p = check.expected / n
        assert check.p_value == pytest.approx(stats.binom.sf(against - 1, n, p), rel=1e-9)


def test_forty_pushes_with_ten_unexplained_are_inconsistent_nine_are_not():
    """The docstring's example: flip_prob 0.05 and 40 pushes, 10 or more unexplained."""
    nine, ten = sense_check(_tally(40, 9), 0), sense_check(_tally(40, 10), 0)
    assert nine.p_value >= SENSE_ALPHA and nine.consistent
    assert ten.p_value < SENSE_ALPHA and not ten.consistent


def test_an_estimate_that_most_senses_contradict_is_inconsistent():
    """Pixel 2 explains every sense; the estimate at pixel 1 half of them, or fewer."""

    def tally(n_against_pixel_1, n=10):
        t = SenseTally((3, 1))
        for i in range(n):
            d1 = -5.0 if i < n_against_pixel_1 else 5.0
            t.add(np.array([[-5.0], [d1], [5.0]]), +1, 0.05, 1.0)
        return t

    half, most = sense_check(tally(5), 1), sense_check(tally(6), 1)
    assert half.fewest_unexplained == most.fewest_unexplained == 0 and half.p_value == 1.0
    assert (half.unexplained_at_estimate, most.unexplained_at_estimate) == (5, 6)
    assert half.consistent and not most.consistent
    assert sense_check(tally(6), 2).consistent  # at the best pixel
    empty = sense_check(SenseTally((3, 1)), 0)
    assert empty.n_pushes == 0 and empty.p_value == 1.0 and empty.consistent


# -- stop_index ------------------------------------------------------------------------------


def test_stop_index_is_the_first_state_the_rule_stops_at():
    rule = comcore.StopRule(max_pushes=4, min_pushes=2)
    radii = [50.0, 10.0, 2.0, 1.0, 0.5]  # below 6 mm (2.4 px) from the third state on
    states = [_state(r, n_pushes=k) for k, r in enumerate(radii)]
    assert stop_index(rule, states, RESOLUTION) == 2
    assert rule.stop_index(states, RESOLUTION) == 2
    # with a higher bar it runs to the budget; with none, to the end of the record
    assert stop_index(comcore.StopRule(max_pushes=4, min_pushes=3), states, RESOLUTION) == 3
    strict = comcore.StopRule(max_pushes=10, target_radius=0.0005)
    assert stop_index(strict, states, RESOLUTION) == len(states) - 1
    assert stop_index(strict, iter(states[:1]), RESOLUTION) == 0  # any iterable


def test_stop_index_needs_the_prior_state():
    with pytest.raises(ValueError, match="states must hold at least the prior's state"):
        stop_index(comcore.StopRule(), [], RESOLUTION)


def test_a_session_stops_where_stop_index_says_its_history_would_have():
    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 6))
    session = comcore.ActiveSession(
        mask, model=None, stop=comcore.StopRule(max_pushes=20, target_radius=0.008), rng=0
    )
    com = np.array([14.0, 18.0])
    while not session.done:
        action = session.next_push()
        c = comcore.geometry.contacts(mask, action)
        s = comcore.vt.predicted_sense(com, c.point[0], c.normal[0], action.direction, 0.3)
        session.observe(motion=comcore.Motion(0.1 * s, 0.0, 0.0), reset=True)
    assert session.status in STATUSES
    assert session.status == "ok"
    history = session.history
    loose = comcore.StopRule(max_pushes=20, target_radius=0.008)
    assert stop_index(loose, history, mask.resolution) == len(history) - 1
    # a rule with a smaller budget would have stopped that run earlier, on its budget
    short = comcore.StopRule(max_pushes=2, target_radius=0.008)
    assert stop_index(short, history, mask.resolution) == min(2, len(history) - 1)


def test_offline_status_is_wide_when_the_region_did_not_reach_the_target():
    # consistent but wide is "wide", the sessions' budget/exhausted/uninformative
    assert offline_status(_state(n_pushes=3), reached=False) == "wide"
    assert offline_status(_state(n_pushes=3), reached=True) == "ok"
    # inconsistent and no evidence come first, whatever the region
    assert offline_status(_inconsistent(n_pushes=3), reached=False) == "inconsistent"
    assert offline_status(_state(n_pushes=3, n_evidence=0), reached=False) == "no_evidence"
    bad = sense_check(_tally(20, 0), 1)
    assert offline_status(_state(n_pushes=20), bad, reached=False) == "inconsistent"


def test_the_stop_rule_and_the_offline_status_share_one_comparison():
    # exactly at the target is "ok" for both; a hair wider is a stop on budget, and "wide"
    from comcore._status import region_reached

    rule = comcore.StopRule(max_pushes=3)
    for radius_px, stop, offline in ((2.4, "ok", "ok"), (2.4 + 1e-9, "budget", "wide")):
        state = _state(radius_px, n_pushes=3)
        reached = region_reached(radius_px, rule.target_radius, 0.0025)
        assert stop_reason(rule, state, 0.0025) == stop
        assert offline_status(state, reached=reached) == offline
