"""Tests of choosing the next push (comcore/active/_choice.py): candidates, offers, gains."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import comcore
from comcore.active._choice import (
    Candidates,
    binary_entropy,
    model_gains,
    particles,
    sense_information,
)
from comcore.active._grid import GridPosterior, prior_grid
from comcore.active._likelihood import Scoring
from comcore.active._motion_term import ModelNoise
from comcore.camera._pose_tracking import moved_mask
from comcore.geometry._disc_contacts import pusher_contacts
from comcore.vt._voting import push_force_lines

PLATE = comcore.Mask(np.pad(np.ones((20, 20), bool), 8))  # object pixels 8..27
MUS = comcore.Likelihood(n_mu=3).mus
RADIUS = 0.004  # the default pusher, metres


def _candidates(candidates=None, choice=None, rng=0, mask=PLATE, name="candidates"):
    choice = choice or comcore.PushChoice(n_candidates=30)
    return Candidates(mask, candidates, choice, MUS, np.random.default_rng(rng), name,
                      pusher_radius=RADIUS)  # fmt: skip


def _uniform_posterior(mask=PLATE, mus=MUS, **kw):
    pixels, prior = prior_grid(mask, None)
    return GridPosterior(pixels, prior, mus, **kw)


# -- the candidates ----------------------------------------------------------------------------


def test_default_candidates_are_drawn_once_and_the_same_for_a_seed():
    one, again, other = _candidates(rng=4), _candidates(rng=4), _candidates(rng=5)
    assert len(one) == 30 and one.actions.shape == (30, 4)
    np.testing.assert_array_equal(one.actions, again.actions)
    assert not np.array_equal(one.actions, other.actions)
    # every one drawn can be pushed: it starts outside the plate and hits it
    con = pusher_contacts(PLATE, one.actions, RADIUS)
    assert (con.hit & ~con.starts_inside).all() and one.available.all()
    assert one.lines.shape == (30, len(MUS), 3)


def test_given_candidates_that_cannot_be_pushed_are_skipped_and_said_why():
    given_ = [
        (0.0, 15.0, 30.0, 15.0),  # a push from the left
        (15.0, 15.0, 20.0, 15.0),  # starts inside the object
        (0.0, 2.0, 30.0, 2.0),  # passes above it
        (35.0, 20.0, 10.0, 20.0),  # a push from the right
    ]
    cands = _candidates(given_)
    assert cands.available.tolist() == [True, False, False, True]
    skipped = {s.index: s for s in cands.skipped}
    assert sorted(skipped) == [1, 2]
    assert skipped[1].reason == "starts_inside" and "candidates[1] starts inside" in skipped[1].detail
    assert skipped[2].reason == "misses" and "candidates[2] never touches" in skipped[2].detail
    offered = cands.offerable(comcore.Motion.identity(), PLATE)
    assert offered.tolist() == [True, False, False, True]


def test_no_usable_candidate_is_an_error_naming_the_argument():
    with pytest.raises(ValueError, match="pushes must start outside the object and touch it"):
        _candidates([(15.0, 15.0, 20.0, 15.0)], name="pushes")
    with pytest.raises(ValueError, match="candidates"):
        _candidates(np.zeros((0, 4)))


def test_the_candidates_are_a_copy_the_caller_cannot_change():
    given_ = np.array([[0.0, 15.0, 30.0, 15.0], [40.0, 20.0, 10.0, 20.0]])
    cands = _candidates(given_)
    given_[0] = 99.0
    np.testing.assert_array_equal(cands.actions[0], [0.0, 15.0, 30.0, 15.0])
    with pytest.raises(ValueError):
        cands.actions[0, 0] = 1.0


def test_a_candidate_made_is_never_offered_again_nor_its_duplicates():
    push, other = (0.0, 15.0, 30.0, 15.0), (35.0, 20.0, 10.0, 20.0)
    cands = _candidates([push, other, push])
    cands.made(2)
    assert cands.offerable(comcore.Motion.identity(), PLATE).tolist() == [False, True, False]
    cands.made(1)
    assert not cands.offerable(comcore.Motion.identity(), PLATE).any()


def test_candidates_leaving_the_image_or_an_object_out_of_view_are_not_offered():
    cands = _candidates([(0.0, 15.0, 30.0, 15.0), (15.0, -8.0, 15.0, 20.0)])  # from above the image
    assert cands.available.tolist() == [True, True]
    assert cands.offerable(comcore.Motion.identity(), PLATE).tolist() == [True, False]
    assert not cands.offerable(comcore.Motion(0.0, 3.0, 0.0), None).any()  # it left the image
    # the image's edge is where the candidates may end: (35, y) is the last pixel's centre
    edge = _candidates([(35.0, 20.0, 10.0, 20.0), (35.6, 20.0, 10.0, 20.0)])
    assert edge.offerable(comcore.Motion.identity(), PLATE).tolist() == [True, False]


def test_offered_candidates_at_a_pose_can_be_pushed_on_the_object_there():
    cands = _candidates(choice=comcore.PushChoice(n_candidates=60), rng=1)
    pose = comcore.Motion(0.4, 3.0, -2.0)
    now = moved_mask(PLATE, pose)
    offered = cands.offerable(pose, now)
    assert 0 < offered.sum() <= cands.available.sum()
    moved = cands.in_pose(pose, np.flatnonzero(offered))
    con = pusher_contacts(now, moved, RADIUS)
    assert (con.hit & ~con.starts_inside).all()
    h, w = PLATE.shape
    assert (moved[:, 0::2] >= -0.5).all() and (moved[:, 0::2] <= w - 0.5).all()
    assert (moved[:, 1::2] >= -0.5).all() and (moved[:, 1::2] <= h - 0.5).all()
    # a translated pose moves every candidate by the translation
    shifted = cands.in_pose(comcore.Motion(0.0, 3.0, -2.0))
    np.testing.assert_allclose(shifted, cands.actions + np.array([3.0, -2.0, 3.0, -2.0]))
    np.testing.assert_array_equal(cands.in_pose(comcore.Motion.identity()), cands.actions)


# -- choosing ----------------------------------------------------------------------------------


def _scoring(models=()):
    return Scoring.build(comcore.Likelihood(n_mu=3), PLATE, tuple(models))


def test_the_chosen_push_is_the_most_informative_offered_one():
    cands = _candidates(rng=2)
    post, scoring = _uniform_posterior(), _scoring()
    offered = cands.offerable(comcore.Motion.identity(), PLATE)
    index, gain = cands.choose(post, offered, scoring, "sense")
    gains = sense_information(post.pixels, post.sense_weights, cands.lines, scoring.flip_prob,
                              scoring.line_scale_px)  # fmt: skip
    assert offered[index] and gain == pytest.approx(gains[offered].max())
    # among a subset, a member of the subset; the same again for the same state
    subset = np.zeros(len(cands), dtype=bool)
    subset[[3, 7, 11]] = True
    picked, _ = cands.choose(post, subset, scoring, "sense")
    assert picked in (3, 7, 11)
    assert cands.choose(post, subset, scoring, "sense")[0] == picked
    assert cands.choose(post, np.zeros(len(cands), bool), scoring, "sense") == (None, None)


class Lever:
    """theta proportional to the CoM's signed distance to the push line (pixels)."""

    def predict_hypotheses(self, mask, actions, coms, mu):
        lever = comcore.geometry.signed_line_distance(coms, actions)
        return np.stack([0.01 * lever, 0 * lever + 5.0, 0 * lever], axis=-1)


