"""Tests of comcore.estimate_posterior (comcore/active/_blocking.py): the offline active posterior."""

from __future__ import annotations

import numpy as np
import pytest

import comcore
from tests.active.test_blocking import ToyModel, _ell, _plate, _robot
from tests.records import actions_of, motions_of, outcomes_of


@pytest.mark.parametrize("model", [None, ToyModel()])
def test_it_is_the_active_posterior_of_the_same_pushes(model):
    mask = _ell()
    active = comcore.estimate_active(mask, _robot(mask, (30.0, 24.0), 0.4), model=model, rng=3)
    session_floor = comcore.Likelihood(systematic_error=comcore.active.SESSION_SYSTEMATIC_ERROR)
    offline = comcore.estimate_posterior(
        mask, actions_of(active), motions_of(active), model=model, likelihood=session_floor,
        bootstrap=0,
    )  # fmt: skip
    # the same region, the same meaning: the session's "ok", or "wide" where it stopped on
    # its budget with a region wider than the target (the Voting Theorem alone here)
    assert offline.status == {"ok": "ok", "budget": "wide"}[active.status]
    assert offline.used == tuple(range(len(active.used)))
    np.testing.assert_allclose(offline.posterior.image, active.posterior.image, atol=1e-12)
    np.testing.assert_array_equal(offline.region, active.region)
    assert offline.com == pytest.approx(active.com, abs=1e-9)
    # by default the offline posterior's region is the bagged posterior's, blurred by the
    # recordings' floor: the same posterior and estimate, a wider region
    default = comcore.estimate_posterior(mask, actions_of(active), motions_of(active), model=model)
    np.testing.assert_allclose(default.posterior.image, active.posterior.image, atol=1e-12)
    assert default.com == pytest.approx(active.com, abs=1e-9)
    assert default.region.sum() > active.region.sum()


def test_the_order_of_the_pushes_does_not_matter():
    # the Voting Theorem alone (the toy robot has no physics); with a model the powers on
    # its likelihood are learned push by push, so the order matters there
    mask = _plate()
    push = _robot(mask, (20.0, 15.0), 0.3)
    actions = comcore.sample_pushes(mask, 6, rng=1)
    motions = [push(comcore.Action(*a)) for a in actions]
    one = comcore.estimate_posterior(mask, actions, motions, model=None)
    other = comcore.estimate_posterior(mask, actions[::-1], motions[::-1], model=None)
    np.testing.assert_allclose(one.posterior.image, other.posterior.image, atol=1e-12)


def test_a_push_that_did_not_move_the_object_carries_no_evidence():
    mask = _plate()
    push = _robot(mask, (20.0, 15.0), 0.3)
    actions = comcore.sample_pushes(mask, 3, rng=2)
    motions = [tuple(push(comcore.Action(*a))) for a in actions]
    with_miss = comcore.estimate_posterior(mask, actions, [motions[0], (0.0, 0.0, 0.0), motions[2]])
    without = comcore.estimate_posterior(mask, actions[[0, 2]], [motions[0], motions[2]])
    assert outcomes_of(with_miss) == ("evidence", "miss", "evidence")
    assert with_miss.used == (0, 2)
    np.testing.assert_allclose(with_miss.posterior.image, without.posterior.image)
    only_misses = comcore.estimate_posterior(mask, actions[:1], [(0.0, 0.0, 0.0)])
    assert only_misses.status == "no_evidence" and only_misses.com == pytest.approx(mask.centroid)


_ONE = ([(0, 20, 20, 20)], [(0.1, 0, 0)])


@pytest.mark.parametrize(
    ("args", "kwargs", "error", "match"),
    [
        (([(0, 0, 0, 1)], [(0.1, 0, 0)]), {}, ValueError, "actions must start outside the object and touch it"),
        (([(0, 20, 20, 20)], [(0.1, 0, 0)] * 2), {}, ValueError, "motions"),
        (_ONE, {"max_pushes": 3}, TypeError, "unexpected keyword argument 'max_pushes'"),
        (_ONE, {"min_pushes": 1}, TypeError, "unexpected keyword argument 'min_pushes'"),
        (_ONE, {"flip_prob": 0.1}, TypeError, "unexpected keyword argument 'flip_prob'"),
        (([], []), {}, ValueError, "actions"),
        (_ONE, {"rotation_observed": [True, False]}, ValueError, r"rotation_observed .* \(1\)"),
        (_ONE, {"rotation_observed": [1]}, TypeError, "rotation_observed must hold bools"),
        (_ONE, {"residual_px": ["a"]}, TypeError, "residual_px must hold numbers"),
        (_ONE, {"residual_px": [-1.0]}, ValueError, "residual_px must be >= 0"),
        (_ONE, {"residual_px": 0.3}, ValueError, "residual_px must hold one value per push"),
        (_ONE, {"stop": comcore.StopRule(target_radius=0.01)}, TypeError,
         "unexpected keyword argument 'stop'"),
        (_ONE, {"target_radius": -0.01}, ValueError, "target_radius"),
        (_ONE, {"target_radius": "1 cm"}, TypeError, "target_radius"),
        (_ONE, {"likelihood": {"flip_prob": 0.1}}, TypeError,
         "likelihood must be a comcore.Likelihood or None, got dict"),
    ],
)
def test_bad_arguments_are_named(args, kwargs, error, match):
    with pytest.raises(error, match=match):
        comcore.estimate_posterior(_plate(), *args, **kwargs)


