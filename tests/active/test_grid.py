"""Tests of the grid posterior (comcore/active/_grid.py): prior, update, marginals, regions."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import comcore
from comcore.active._grid import GridPosterior, prior_grid


def _small_mask():
    return comcore.Mask(np.pad(np.ones((6, 8), bool), 3))


def _line(n=5):
    """``n`` pixels along x at y = 0."""
    return np.column_stack([np.arange(n, dtype=float), np.zeros(n)])


# -- the prior ---------------------------------------------------------------------------


def test_the_default_prior_is_uniform_over_the_mask_pixels():
    mask = _small_mask()
    pixels, weights = prior_grid(mask, None)
    np.testing.assert_array_equal(pixels, mask.pixels)
    assert len(pixels) == mask.area_px == 48
    np.testing.assert_allclose(weights, 1 / 48)
    # every hypothesis lies on the object
    cols, rows = pixels[:, 0].astype(int), pixels[:, 1].astype(int)
    assert mask.data[rows, cols].all()


def test_a_given_prior_keeps_its_positive_pixels_normalised_on_or_off_the_object():
    mask = _small_mask()
    prior = np.zeros(mask.shape)
    prior[4, 5], prior[0, 0], prior[7, 9] = 3.0, 1.0, 0.0  # (0, 0) is off the object
    pixels, weights = prior_grid(mask, prior)
    assert sorted(map(tuple, pixels.tolist())) == [(0.0, 0.0), (5.0, 4.0)]  # (x, y)
    by_pixel = dict(zip(map(tuple, pixels.tolist()), weights))
    assert by_pixel[(5.0, 4.0)] == pytest.approx(0.75) and by_pixel[(0.0, 0.0)] == pytest.approx(0.25)


@pytest.mark.parametrize(
    ("prior", "error", "match"),
    [
        (np.ones((3, 3)), ValueError, r"prior must have the mask's shape \(12, 14\), got \(3, 3\)"),
        ("uniform", TypeError, r"prior must be an array_like of numbers of shape \(12, 14\)"),
        ([[object()]], TypeError, "prior must be an array_like"),
        (np.zeros((12, 14)), ValueError, "prior must be finite, non-negative and not all zero"),
        (np.full((12, 14), -1.0), ValueError, "prior must be finite, non-negative"),
        (np.full((12, 14), np.nan), ValueError, "prior must be finite"),
        (np.full((12, 14), np.inf), ValueError, "prior must be finite"),
    ],
)
def test_a_bad_prior_is_named(prior, error, match):
    with pytest.raises(error, match=match):
        prior_grid(_small_mask(), prior)


# -- weights and marginals -----------------------------------------------------------------


def test_the_joint_starts_at_the_prior_times_the_friction_prior():
    post = GridPosterior(_line(3), [0.5, 0.3, 0.2], [0.1, 0.5], n_models=2, n_scales=3,
                         mu_weights=[0.25, 0.75])  # fmt: skip
    assert post.log_w.shape == (3, 2, 6)
    np.testing.assert_allclose(post.marginal, [0.5, 0.3, 0.2])
    np.testing.assert_allclose(post.mu_marginal, [0.25, 0.75])
    np.testing.assert_allclose(post.model_marginal, [0.5, 0.5])
    np.testing.assert_allclose(post.scale_marginal, [1 / 3] * 3)
    np.testing.assert_allclose(post.sense_weights, np.outer([0.5, 0.3, 0.2], [0.25, 0.75]))


@settings(max_examples=40)
@given(
    loglik=hnp.arrays(float, (3, 4, 2, 6), elements=st.floats(-40, 40)),
    n_updates=st.integers(1, 3),
)
def test_weights_and_every_marginal_sum_to_one_after_updates(loglik, n_updates):
    post = GridPosterior(_line(4), [0.1, 0.2, 0.3, 0.4], [0.2, 0.6], n_models=2, n_scales=3)
    for i in range(n_updates):
        post.update(loglik[i])
    for w in (post.weights, post.marginal, post.mu_marginal, post.model_marginal,
              post.scale_marginal, post.sense_weights):  # fmt: skip
        assert w.sum() == pytest.approx(1.0) and (w >= 0).all()


def test_the_model_axis_is_model_major():
    """k = model x scale: a likelihood favouring entry 4 of 2 x 3 is model 1 at scale 1."""
    post = GridPosterior(_line(2), [0.5, 0.5], [0.3], n_models=2, n_scales=3)
    loglik = np.zeros((2, 1, 6))
    loglik[:, :, 4] = 10.0
    post.update(loglik)
    assert np.argmax(post.model_marginal) == 1 and np.argmax(post.scale_marginal) == 1
    assert post.model_marginal[1] > 0.99 and post.scale_marginal[1] > 0.99


def test_update_multiplies_the_likelihood_in_and_returns_its_evidence():
    prior = np.array([0.5, 0.25, 0.25])
    post = GridPosterior(_line(3), prior, [0.3])
    lik = np.array([0.2, 0.4, 0.0])
    with np.errstate(divide="ignore"):
        evidence = post.update(np.log(lik)[:, None, None])
    assert evidence == pytest.approx(np.log(prior @ lik))
    np.testing.assert_allclose(post.marginal, prior * lik / (prior @ lik))
    assert post.marginal[2] == 0.0  # ruled out, and stays out
    post.update(np.full((3, 1, 1), 5.0))  # a likelihood flat over the grid changes nothing
    np.testing.assert_allclose(post.marginal, prior * lik / (prior @ lik))


@settings(max_examples=30)
@given(
    loglik=hnp.arrays(float, (4, 5, 3, 1), elements=st.floats(-30, 30)),
    order=st.permutations(range(4)),
)
def test_the_order_of_the_updates_does_not_matter(loglik, order):
    one = GridPosterior(_line(5), np.full(5, 0.2), [0.2, 0.5, 0.9])
    other = GridPosterior(_line(5), np.full(5, 0.2), [0.2, 0.5, 0.9])
    total_one = sum(one.update(loglik[i]) for i in range(4))
    total_other = sum(other.update(loglik[i]) for i in order)
    np.testing.assert_allclose(one.weights, other.weights, atol=1e-12)
    # the summed log evidence is the log marginal likelihood of all of them, in any order
    assert total_one == pytest.approx(total_other, abs=1e-9)


def test_predictive_is_the_evidence_update_would_return_and_changes_nothing():
    post = GridPosterior(_line(3), [0.2, 0.3, 0.5], [0.3, 0.6])
    full = np.log(np.array([[0.9, 0.1], [0.5, 0.5], [0.1, 0.2]]))[:, :, None]
    before = post.weights.copy()
    predicted = post.predictive(full)
    np.testing.assert_array_equal(post.weights, before)
    assert post.update(full) == pytest.approx(predicted)


def test_temper_weights_start_equal_and_sum_to_one():
    post = GridPosterior(_line(3), [1 / 3] * 3, [0.3], n_tempers=4)
    np.testing.assert_allclose(post.temper_weights, 0.25)
    full = np.log([0.7, 0.2, 0.1])[:, None, None]
    post.update(np.stack([p * full for p in (0.25, 0.4, 0.6, 1.0)]), full)
    assert post.temper_weights.sum() == pytest.approx(1.0)


# -- mean, covariance, entropy ---------------------------------------------------------------


def test_mean_and_covariance_of_a_known_distribution():
    pixels = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 2.0], [4.0, 2.0]])
    post = GridPosterior(pixels, [0.25] * 4, [0.3])
    np.testing.assert_allclose(post.mean(), [2.0, 1.0])
    # variance 4 in x, 1 in y, uncorrelated, plus 1/12 px^2 within a pixel
    np.testing.assert_allclose(post.covariance(), np.diag([4.0, 1.0]) + np.eye(2) / 12)
    # correlated: two pixels on the diagonal
    diag = GridPosterior(np.array([[0.0, 0.0], [2.0, 2.0]]), [0.5, 0.5], [0.3])
    np.testing.assert_allclose(diag.covariance(), np.ones((2, 2)) + np.eye(2) / 12)
    # one pixel: the spread within it alone
    one = GridPosterior(np.array([[3.0, 7.0]]), [1.0], [0.3])
    np.testing.assert_allclose(one.mean(), [3.0, 7.0])
    np.testing.assert_allclose(one.covariance(), np.eye(2) / 12)


def test_covariance_with_other_weights_is_their_spread_about_the_posterior_mean():
    post = GridPosterior(_line(3), [1e-300, 1.0, 1e-300], [0.3])  # mean at x = 1
    spread = post.covariance(np.array([0.5, 0.0, 0.5]))  # half at x = 0, half at x = 2
    np.testing.assert_allclose(spread, np.diag([1.0, 0.0]) + np.eye(2) / 12, atol=1e-12)


def test_entropy_in_bits():
    assert GridPosterior(_line(8), [1 / 8] * 8, [0.3]).entropy_bits() == pytest.approx(3.0)
    assert GridPosterior(_line(2), [1.0, 1e-300], [0.3]).entropy_bits() == pytest.approx(0.0)
    # friction does not count: the CoM pixels' entropy alone
    assert GridPosterior(_line(4), [0.25] * 4, [0.1, 0.5, 0.9]).entropy_bits() == pytest.approx(2.0)


# -- credible regions ------------------------------------------------------------------------


def test_the_credible_region_takes_the_most_probable_pixels_first():
    post = GridPosterior(_line(5), [0.05, 0.4, 0.1, 0.3, 0.15], [0.3])
    chosen, area = post.credible(0.7)
    assert chosen.tolist() == [False, True, False, True, False]
    assert area == pytest.approx(2.0)  # 0.4 + 0.3 is exactly 0.7: the second pixel wholly
    chosen, area = post.credible(1.0)
    assert chosen.all() and area == pytest.approx(5.0)
    chosen, area = post.credible(0.2)  # half of the most probable pixel's mass
    assert chosen.sum() == 1 and area == pytest.approx(0.5)


@settings(max_examples=40)
@given(
    weights=hnp.arrays(float, 12, elements=st.floats(1e-6, 1.0)),
    levels=st.tuples(st.floats(0.01, 0.99), st.floats(0.01, 0.99)),
)
def test_a_higher_level_never_gives_a_smaller_region(weights, levels):
    pixels = np.column_stack([np.arange(12.0) % 4, np.arange(12.0) // 4])
    post = GridPosterior(pixels, weights / weights.sum(), [0.3])
    low, high = sorted(levels)
    (in_low, area_low), (in_high, area_high) = post.credible(low), post.credible(high)
    assert area_low <= area_high + 1e-12
    assert not (in_low & ~in_high).any()  # nested
    assert post.marginal[in_low].sum() >= low - 1e-9  # holds at least the level
    assert in_low.sum() - 1 <= area_low <= in_low.sum() + 1e-12


def test_the_region_weights_are_the_marginal_or_its_blur():
    mask = _small_mask()
    pixels, _ = prior_grid(mask, None)
    point = np.zeros(len(pixels))
    centre = int(np.argmin(((pixels - [7.0, 5.0]) ** 2).sum(axis=1)))
    point[centre] = 1.0
    post = GridPosterior(pixels, np.where(point > 0, 1.0, 1e-300), [0.3])
    np.testing.assert_array_equal(post.region_weights(), post.marginal)
    np.testing.assert_array_equal(post.region_weights(blur_px=0.0), post.marginal)
    blurred = post.region_weights(blur_px=1.0)
    assert blurred.sum() == pytest.approx(1.0) and (blurred >= 0).all()
    assert np.argmax(blurred) == centre and blurred[centre] < 0.5  # spread to its neighbours
    # a wider blur, a wider region
    areas = [post.credible(0.9, blur_px=b)[1] for b in (0.0, 0.5, 1.0, 2.0)]
    assert areas[0] < 1.0 and np.all(np.diff(areas) > 0)
    # isotropic: the four neighbours of the point get the same weight
    offsets = pixels - pixels[centre]
    near = [int(np.flatnonzero((offsets == d).all(axis=1))[0]) for d in ([1, 0], [-1, 0], [0, 1], [0, -1])]
    np.testing.assert_allclose(blurred[near], blurred[near[0]], rtol=1e-9)
    assert blurred[near[0]] > 0.05


def test_the_region_can_be_read_from_other_weights_over_the_same_pixels():
    post = GridPosterior(_line(4), [0.7, 0.1, 0.1, 0.1], [0.3])
    other = np.array([0.0, 0.0, 0.2, 0.8])
    chosen, area = post.credible(0.75, marginal=other)
    assert chosen.tolist() == [False, False, False, True] and area == pytest.approx(0.75 / 0.8)
    np.testing.assert_array_equal(post.region_weights(marginal=other), other)