def test_the_model_s_choice_is_an_offered_push_with_a_finite_gain():
    cands = _candidates(rng=3)
    post, scoring = _uniform_posterior(), _scoring([Lever()])
    offered = cands.offerable(comcore.Motion.identity(), PLATE)
    offered[::2] = False
    index, gain = cands.choose(post, offered, scoring, "model")
    assert offered[index] and math.isfinite(gain) and gain > 0
    assert cands.choose(post, offered, scoring, "model") == (index, gain)


class OneInformative:
    """A push from the left turns by the CoM's row; one from the right moves every CoM alike."""

    def predict_hypotheses(self, mask, actions, coms, mu):
        coms, actions = np.asarray(coms, float), np.asarray(actions, float)
        out = np.zeros((len(coms), len(actions), 3))
        out[:, :, 1] = 5.0
        from_left = actions[:, 0] < actions[:, 2]
        out[:, from_left, 0] = -0.02 * (coms[:, 1:2] - 17.5)  # the sense the Voting Theorem gives
        return out


def test_a_push_all_hypotheses_predict_alike_teaches_nothing_about_the_com():
    given_ = [(0.0, 17.5, 30.0, 17.5), (0.0, 17.5, 30.0, 17.5), (35.0, 17.5, 10.0, 17.5)]
    cands = _candidates(given_)
    post = _uniform_posterior()
    noise = ModelNoise(theta=(0.01, 0.13), translation_px=(0.4, 0.056), near_px=15.0)
    gains = model_gains((OneInformative(),), PLATE, post, cands.actions, cands.lines, noise)
    assert gains[0] > 0.5  # nats: the rotation separates the rows
    assert abs(gains[1] - gains[0]) < 1e-9  # the same push twice: the same gain
    assert gains[2] < 0.1 * gains[0]


