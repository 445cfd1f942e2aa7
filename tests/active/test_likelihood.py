"""Tests of one push's likelihood (comcore/active/_likelihood.py): senses, model, noise."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import comcore
from comcore.active._grid import GridPosterior, prior_grid
from comcore.active._likelihood import (
    LINE_BLUR_M,
    PushMemo,
    Scoring,
    check_models,
    consistency_threshold,
    gyration_px,
    push_evidence,
    push_log_likelihood,
    sense_flip_prob,
    tracking_noise,
)
from comcore.active._options import DEFAULT_MODEL
from comcore.geometry._disc_contacts import pusher_contacts
from comcore.vt._voting import LINE_SCALE_PX, push_force_lines
from tests.active.test_blocking import ToyModel  # the Voting Theorem's sense, |theta| by lever

#: A 20 x 20 plate, 6 px margin: object pixels 6..25, centroid (15.5, 15.5).
PLATE = comcore.Mask(np.pad(np.ones((20, 20), bool), 6))
#: A push from the left along the plate's axis of symmetry y = 15.5 (along the normal).
PUSH = np.array([0.0, 15.5, 30.0, 15.5])


def _setup(likelihood=None, models=(), mask=PLATE, actions=(PUSH,)):
    likelihood = likelihood or comcore.Likelihood()
    scoring = Scoring.build(likelihood, mask, tuple(models))
    pixels, prior = prior_grid(mask, None)
    post = scoring.posterior(pixels, prior)
    acts = np.array(actions, dtype=float)
    lines = push_force_lines(pusher_contacts(mask, acts, 0.0), acts, scoring.mus)
    return scoring, post, lines


def _true_motion(com, action=PUSH, mu=0.4):
    return ToyModel().predict_hypotheses(PLATE, [action], [com], mu)[0, 0]


def _index(post, xy):
    return int(np.flatnonzero((post.pixels == xy).all(axis=1))[0])


# -- the Voting Theorem's term ---------------------------------------------------------------


@settings(max_examples=100)
@given(
    d=st.floats(0.01, 100.0),
    theta=st.floats(0.02, 1.0),
    sign=st.sampled_from([-1, 1]),
    flip_prob=st.floats(1e-4, 0.45),
    scale=st.floats(0.2, 5.0),
)
def test_the_side_the_sense_says_scores_higher_than_its_mirror(d, theta, sign, flip_prob, scale):
    distances = np.array([[[d]], [[-d]]])
    ll = push_log_likelihood(distances, (sign * theta, 0.0, 0.0), flip_prob, 1e-3, scale=scale)
    same, mirrored = (ll[0, 0, 0], ll[1, 0, 0]) if sign > 0 else (ll[1, 0, 0], ll[0, 0, 0])
    assert same > mirrored
    # a wrong sense has probability flip_prob at worst: the likelihood is in [f, 1 - f]
    p = np.exp(ll)
    assert (p >= flip_prob * (1 - 1e-9)).all() and (p <= (1 - flip_prob) * (1 + 1e-9)).all()
    # mirroring both the hypothesis and the sense changes nothing
    flipped = push_log_likelihood(-distances, (-sign * theta, 0.0, 0.0), flip_prob, 1e-3, scale=scale)
    np.testing.assert_allclose(flipped, ll, rtol=1e-12)


def test_a_rotation_within_theta_tol_carries_no_sense():
    distances = np.linspace(-10, 10, 7).reshape(7, 1, 1)
    ll = push_log_likelihood(distances, (0.01, 0.0, 0.0), 0.05, theta_tol=0.01)
    np.testing.assert_allclose(ll, 0.0, atol=1e-15)
    assert np.ptp(push_log_likelihood(distances, (0.011, 0.0, 0.0), 0.05, theta_tol=0.01)) > 1.0


def test_a_softer_line_tells_less_near_it():
    distances = np.array([[[1.0]], [[-1.0]]])
    sharp = push_log_likelihood(distances, (0.1, 0, 0), 0.05, 1e-3, scale=0.5)
    soft = push_log_likelihood(distances, (0.1, 0, 0), 0.05, 1e-3, scale=LINE_SCALE_PX * 3)
    assert sharp[0] - sharp[1] > soft[0] - soft[1] > 0


def test_the_model_s_term_adds_when_it_is_the_same_for_either_sense():
    rng = np.random.default_rng(0)
    distances = rng.normal(size=(5, 2, 1)) * 4
    term = rng.normal(size=(5, 2, 3))
    alone = push_log_likelihood(distances, (0.1, 0, 0), 0.05, 1e-3)
    both = push_log_likelihood(distances, (0.1, 0, 0), 0.05, 1e-3, model_term=term, flipped_term=term)
    assert both.shape == (5, 2, 3)
    np.testing.assert_allclose(both, alone + term, atol=1e-12)
    # a model that explains the flipped sense far better makes a flip the likely reading
    worse = push_log_likelihood(
        distances, (0.1, 0, 0), 0.05, 1e-3, model_term=term - 50, flipped_term=term
    )
    flipped = push_log_likelihood(-distances, (0.1, 0, 0), 1e-300, 1e-3)
    np.testing.assert_allclose(worse, np.log(0.05) + flipped + term, atol=1e-9)


# -- push_evidence: shapes, senses and the model ------------------------------------------


def test_evidence_shapes_with_and_without_a_model():
    likelihood = comcore.Likelihood(n_mu=3, model_scales=(1.0, 2.0))
    scoring, post, lines = _setup(likelihood)
    p = len(post.pixels)
    ev, excess = push_evidence(post, scoring, PLATE, PUSH, lines[0], (0.1, 5.0, 0.0))
    assert ev.full.shape == excess.shape == (p, 3, 1)  # no model: one hypothesis column
    assert ev.tempered.shape == (1, p, 3, 1)
    scoring, post, lines = _setup(likelihood, [ToyModel()])
    ev, excess = push_evidence(post, scoring, PLATE, PUSH, lines[0], (0.1, 5.0, 0.0))
    assert ev.full.shape == excess.shape == post.log_w.shape == (p, 3, 2)
    assert ev.tempered.shape == (4, p, 3, 2)  # one row per power of model_weight
    ones = likelihood.model_weight.index(1.0)
    np.testing.assert_array_equal(ev.tempered[ones], ev.full)
    assert np.isfinite(ev.full).all()


@pytest.mark.parametrize("with_model", [False, True])
@pytest.mark.parametrize("com", [(12.0, 10.0), (20.0, 21.0), (9.0, 24.0)])
def test_the_true_com_scores_higher_than_its_mirror_across_the_push(com, with_model):
    models = [ToyModel()] if with_model else []
    scoring, post, lines = _setup(comcore.Likelihood(mu=0.4), models)
    ev, excess = push_evidence(post, scoring, PLATE, PUSH, lines[0], _true_motion(com))
    mirror = (com[0], 31.0 - com[1])  # across the push line y = 15.5
    i, j = _index(post, com), _index(post, mirror)
    assert ev.full[i].max() > ev.full[j].max() + 1.0
    assert excess[i].min() < excess[j].min()


def test_the_senses_are_a_distribution_and_their_excess_is_zero_on_average():
    """Without a model: P(+ | h) + P(- | h) = 1, and the excess averages 0 under h itself."""
    scoring, post, lines = _setup(comcore.Likelihood(mu=0.4, flip_prob=0.1))
    plus, ex_plus = push_evidence(post, scoring, PLATE, PUSH, lines[0], (0.1, 0.0, 0.0))
    minus, ex_minus = push_evidence(post, scoring, PLATE, PUSH, lines[0], (-0.1, 0.0, 0.0))
    q_plus, q_minus = np.exp(plus.full), np.exp(minus.full)
    np.testing.assert_allclose(q_plus + q_minus, 1.0, atol=1e-12)
    np.testing.assert_allclose(q_plus * ex_plus + q_minus * ex_minus, 0.0, atol=1e-12)
    # the sense a hypothesis makes less likely surprises it more
    assert ((q_plus < q_minus) == (ex_plus > ex_minus)).all()


def test_the_tempered_rows_weaken_the_model_s_term():
    scoring, post, lines = _setup(comcore.Likelihood(mu=0.4), [ToyModel()])
    ev, _ = push_evidence(post, scoring, PLATE, PUSH, lines[0], _true_motion((12.0, 10.0)))
    spread = [np.ptp(row) for row in ev.tempered]  # the powers 0.25, 0.4, 0.6, 1 in order
    assert np.all(np.diff(spread) > 0)


def test_an_unobserved_rotation_scores_neither_its_sense_nor_its_size():
    scoring, post, lines = _setup()
    ev, excess = push_evidence(
        post, scoring, PLATE, PUSH, lines[0], (0.2, 5.0, 0.0), rotation_observed=False
    )
    np.testing.assert_allclose(ev.full, 0.0, atol=1e-15)  # senses alone: no information
    np.testing.assert_allclose(excess, 0.0)
    scoring, post, lines = _setup(comcore.Likelihood(mu=0.4), [ToyModel()])
    one, _ = push_evidence(
        post, scoring, PLATE, PUSH, lines[0], (0.2, 5.0, 0.0), rotation_observed=False
    )
    other, _ = push_evidence(
        post, scoring, PLATE, PUSH, lines[0], (-0.1, 5.0, 0.0), rotation_observed=False
    )
    np.testing.assert_array_equal(one.full, other.full)
    assert np.ptp(one.full) > 0  # the translation still tells something


def test_the_order_of_the_pushes_does_not_matter():
    actions = comcore.sample_pushes(PLATE, 4, cone=0.3, rng=1)
    com = (12.0, 19.0)
    for models, likelihood in (((), comcore.Likelihood()),
                               ((ToyModel(),), comcore.Likelihood(model_weight=1.0, n_mu=2))):  # fmt: skip
        scoring, _, lines = _setup(likelihood, models, actions=actions)
        motions = [
            ToyModel().predict_hypotheses(PLATE, [a], [com], 0.4)[0, 0] for a in actions
        ]
        posteriors = []
        for order in ([0, 1, 2, 3], [3, 1, 0, 2]):
            pixels, prior = prior_grid(PLATE, None)
            post = scoring.posterior(pixels, prior)
            for i in order:
                ev, _ = push_evidence(post, scoring, PLATE, actions[i], lines[i], motions[i])
                post.update(ev.tempered, ev.full)
            posteriors.append(post.weights)
        np.testing.assert_allclose(posteriors[0], posteriors[1], atol=1e-9)


def test_a_rotation_within_the_tracking_noise_tells_less_about_the_side():
    scoring, post, lines = _setup(comcore.Likelihood(motion_noise=(0.02, 0.0005)))
    sure, _ = push_evidence(post, scoring, PLATE, PUSH, lines[0], (0.2, 0.0, 0.0))
    faint, _ = push_evidence(post, scoring, PLATE, PUSH, lines[0], (0.01, 0.0, 0.0))
    exact, _ = push_evidence(post, scoring, PLATE, PUSH, lines[0], (0.01, 0.0, 0.0),
                             tracking=(0.0, 0.0))  # fmt: skip
    assert np.ptp(faint.full) < np.ptp(sure.full)
    np.testing.assert_allclose(exact.full, sure.full)  # without noise only the sense counts


# -- sense_flip_prob ---------------------------------------------------------------------


@settings(max_examples=60)
@given(
    flip_prob=st.floats(1e-6, 0.45),
    theta=st.floats(-0.5, 0.5),
    track=st.floats(1e-4, 0.1),
)
def test_the_flip_probability_rises_towards_one_half_near_zero(flip_prob, theta, track):
    p = sense_flip_prob(flip_prob, theta, track, True)
    assert flip_prob - 1e-15 <= p <= 0.5 + 1e-15
    assert sense_flip_prob(flip_prob, theta / 2, track, True) >= p - 1e-15  # nearer zero: more
    assert sense_flip_prob(flip_prob, theta, track, False) == flip_prob
    assert sense_flip_prob(flip_prob, theta, 0.0, True) == flip_prob


def test_a_rotation_of_zero_is_a_coin_toss():
    assert sense_flip_prob(0.05, 0.0, 0.01, True) == pytest.approx(0.5)
    assert sense_flip_prob(0.05, 1.0, 0.01, True) == pytest.approx(0.05)


# -- the noise and the consistency check -----------------------------------------------------


def test_the_consistency_threshold_is_ten_plus_six_root_n_above_the_simulated_quantiles():
    assert consistency_threshold(4) == pytest.approx(22.0)
    assert consistency_threshold(0) == consistency_threshold(1) == pytest.approx(16.0)
    for n, quantile in ((1, 10.9), (3, 15.4), (8, 22.0)):
        assert consistency_threshold(n) > quantile
    values = [consistency_threshold(n) for n in range(1, 30)]
    assert np.all(np.diff(values) > 0)


def test_the_radius_of_gyration():
    side = 20
    assert gyration_px(PLATE) == pytest.approx(math.sqrt((side**2 - 1) / 6))
    dot = comcore.Mask(np.pad(np.ones((1, 1), bool), 3))
    assert gyration_px(dot) == 0.5  # floored


def test_a_registration_residual_widens_the_tracking_noise_in_quadrature():
    assert tracking_noise((0.01, 0.2), None, 10.0) == (0.01, 0.2)
    assert tracking_noise((0.01, 0.2), float("nan"), 10.0) == (0.01, 0.2)
    theta, px = tracking_noise((0.03, 0.4), 0.3, 7.5)
    assert theta == pytest.approx(math.hypot(0.03, 0.04))
    assert px == pytest.approx(0.5)


# -- Scoring and the models ----------------------------------------------------------------


def test_the_scoring_is_the_likelihood_in_pixels_of_the_mask():
    mask = comcore.Mask(np.pad(np.ones((10, 10), bool), 4), resolution=0.002)
    likelihood = comcore.Likelihood(
        translation_error=(0.002, 0.05), motion_noise=(0.01, 0.001), pusher_error=0.0015, n_mu=3
    )
    s = Scoring.build(likelihood, mask, ())
    assert s.translation_px == pytest.approx((1.0, 0.05))
    assert s.tracking == pytest.approx((0.01, 0.5))
    assert s.pusher_px == pytest.approx(0.75)
    assert s.near_px == pytest.approx(0.0375 / 0.002)
    np.testing.assert_array_equal(s.mus, likelihood.mus)
    assert s.systematic_px == 0.0  # the sessions' floor
    assert Scoring.build(likelihood, mask, (), systematic_floor=0.004).systematic_px == 2.0
    own = comcore.Likelihood(systematic_error=0.001)
    assert Scoring.build(own, mask, (), systematic_floor=0.004).systematic_px == pytest.approx(0.5)


def test_the_force_line_blur_is_1_2_px_at_2_5_mm_per_px_and_scales_with_the_resolution():
    exact = comcore.Likelihood(pusher_error=0.0)
    at = {res: Scoring.build(exact, comcore.Mask(np.ones((4, 4), bool), resolution=res), ())
          for res in (0.0025, 0.00125)}  # fmt: skip
    assert at[0.0025].line_scale_px == pytest.approx(1.2)
    assert at[0.00125].line_scale_px == pytest.approx(2.4)
    # the pusher's error adds in quadrature (standard deviations, metres)
    noisy = Scoring.build(comcore.Likelihood(pusher_error=LINE_BLUR_M), PLATE, ())
    assert noisy.line_scale_px == pytest.approx(1.2 * math.sqrt(2))


def test_without_a_model_there_is_one_temper_and_one_scale():
    likelihood = comcore.Likelihood(model_scales=(1.0, 1.5, 2.0))
    bare = Scoring.build(likelihood, PLATE, ())
    assert (bare.n_tempers, bare.n_scales) == (1, 1)
    modelled = Scoring.build(likelihood, PLATE, (ToyModel(), ToyModel()))
    assert (modelled.n_tempers, modelled.n_scales) == (4, 3)
    post = modelled.posterior(np.zeros((5, 2)), np.full(5, 0.2))
    assert isinstance(post, GridPosterior) and post.log_w.shape == (5, 6, 6)
    assert post.n_tempers == 4


def test_check_models():
    (default,) = check_models(DEFAULT_MODEL, 0.003)
    assert isinstance(default, comcore.LimitSurfaceModel) and default.pusher_radius == 0.003
    assert check_models(None) == ()
    model = ToyModel()
    assert check_models(model) == (model,)
    assert check_models([model, model]) == (model, model)
    with pytest.raises(TypeError, match="model must implement comcore.Predictor .* got str"):
        check_models("limit surface")
    with pytest.raises(TypeError, match="got int"):
        check_models([model, 3])
    with pytest.raises(ValueError, match="model must not be an empty sequence"):
        check_models([])


def test_a_memo_shared_by_a_push_s_readings_changes_no_evidence():
    """The model's predictions are kept for the push's other readings, not its motion."""
    scoring, post, lines = _setup(comcore.Likelihood(mu=0.4), [ToyModel()])
    memo = PushMemo()
    for motion in [_true_motion((12.0, 10.0)), (-0.1, 4.0, 1.0), (0.3, 6.0, -2.0)]:
        fresh, fresh_excess = push_evidence(post, scoring, PLATE, PUSH, lines[0], motion)
        kept, kept_excess = push_evidence(post, scoring, PLATE, PUSH, lines[0], motion, memo=memo)
        np.testing.assert_array_equal(kept.full, fresh.full)
        np.testing.assert_array_equal(kept_excess, fresh_excess)
    assert memo.offset_marginal is not None and len(memo.end_terms) == 6  # 3 readings x 2 senses
    # another posterior (fewer live hypotheses) is not answered from the memo
    import copy

    from comcore.active._likelihood import PRUNE_LOG

    narrowed = copy.deepcopy(post)
    cut = np.where(post.pixels[:, 0] < 15, 0.0, -2 * PRUNE_LOG)[:, None, None]  # left half
    cut = np.broadcast_to(cut, fresh.full.shape)
    narrowed.update(np.broadcast_to(cut, fresh.tempered.shape), cut)
    assert (narrowed.log_w > narrowed.log_w.max() - PRUNE_LOG).sum() < post.log_w.size
    # its memo holds predictions for its live hypotheses only: the wider posterior's
    # others are asked for, not read as missing
    narrow_memo = PushMemo()
    push_evidence(narrowed, scoring, PLATE, PUSH, lines[0], motion, memo=narrow_memo)
    again, _ = push_evidence(post, scoring, PLATE, PUSH, lines[0], motion, memo=narrow_memo)
    np.testing.assert_array_equal(again.full, fresh.full)
