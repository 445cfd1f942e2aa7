"""Tests of what a session records (comcore/active/_records.py): states, the log, the estimate."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import comcore
from comcore.active._grid import GridPosterior, prior_grid
from comcore.active._likelihood import Evidence, consistency_threshold
from comcore.active._records import PushLog, SessionState

MASK = comcore.Mask(np.pad(np.ones((6, 8), bool), 3))  # 48 pixels, x 3..10, y 3..8
PUSH = comcore.Action(0.0, 5.0, 10.0, 5.0)


def _post():
    pixels, prior = prior_grid(MASK, None)
    return GridPosterior(pixels, prior, [0.3])


def _record(outcome, index=0):
    motion = None if outcome == "failed" else (0.1, 1.0, 0.0)
    return comcore.PushRecord(action=PUSH, motion=motion, outcome=outcome, index=index)


def _evidence(post, favour_x=4.0):
    """A likelihood favouring the pixels left of ``favour_x``, and an excess for each."""
    left = post.pixels[:, 0] < favour_x
    full = np.where(left, 0.0, -2.0)[:, None, None]
    return Evidence(full[None], full), np.where(left, 1.0, 5.0)[:, None, None]


# -- SessionState -----------------------------------------------------------------------------


def test_a_state_is_consistent_up_to_the_threshold_and_always_before_evidence():
    state = SessionState((1.0, 2.0), 3.0, 4.0, -1.0, 1e6)
    assert state.n_pushes == state.n_evidence == 0 and state.expected_gain_bits is None
    assert state.consistent  # no evidence: nothing to contradict
    at = consistency_threshold(3)
    assert state._replace(n_evidence=3, excess_nats=at).consistent
    assert not state._replace(n_evidence=3, excess_nats=at + 1e-9).consistent
    assert state._replace(n_evidence=3, excess_nats=-50.0).consistent


# -- PushLog -------------------------------------------------------------------------------------


def test_the_log_starts_with_the_prior_s_state():
    post = _post()
    log = PushLog(post, credible=0.5)
    assert len(log.history) == 1 and log.records == [] and log.state is log.history[-1]
    prior = log.state
    assert prior.com == pytest.approx(MASK.centroid)
    assert prior.credible_radius_px == pytest.approx(math.sqrt(24 / math.pi))  # half of 48 px
    assert prior.entropy_bits == pytest.approx(math.log2(48))
    assert (prior.n_pushes, prior.n_evidence, prior.excess_nats, prior.log_evidence) == (0, 0, 0.0, 0.0)
    # the state's region is read from the blurred posterior: a blur widens a peaked one
    assert PushLog(_peaked(), 0.5, blur_px=1.0).state.credible_radius_px > PushLog(
        _peaked(), 0.5).state.credible_radius_px  # fmt: skip


def test_failed_pushes_are_recorded_but_not_counted_and_misses_count_without_evidence():
    post = _post()
    log = PushLog(post, 0.9)
    log.add(_record("failed"), post)
    log.add(_record("miss", 1), post)
    assert [r.outcome for r in log.records] == ["failed", "miss"]
    assert [r.outcome for r in log.executed] == ["miss"]
    assert [(s.n_pushes, s.n_evidence) for s in log.history] == [(0, 0), (0, 0), (1, 0)]
    assert log.excess_nats == 0.0 and log.state.consistent
    # neither changed the posterior
    np.testing.assert_allclose(post.marginal, 1 / 48)


def test_a_push_with_evidence_updates_the_posterior_and_records_its_evidence():
    post = _post()
    log = PushLog(post, 0.9)
    loglik, excess = _evidence(post)
    expected = post.predictive(loglik.full)
    log.add(_record("evidence"), post, loglik, excess)
    record = log.records[-1]
    assert record.log_evidence == pytest.approx(expected) and record.outcome == "evidence"
    assert log.log_evidence == pytest.approx(expected)
    assert log.state.n_evidence == log.state.n_pushes == 1
    assert log.excess_nats == 1.0  # the best hypothesis' excess
    assert log.state.com[0] < MASK.centroid[0]  # the mean moved left
    # a second push: the evidence and the excess add up
    loglik2, excess2 = _evidence(post, favour_x=6.0)
    second = post.predictive(loglik2.full)
    log.add(_record("evidence", 1), post, loglik2, excess2)
    assert log.log_evidence == pytest.approx(expected + second)
    assert log.excess_nats == pytest.approx(2.0)
    assert [s.log_evidence for s in log.history] == pytest.approx([0.0, expected, expected + second])


def test_the_expected_gain_is_noted_on_the_latest_state_only():
    post = _post()
    log = PushLog(post, 0.9)
    log.set_gain(0.7)
    log.add(_record("miss"), post)
    log.set_gain(None)
    assert [s.expected_gain_bits for s in log.history] == [0.7, None]


# -- the estimate --------------------------------------------------------------------------------


def _peaked():
    """A Gaussian about (5, 4) over the mask's pixels, jittered so that no two weigh the same."""
    pixels, _ = prior_grid(MASK, None)
    weights = np.exp(-0.5 * ((pixels - [5.0, 4.0]) ** 2).sum(axis=1) / 1.5**2)
    weights *= 1 + 1e-3 * np.random.default_rng(0).random(len(weights))
    return GridPosterior(pixels, weights / weights.sum(), [0.2, 0.6])