def test_ok_needs_the_credible_region_within_the_target_radius():
    # The docstring's four pushes: consistent, a 90 % region of radius 9 px = 22.5 mm. "ok"
    # used to say only "consistent"; it now says the region reached target_radius (6 mm, the
    # sessions' StopRule default), as a session's "ok" does.
    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
    motions = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)]
    est = comcore.estimate_posterior(mask, actions, motions, model=None)
    radius_m = est.posterior.credible_radius_px * mask.resolution
    assert est.status == "wide" and not est.ok and radius_m > comcore.StopRule().target_radius
    at = comcore.estimate_posterior(mask, actions, motions, model=None,
                                   target_radius=radius_m)
    assert at.status == "ok" and at.ok and at.com == est.com  # at most the target: "ok"
    below = comcore.estimate_posterior(
        mask, actions, motions, model=None, target_radius=radius_m * 0.999
    )
    assert below.status == "wide"
    # the same answer when the pushes contradict each other, whatever the target
    liar = comcore.estimate_posterior(
        mask, [(0, 8, 30, 8), (0, 18, 30, 18)] * 5, [(0.2, 3, 0), (-0.2, 3, 0)] * 5,
        model=None, target_radius=0.5,
    )  # fmt: skip
    assert liar.status == "inconsistent"


def test_pushes_no_com_explains_are_inconsistent():
    mask = _ell()
    actions = comcore.sample_pushes(mask, 5, rng=0)
    honest = [_robot(mask, (30.0, 24.0), 0.4)(comcore.Action(*a)) for a in actions]
    kwargs = {"model": ToyModel()}
    # consistent; five pushes leave a region (13 mm) wider than the 6 mm target
    assert comcore.estimate_posterior(mask, actions, honest, **kwargs).status == "wide"
    liar = [(0.1, 0.0, 0.0)] * 5
    est = comcore.estimate_posterior(mask, actions, liar, **kwargs)
    assert est.status == "inconsistent" and est.posterior.excess_nats > 30


# -- learned tempering (model_weight as a set of powers) --------------------------------


def _toy_tempered(powers):
    from comcore.active._grid import GridPosterior

    pixels = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    return GridPosterior(pixels, [1 / 3] * 3, [0.3], n_tempers=len(powers))


def test_tempered_posterior_is_the_prequential_mixture_of_its_members():
    powers = np.array([0.25, 1.0])
    post = _toy_tempered(powers)
    pushes = [np.log([0.7, 0.2, 0.1]), np.log([0.1, 0.3, 0.6]), np.log([0.6, 0.3, 0.1])]
    members = np.tile(np.log(np.full(3, 1 / 3)), (2, 1))
    scores = np.zeros(2)
    for full in pushes:
        full3 = full[:, None, None]
        evidence = post.update(powers[:, None, None, None] * full3, full3)
        member_w = np.exp(members)
        predictive = np.log(member_w @ np.exp(full))
        mix_before = np.exp(scores - scores.max()) / np.exp(scores - scores.max()).sum()
        assert evidence == pytest.approx(np.log(mix_before @ np.exp(predictive)))
        scores = scores + predictive
        members = members + powers[:, None] * full
        members -= np.log(np.exp(members).sum(axis=1, keepdims=True))
    mix = np.exp(scores) / np.exp(scores).sum()
    np.testing.assert_allclose(post.temper_weights, mix)
    np.testing.assert_allclose(post.marginal, mix @ np.exp(members))
    assert post.marginal.sum() == pytest.approx(1.0)


def test_tempering_favours_the_power_that_predicts_the_next_push():
    # Pushes that contradict each other: the flat power predicts each next one better.
    post = _toy_tempered([0.2, 1.0])
    for full in (np.log([0.98, 0.01, 0.01]), np.log([0.01, 0.01, 0.98])) * 3:
        post.update(np.stack([0.2 * full, full])[:, :, None, None], full[:, None, None])
    assert post.temper_weights[0] > 0.9
    # Pushes that agree: the untempered power wins (once both members hold the same
    # pixel they predict alike, so its lead stops growing).
    post = _toy_tempered([0.2, 1.0])
    for full in (np.log([0.9, 0.05, 0.05]),) * 6:
        post.update(np.stack([0.2 * full, full])[:, :, None, None], full[:, None, None])
    assert post.temper_weights[1] > 0.8


def test_a_tempered_posterior_needs_the_untempered_likelihood():
    post = _toy_tempered([0.5, 1.0])
    with pytest.raises(ValueError, match="untempered"):
        post.update(np.zeros((2, 3, 1, 1)))


