"""Tests of the motion model's term (comcore/active/_motion_term.py): residuals, scales, nodes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

import comcore
from comcore.active._likelihood import Scoring
from comcore.active._motion_term import (
    NEAR_LINE_M,
    STUDENT_DOF,
    ModelNoise,
    com_shift,
    excess_surprise,
    log_likelihood,
    model_error_log_density,
    model_predictions,
    motion_terms,
    offset_marginal,
    pusher_nodes,
    student_t,
    theta_scale,
)

PLATE = comcore.Mask(np.pad(np.ones((20, 20), bool), 6))  # centroid (15.5, 15.5)
NOISE = ModelNoise(theta=(0.01, 0.13), translation_px=(0.4, 0.056), near_px=15.0)


# -- Student-t residuals ---------------------------------------------------------------------


@pytest.mark.parametrize("dim", [1, 2])
def test_student_t_is_the_student_density_up_to_a_constant(dim):
    rng = np.random.default_rng(0)
    residuals = rng.normal(size=(20, dim)) * 3
    scales = rng.uniform(0.1, 4.0, size=20)
    ours = student_t((residuals**2).sum(axis=1), scales, STUDENT_DOF, dim)
    if dim == 1:
        exact = stats.t.logpdf(residuals[:, 0], STUDENT_DOF, scale=scales)
    else:
        exact = np.array([
            stats.multivariate_t.logpdf(r, shape=s**2 * np.eye(2), df=STUDENT_DOF)
            for r, s in zip(residuals, scales)
        ])  # fmt: skip
    np.testing.assert_allclose(ours - exact, (ours - exact)[0], atol=1e-9)


def test_student_t_peaks_at_no_residual_and_falls_with_it():
    r = np.linspace(0, 5, 11)
    values = student_t(r**2, 1.0, STUDENT_DOF, 1)
    assert np.all(np.diff(values) < 0)
    # a wider scale makes a large residual less surprising and a small one less probable
    assert student_t(25.0, 2.0, 3.0, 1) > student_t(25.0, 1.0, 3.0, 1)
    assert student_t(0.0, 2.0, 3.0, 1) < student_t(0.0, 1.0, 3.0, 1)


def test_the_rotation_error_scale_falls_off_with_the_lever_arm():
    absolute, near = 0.01, 0.13
    assert theta_scale(0.0, (absolute, near), 15.0) == pytest.approx(absolute + near)
    assert theta_scale(15.0, (absolute, near), 15.0) == pytest.approx(absolute + near / 2)
    assert theta_scale(1e6, (absolute, near), 15.0) == pytest.approx(absolute, abs=1e-9)
    levers = np.linspace(0, 60, 13)
    assert np.all(np.diff(theta_scale(levers, (absolute, near), 15.0)) < 0)
    np.testing.assert_array_equal(theta_scale(-levers, (absolute, near), 15.0),
                                  theta_scale(levers, (absolute, near), 15.0))  # fmt: skip


@settings(max_examples=60)
@given(theta=st.floats(-3.0, 3.0), x=st.floats(-30, 30), y=st.floats(-30, 30))
def test_com_shift_moves_a_point_along_its_circle(theta, x, y):
    offset = np.array([[x, y]])
    shift = com_shift(theta, offset)
    assert shift.shape == (1, 2)
    assert np.hypot(*shift[0]) == pytest.approx(2 * abs(math.sin(theta / 2)) * math.hypot(x, y),
                                                abs=1e-9)  # fmt: skip
    # the moved point stays as far from the centroid as it was
    assert np.hypot(*(offset + shift)[0]) == pytest.approx(math.hypot(x, y), abs=1e-9)


def test_com_shift_broadcasts_hypotheses_against_friction_values():
    offset = np.arange(8.0).reshape(4, 1, 2)  # (p, 1, 2)
    theta = np.linspace(-0.2, 0.2, 12).reshape(4, 3)  # (p, m)
    shift = com_shift(theta, offset)
    assert shift.shape == (4, 3, 2)
    np.testing.assert_allclose(shift[2, 1], com_shift(theta[2, 1], offset[2])[0])
    np.testing.assert_array_equal(com_shift(0.0, offset), 0.0)


# -- motion_terms ---------------------------------------------------------------------------


def _shapes(p=4, m=3):
    rng = np.random.default_rng(1)
    predicted = rng.normal(size=(p, m, 3)) * [0.1, 5, 5]
    lever = rng.uniform(0, 20, size=(p, m))
    offset = rng.normal(size=(p, 1, 2)) * 5
    return predicted, lever, offset


def test_each_term_is_per_hypothesis_and_a_perfect_prediction_scores_best():
    predicted, lever, offset = _shapes()
    observed = predicted[2, 1]
    terms = motion_terms(observed, predicted, lever, offset, NOISE)
    assert [t[2] for t in terms] == [1, 2]  # rotation, then the CoM's displacement
    for res_sq, scale, _ in terms:
        assert res_sq.shape == scale.shape == (4, 3) and (scale > 0).all()
        assert res_sq[2, 1] == pytest.approx(0.0, abs=1e-18)
    ll = log_likelihood(terms)
    assert ll.shape == (4, 3)
    # against a hypothesis with the same scales, the one that predicted the motion wins
    moved = observed + np.array([0.05, 1.0, -1.0])
    same_scales = motion_terms(moved, predicted, lever, offset, NOISE)
    assert log_likelihood(same_scales)[2, 1] < ll[2, 1]


def test_the_displacement_is_compared_at_each_hypothesis_com():
    """A centroid displacement off by what the rotation moves the CoM by leaves no residual."""
    offset = np.array([[[6.0, -4.0]]])
    theta_p, theta_o = 0.1, 0.25
    t_p = np.array([5.0, 1.0])
    t_o = t_p + com_shift(theta_p, offset[0])[0] - com_shift(theta_o, offset[0])[0]
    predicted = np.array([[[theta_p, *t_p]]])
    terms = motion_terms(np.array([theta_o, *t_o]), predicted, np.array([[8.0]]), offset, NOISE)
    assert terms[0][0][0, 0] == pytest.approx(0.15**2)
    assert terms[1][0][0, 0] == pytest.approx(0.0, abs=1e-20)


def test_the_tracking_noise_adds_in_quadrature_and_the_displacement_scale_grows_with_it():
    predicted, lever, offset = _shapes()
    args = (predicted[0, 0], predicted, lever, offset, NOISE)
    plain = motion_terms(*args)
    noisy = motion_terms(*args, tracking=(0.02, 0.3))
    np.testing.assert_allclose(noisy[0][1], np.hypot(plain[0][1], 0.02))
    np.testing.assert_allclose(noisy[1][1], np.hypot(plain[1][1], 0.3))
    np.testing.assert_array_equal(noisy[0][0], plain[0][0])  # the residuals are the same
    # the displacement's scale: absolute + relative * |predicted displacement of the CoM|
    moved = predicted[..., 1:] + com_shift(predicted[..., 0], offset)
    np.testing.assert_allclose(plain[1][1], 0.4 + 0.056 * np.hypot(*np.moveaxis(moved, -1, 0)))


def test_without_the_rotation_only_the_centroid_displacement_is_scored_and_widened():
    predicted, lever, offset = _shapes()
    observed = np.array([0.3, *predicted[1, 0, 1:]])  # any rotation: it is not seen
    terms = motion_terms(observed, predicted, lever, offset, NOISE, rotation=False)
    assert len(terms) == 1 and terms[0][2] == 2
    res_sq, scale, _ = terms[0]
    assert res_sq[1, 0] == 0.0
    np.testing.assert_allclose(res_sq, ((observed[1:] - predicted[..., 1:]) ** 2).sum(axis=-1))
    # the farther a hypothesis' CoM from the centroid, the wider its scale
    base = 0.4 + 0.056 * np.hypot(predicted[..., 1], predicted[..., 2])
    widened = scale - base
    th = theta_scale(lever, NOISE.theta, NOISE.near_px)
    np.testing.assert_allclose(widened, th * np.hypot(offset[..., 0], offset[..., 1]))


# -- excess surprise -------------------------------------------------------------------------


def test_a_perfect_prediction_is_less_surprising_than_the_model_s_own_motions():
    # E[(dof + d) / 2 log(1 + |T|^2 / dof)]: 0.773 and 1.667 nats (the module's numbers)
    assert excess_surprise([(0.0, 1.0, 1)]) == pytest.approx(-0.773, abs=5e-4)
    assert excess_surprise([(0.0, 1.0, 2)]) == pytest.approx(-1.667, abs=5e-4)


def test_the_excess_surprise_is_zero_on_average_for_the_hypothesis_that_made_the_motion():
    rng = np.random.default_rng(2)
    n, theta_scale_, moved_scale = 40_000, 0.05, 2.0
    t1 = theta_scale_ * rng.standard_t(STUDENT_DOF, n)
    z = rng.normal(size=(n, 2)) / np.sqrt(rng.chisquare(STUDENT_DOF, n) / STUDENT_DOF)[:, None]
    t2 = moved_scale * z
    excess = excess_surprise([(t1**2, theta_scale_, 1), ((t2**2).sum(axis=1), moved_scale, 2)])
    assert abs(excess.mean()) < 4 * excess.std() / math.sqrt(n)
    # and large for motions the hypothesis did not make
    off = excess_surprise([((t1 + 0.3) ** 2, theta_scale_, 1), ((t2**2).sum(axis=1), moved_scale, 2)])
    assert off.mean() > 3.0  # six scales off: about 2 log(13) - 0.77 = 4.4 nats


# -- model_predictions -----------------------------------------------------------------------


class Recorder:
    """A model that records what it is asked and predicts theta = 0.01 * (y - 15.5)."""

    def __init__(self, out=None):
        self.calls, self.told, self.out = [], [], out

    def expect_frictions(self, mask, mus):
        self.told.append(tuple(mus))

    def predict_hypotheses(self, mask, actions, coms, mu):
        coms = np.asarray(coms, float)
        self.calls.append((len(coms), mu))
        if self.out is not None:
            return self.out
        out = np.zeros((len(coms), len(actions), 3))
        out[..., 0] = 0.01 * (coms[:, 1:2] - 15.5)
        out[..., 1] = 5.0
        return out


def test_only_live_hypotheses_are_asked_and_the_rest_are_nan():
    model = Recorder()
    pixels = PLATE.pixels[:6]
    alive = np.zeros((6, 2, 1), dtype=bool)
    alive[[0, 3], 0, 0] = True  # two pixels at the first friction value, none at the second
    actions = np.array([[0.0, 10.0, 30.0, 10.0], [0.0, 20.0, 30.0, 20.0]])
    out = model_predictions([model], PLATE, actions, pixels, [0.2, 0.6], alive)
    assert out.shape == (6, 2, 1, 2, 3)
    assert model.calls == [(2, 0.2)] and model.told == [(0.2, 0.6)]
    assert np.isfinite(out[alive]).all() and np.isnan(out[~alive]).all()
    np.testing.assert_allclose(out[3, 0, 0, :, 0], 0.01 * (pixels[3, 1] - 15.5))


@pytest.mark.parametrize("out", [np.zeros((1, 1, 3)), np.full((2, 1, 3), np.nan)])
def test_a_model_returning_the_wrong_shape_or_nan_is_named(out):
    alive = np.ones((2, 1, 1), dtype=bool)
    with pytest.raises(ValueError, match=r"Recorder.predict_hypotheses returned (motions of shape "
                                         r"\(1, 1, 3\), expected|NaN as the theta of push 0)"):  # fmt: skip
        model_predictions([Recorder(out)], PLATE, np.array([[0.0, 10, 30, 10]]),
                          PLATE.pixels[:2], [0.3], alive)  # fmt: skip


# -- the pusher's offset ---------------------------------------------------------------------


def _scoring(pusher_error_px, models=()):
    likelihood = comcore.Likelihood(pusher_error=pusher_error_px * PLATE.resolution)
    return Scoring.build(likelihood, PLATE, tuple(models))


def test_without_a_pusher_error_the_planned_push_alone_is_asked():
    shifts, log_w = pusher_nodes([0, 10, 30, 10], _scoring(0.0))
    np.testing.assert_array_equal(shifts, np.zeros((1, 2)))
    np.testing.assert_array_equal(log_w, [0.0])


@settings(max_examples=30)
@given(angle=st.floats(-math.pi, math.pi), sigma=st.floats(0.1, 3.0))
def test_the_nodes_lie_across_the_push_at_gauss_hermite_offsets(angle, sigma):
    direction = np.array([math.cos(angle), math.sin(angle)])
    action = np.r_[np.array([15.0, 15.0]) - 20 * direction, np.array([15.0, 15.0]) + 10 * direction]
    shifts, log_w = pusher_nodes(action, _scoring(sigma))
    np.testing.assert_allclose(shifts @ direction, 0.0, atol=1e-9)
    np.testing.assert_allclose(sorted(np.hypot(*shifts.T)), [0, math.sqrt(3) * sigma, math.sqrt(3) * sigma])
    w = np.exp(log_w)
    assert w.sum() == pytest.approx(1.0)
    # they reproduce the normal's mean and variance
    assert (w[:, None] * shifts).sum(axis=0) == pytest.approx([0.0, 0.0], abs=1e-9)
    assert (w * (shifts**2).sum(axis=1)).sum() == pytest.approx(sigma**2)


def _marginal(sigma_px):
    model = Recorder()
    scoring = _scoring(sigma_px, [model])
    pixels = np.array([[10.0, 8.0], [12.0, 15.5], [20.0, 22.0]])
    offset = (pixels - np.asarray(PLATE.centroid))[:, None, None, :]
    alive = np.ones((3, len(scoring.mus), 1), dtype=bool)
    action = np.array([0.0, 15.5, 30.0, 15.5])  # along x: the offsets are along y
    return model, offset_marginal(scoring, PLATE, action, pixels, offset, alive), pixels


def test_the_offset_marginal_is_the_model_itself_without_a_pusher_error():
    model, (mean, spread), pixels = _marginal(0.0)
    assert spread == (0.0, 0.0)
    assert mean.shape == (3, 6, 1, 3)
    np.testing.assert_allclose(mean[..., 0], 0.01 * (pixels[:, 1:2, None] - 15.5) * np.ones((3, 6, 1)))
    assert [n for n, _ in model.calls] == [3] * 6  # one call per friction value


def test_the_offset_marginal_of_a_linear_model_is_exact():
    """theta linear in the CoM: the nodes' mean is theta at the CoM, its spread a sigma."""
    sigma = 2.0
    model, (mean, spread), pixels = _marginal(sigma)
    np.testing.assert_allclose(mean[..., 0], np.broadcast_to(0.01 * (pixels[:, 1:2, None] - 15.5), (3, 6, 1)))
    np.testing.assert_allclose(spread[0], 0.01 * sigma, rtol=1e-9)
    assert [n for n, _ in model.calls] == [9] * 6  # three nodes per hypothesis, one call each