def test_the_estimate_is_the_posterior_s_mean_covariance_and_region():
    post = _peaked()
    log = PushLog(post, 0.8)
    log.add(_record("miss", 3), post)
    est = log.estimate(MASK, post, used=[3], status="budget")
    assert est.com == pytest.approx(tuple(post.mean()))
    assert est.com_m == pytest.approx(tuple(MASK.to_metres(post.mean())))
    np.testing.assert_allclose(est.covariance, post.covariance())
    chosen, _ = post.credible(0.8)
    expected = np.zeros(MASK.shape, bool)
    expected[post.pixels[chosen, 1].astype(int), post.pixels[chosen, 0].astype(int)] = True
    np.testing.assert_array_equal(est.region, expected)
    assert est.status == "budget" and not est.ok and est.used == (3,)
    assert est.pushes == tuple(log.records)
    assert est.region_holds((5.0, 4.0)) and not est.region_holds((10.0, 8.0))


def test_an_estimate_read_from_other_weights_has_their_region_and_spread():
    post = _peaked()
    other = np.where(post.pixels[:, 0] >= 9.0, 1.0, 0.0)
    other /= other.sum()
    est = PushLog(post, 0.95).estimate(MASK, post, [], "ok", marginal=other)
    assert est.region[:, 9:].any() and not est.region[:, :9].any()
    np.testing.assert_allclose(est.covariance, post.covariance(other))
    assert est.com == pytest.approx(tuple(post.mean()))  # the estimate is the posterior's mean


# -- credible_level ------------------------------------------------------------------------------


def test_the_credible_level_of_a_point_is_the_mass_more_probable_than_its_pixel():
    post = _peaked()
    est = PushLog(post, 0.9).estimate(MASK, post, [], "ok")
    w = post.marginal
    for i in (0, 7, 20, 47):
        x, y = post.pixels[i]
        assert comcore.credible_level(est, (x + 0.3, y - 0.4)) == pytest.approx(w[w > w[i]].sum())
    assert comcore.credible_level(est, (5.0, 4.0)) == 0.0  # the mode
    assert comcore.credible_level(est, (0.0, 0.0)) == pytest.approx(1.0)  # off the object
    assert comcore.credible_level(est, (-3.0, 4.0)) == 1.0  # outside the image
    assert comcore.credible_level(est, (5.0, 40.0)) == 1.0


def test_points_in_the_region_are_below_its_level():
    post = _peaked()
    est = PushLog(post, 0.6).estimate(MASK, post, [], "ok")
    rows, cols = np.nonzero(est.region)
    levels = [comcore.credible_level(est, (c, r)) for r, c in zip(rows, cols)]
    assert max(levels) < 0.6
    rows, cols = np.nonzero(MASK.data & ~est.region)
    assert min(comcore.credible_level(est, (c, r)) for r, c in zip(rows, cols)) >= 0.6 - 1e-12


def test_credible_level_needs_an_active_estimate():
    bare = comcore.Estimate(com=MASK.centroid, com_m=MASK.centroid_m, region=MASK.data)
    with pytest.raises(ValueError, match="estimate must carry a posterior"):
        comcore.credible_level(bare, (5.0, 5.0))


# -- round trips ---------------------------------------------------------------------------------


def test_records_survive_a_copy_field_by_field():
    record = comcore.PushRecord(
        action=(0, 5, 10, 5), motion=[0.1, 1.0, 0.0], outcome="evidence", index=2,
        planned=(0, 5, 10, 5), camera_motion=(0.1, 1.0, 0.0), residual_px=0.4,
    )  # fmt: skip
    assert isinstance(record.action, comcore.Action) and isinstance(record.motion, comcore.Motion)
    copy = comcore.PushRecord(**{f.name: getattr(record, f.name) for f in dataclasses.fields(record)})
    assert copy == record and dataclasses.replace(record) == record


def test_a_session_s_records_replay_its_posterior_through_estimate_posterior():
    """Without resets, with a failed push and a miss: the records are in the first mask's frame."""
    mask = comcore.Mask(np.pad(np.ones((20, 24), bool), 10))
    session = comcore.ActiveSession(mask, model=None, stop=comcore.StopRule(max_pushes=5), rng=2)
    com = np.array([20.0, 18.0])
    k = 0
    while not session.done:
        action = session.next_push()
        if k == 1:
            session.observe(failed=True)
        elif k == 3:
            session.observe(motion=(0.0, 0.0, 0.0))  # a miss
        else:
            d = comcore.geometry.signed_line_distance([com], [tuple(action)])[0, 0]
            session.observe(motion=(0.08 * np.sign(d), 1.5, -1.0))
        k += 1
    est = session.estimate()
    assert [p.outcome for p in est.pushes].count("failed") == 1
    assert [p.outcome for p in est.pushes].count("miss") == 1
    replay = comcore.estimate_posterior(
        mask, pushes=est.pushes, model=None, bootstrap=0,
        likelihood=comcore.Likelihood(systematic_error=0.0),
    )  # fmt: skip
    assert replay.com == pytest.approx(est.com, abs=1e-9)
    np.testing.assert_array_equal(replay.region, est.region)
    np.testing.assert_allclose(replay.covariance, est.covariance, atol=1e-9)
    assert [p.outcome for p in replay.pushes] == [p.outcome for p in est.pushes if p.outcome != "failed"]