# -- particles --------------------------------------------------------------------------------


def test_particles_are_a_deterministic_draw_from_the_posterior():
    post = _uniform_posterior()
    index, weights = particles(post, 64)
    assert weights.sum() == pytest.approx(1.0) and len(np.unique(index)) == len(index)
    again = particles(post, 64)
    np.testing.assert_array_equal(index, again[0])
    # uniform over the 400 pixels: 64 distinct ones, evenly
    assert len(index) == 64 and np.allclose(weights, 1 / 64)
    # a posterior on one pixel: that pixel alone
    peaked = GridPosterior(post.pixels, np.where(np.arange(400) == 123, 1.0, 1e-300), MUS)
    index, weights = particles(peaked, 64)
    assert index.tolist() == [123] and weights.tolist() == [1.0]
    # two pixels holding 3/4 and 1/4
    two = GridPosterior(post.pixels[:2], [0.75, 0.25], MUS)
    assert particles(two, 8)[1].tolist() == [0.75, 0.25]


# -- the senses' information -----------------------------------------------------------------


def _two_pixels_and_lines():
    """Two CoM hypotheses, at y = 0 and y = 40; lines y = c for c in 20 (between) and 60 (not)."""
    pixels = np.array([[10.0, 0.0], [10.0, 40.0]])
    lines = np.array([[[0.0, 1.0, -20.0]], [[0.0, 1.0, -60.0]]])
    return pixels, np.array([[0.5], [0.5]]), lines


def test_a_line_between_two_equal_hypotheses_is_worth_one_bit_less_the_flips():
    pixels, weights, lines = _two_pixels_and_lines()
    for flip in (1e-6, 0.05, 0.2):
        gains = sense_information(pixels, weights, lines, flip, scale=1.0)
        assert gains[0] == pytest.approx(1 - binary_entropy(flip), abs=1e-5)
        assert gains[1] == pytest.approx(0.0, abs=1e-5)  # both on one side: nothing to learn


@settings(max_examples=25)
@given(seed=st.integers(0, 2**16), flips=st.tuples(st.floats(1e-4, 0.45), st.floats(1e-4, 0.45)))
def test_more_flips_never_tell_more_and_a_sense_tells_at_most_a_bit(seed, flips):
    rng = np.random.default_rng(seed)
    cands = comcore.sample_pushes(PLATE, 12, cone=0.4, rng=seed)
    con = pusher_contacts(PLATE, cands, 0.0)
    lines = push_force_lines(con, cands, MUS)
    weights = rng.random((PLATE.area_px, len(MUS))) ** 4
    weights /= weights.sum()
    low, high = sorted(flips)
    g_low = sense_information(PLATE.pixels, weights, lines, low)
    g_high = sense_information(PLATE.pixels, weights, lines, high)
    assert (g_low >= -1e-6).all() and (g_low <= 1 - binary_entropy(low) + 1e-5).all()
    assert (g_high <= g_low + 1e-5).all()


def test_binary_entropy():
    assert binary_entropy(0.5) == pytest.approx(1.0)
    np.testing.assert_allclose(binary_entropy([0.1, 0.9]), [0.4689955935892812] * 2)