# -- the model's errors as the likelihood scores them --------------------------------------


def test_the_error_density_is_invariant_to_the_units_but_for_a_constant():
    rng = np.random.default_rng(3)
    theta_err, lever = rng.normal(size=8) * 0.05, rng.uniform(0, 0.1, 8)
    moved_err, moved = rng.uniform(0, 0.004, 8), rng.uniform(0, 0.04, 8)
    one = model_error_log_density((0.01, 0.13), (0.001, 0.056), theta_err, lever, moved_err, moved)
    # twice the errors against twice the scales: every push loses log 2 (rotation) + 2 log 2
    two = model_error_log_density((0.02, 0.26), (0.002, 0.056), 2 * theta_err, lever, 2 * moved_err,
                                  2 * moved)  # fmt: skip
    np.testing.assert_allclose(two, one - 3 * math.log(2), atol=1e-12)
    # the rotation's extra scale near the line halves at a lever of NEAR_LINE_M (3.75 cm)
    at_near = model_error_log_density((0.0, 0.1), (0.001, 0.0), [0.02], [NEAR_LINE_M], [0.0], [0.0])
    fixed = model_error_log_density((0.05, 0.0), (0.001, 0.0), [0.02], [0.3], [0.0], [0.0])
    np.testing.assert_allclose(at_near, fixed, rtol=1e-12)
    larger = model_error_log_density((0.01, 0.13), (0.001, 0.056), 3 * theta_err, lever, moved_err, moved)
    assert np.all(larger <= one + 1e-12)