def test_an_unobserved_rotation_and_a_registration_residual_tell_less():
    """The replay options of a session's pushes: each widens the posterior, as in the session."""
    mask = _ell()
    actions = comcore.sample_pushes(mask, 3, rng=0)
    motions = [_robot(mask, (30.0, 24.0), 0.4)(comcore.Action(*a)) for a in actions]
    kwargs = {"model": ToyModel(), "likelihood": comcore.Likelihood(model_weight=1.0)}
    plain = comcore.estimate_posterior(mask, actions, motions, **kwargs)
    assert [p.rotation_observed for p in plain.pushes] == [True] * 3
    assert [p.residual_px for p in plain.pushes] == [None] * 3  # not measured: no NaN
    unseen = comcore.estimate_posterior(
        mask, actions, motions, rotation_observed=[True, False, True], **kwargs
    )
    assert [p.rotation_observed for p in unseen.pushes] == [True, False, True]
    blurred = comcore.estimate_posterior(mask, actions, motions, residual_px=[3.0] * 3, **kwargs)
    assert [p.residual_px for p in blurred.pushes] == [3.0] * 3
    for wider in (unseen, blurred):
        assert wider.posterior.credible_radius_px > plain.posterior.credible_radius_px
        # the records carry the readings: a replay of them is the same posterior
        again = comcore.estimate_posterior(mask, pushes=wider.pushes, **kwargs)
        np.testing.assert_array_equal(again.posterior.image, wider.posterior.image)


# -- an error that more pushes do not average away -------------------------------------------


def test_systematic_error_widens_the_region_and_leaves_the_posterior_as_it_is():
    mask = comcore.Mask(np.pad(np.ones((30, 40), bool), 6), resolution=0.0025)
    actions = comcore.sample_pushes(mask, 12, cone=0.3, rng=1)
    com = (24.0, 19.0)
    motions = [(0.05 * np.sign(d), 0.0, 0.0) for d in comcore.geometry.signed_line_distance([com], actions)[0]]
    none = comcore.Likelihood(systematic_error=0.0)
    # the floor alone, on the posterior's own region (bootstrap=0: not bagged)
    plain = comcore.estimate_posterior(
        mask, actions, motions, model=None, likelihood=none, bootstrap=0
    )
    floored = comcore.estimate_posterior(
        mask, actions, motions, model=None,
        likelihood=comcore.Likelihood(systematic_error=0.005), bootstrap=0,
    )  # fmt: skip
    np.testing.assert_array_equal(plain.posterior.image, floored.posterior.image)
    assert plain.com == floored.com
    assert floored.region.sum() > plain.region.sum()
    assert (floored.region | ~plain.region).all()  # it grows around the plain region
    radii = [e.posterior.credible_radius_px for e in (plain, floored)]
    # a 2 px (5 mm) blur adds about its 90 % radius (2.15 std) in quadrature, give or take a pixel
    assert radii[1] > np.hypot(radii[0], 2.15 * 2.0) - 1.0
    assert not floored.region[~mask.data].any()  # only the object's pixels


def test_none_is_each_estimators_own_floor_recordings_1_5_mm_sessions_0():
    assert comcore.Likelihood().systematic_error is None
    assert comcore.active.RECORDED_SYSTEMATIC_ERROR == 0.0015 and comcore.active.SESSION_SYSTEMATIC_ERROR == 0.0
    mask = comcore.Mask(np.pad(np.ones((30, 40), bool), 6), resolution=0.0025)
    actions = comcore.sample_pushes(mask, 12, cone=0.3, rng=1)
    d = comcore.geometry.signed_line_distance([(24.0, 19.0)], actions)[0]
    motions = [(0.05 * np.sign(v), 0.0, 0.0) for v in d]

    def region(systematic_error):
        likelihood = comcore.Likelihood(systematic_error=systematic_error)
        return comcore.estimate_posterior(
            mask, actions, motions, model=None, likelihood=likelihood
        ).region

    np.testing.assert_array_equal(region(None), region(comcore.active.RECORDED_SYSTEMATIC_ERROR))
    assert region(None).sum() > region(0.0).sum()
    # the session's floor is 0: its region is the unblurred posterior's
    session = comcore.ActiveSession(mask, model=None, candidates=actions, rng=0)
    assert session._scoring.systematic_px == 0.0


def test_systematic_error_is_in_metres_and_checked():
    with pytest.raises(ValueError, match=r"systematic_error 2 m is implausible .* millimetres"):
        comcore.Likelihood(systematic_error=2.0)
    with pytest.raises(ValueError, match="systematic_error"):
        comcore.Likelihood(systematic_error=-0.001)


def test_the_benchmarks_replay_scores_a_sessions_pushes_with_the_sessions_floor():
    """benchmarks/calibration/replay.py (the stop-rule and power tuning scripts) replays a session exactly."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "calibration" / "replay.py"
    spec = importlib.util.spec_from_file_location("bench_replay", path)
    replay = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(replay)
    mask = _ell()
    active = comcore.estimate_active(mask, _robot(mask, (30.0, 24.0), 0.4), model=None, rng=3)
    kept = replay.kept_pushes(active, mask, (30.0, 24.0))
    again = replay.replay(kept, replay.posterior_options({"model": None}))
    np.testing.assert_array_equal(again.region, active.region)
    assert again.posterior.credible_radius_px == active.posterior.credible_radius_px
