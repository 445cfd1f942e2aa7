"""Tests of the model's lattice on cameras finer than it (comcore/active/_grid.py)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import comcore
from comcore.active._grid import lattice_stride, model_lattice, prior_grid
from comcore.active._likelihood import Scoring, push_evidence
from comcore.geometry._disc_contacts import pusher_contacts
from comcore.vt._voting import push_force_lines
from tests.active.test_blocking import ToyModel


def _l_shape(size: int) -> np.ndarray:
    """An L of ``size`` px arms, with a one-pixel spur: pixels far from any node."""
    image = np.zeros((size + 8, size + 8), bool)
    image[4 : 4 + size, 4 : 4 + size // 3] = True
    image[4 + 2 * size // 3 : 4 + size, 4 : 4 + size] = True
    image[2, 5] = image[3, 5] = True  # a spur off the L's top
    return image


@settings(max_examples=40, deadline=None)
@given(size=st.integers(6, 40), stride=st.integers(2, 5))
def test_every_pixel_reads_a_convex_combination_of_nodes_on_the_object_near_it(size, stride):
    pixels = comcore.conventions.pixel_centres(_l_shape(size))
    lattice = model_lattice(pixels, stride)
    w = lattice.weights.toarray()
    assert w.shape == (len(pixels), len(lattice.nodes))
    assert (w >= 0).all()
    np.testing.assert_allclose(w.sum(axis=1), 1.0, rtol=0, atol=1e-12)
    # the nodes are pixels of the object, each reading itself alone
    assert len(np.unique(lattice.nodes)) == len(lattice.nodes)
    np.testing.assert_array_equal(w[lattice.nodes], np.eye(len(lattice.nodes)))
    # a pixel's nodes lie within one lattice cell of it
    for i, j in zip(*np.nonzero(w)):
        assert np.abs(pixels[lattice.nodes[j]] - pixels[i]).max() <= stride
    # far fewer hypotheses asked than pixels, on a large enough object
    if size >= 20:
        assert len(lattice.nodes) < 0.6 * len(pixels)


@settings(max_examples=20, deadline=None)
@given(stride=st.integers(2, 4), slope=st.tuples(st.floats(-3, 3), st.floats(-3, 3)))
def test_a_plane_is_reproduced_where_every_pixel_s_cell_lies_on_the_object(stride, slope):
    side = 6 * stride + 1  # a square of whole lattice cells: nodes at its corners and edges
    image = np.zeros((side + 6, side + 6), bool)
    image[3 : 3 + side, 3 : 3 + side] = True
    pixels = comcore.conventions.pixel_centres(image)
    lattice = model_lattice(pixels, stride)
    assert len(lattice.nodes) == 7 * 7
    plane = pixels @ np.array(slope) + 2.0
    got = lattice.spread(plane[lattice.nodes], np.ones(len(lattice.nodes), bool))
    np.testing.assert_allclose(got, plane, atol=1e-9)
    # one node off the object (a hole): its neighbours read the others, renormalised
    image[3 + stride, 3 + stride] = False
    holed = comcore.conventions.pixel_centres(image)
    assert len(model_lattice(holed, stride).nodes) == 7 * 7 - 1


def test_gather_and_spread():
    pixels = comcore.conventions.pixel_centres(np.ones((9, 9), bool))
    lattice = model_lattice(pixels, 2)
    mass = np.random.default_rng(0).random((len(pixels), 3))
    assert lattice.gather_sum(mass).sum() == pytest.approx(mass.sum(), rel=1e-12)
    flags = np.zeros(len(pixels), bool)
    flags[40] = True  # the centre pixel (4, 4), a node
    used = lattice.gather_any(flags)
    assert used.sum() == 1 and lattice.nodes[used][0] == 40
    # an unusable node counts 0, whatever it holds
    values = np.where(used, 1.0, np.nan)
    assert np.isfinite(lattice.spread(values, used)).all()


def test_the_stride_is_the_spacing_in_whole_pixels():
    assert lattice_stride(0.0025, 0.0025) == 1
    assert lattice_stride(0.0025, 0.003) == 1
    assert lattice_stride(0.0025, 0.001) == 2
    assert lattice_stride(0.0025, 0.0005) == 5
    assert lattice_stride(0.0, 0.0005) == 1
    assert model_lattice(np.zeros((4, 2)), 1) is None
    assert model_lattice(np.array([[0.0, 0.0], [1.5, 0.0], [2.0, 1.0]]), 2) is None


def test_model_spacing_is_checked():
    assert comcore.Likelihood().model_spacing == 0.0025
    assert comcore.Likelihood(model_spacing=0).model_spacing == 0.0
    with pytest.raises(ValueError, match="model_spacing"):
        comcore.Likelihood(model_spacing=-0.001)
    with pytest.raises(ValueError, match="model_spacing 2.5 m is implausible.*millimetres"):
        comcore.Likelihood(model_spacing=2.5)
    with pytest.raises(TypeError, match="model_spacing"):
        comcore.Likelihood(model_spacing="2.5 mm")


class _Counting(ToyModel):
    """The toy model, counting the hypotheses it is asked about."""

    def __init__(self):
        super().__init__(length=20.0)
        self.asked = 0

    def predict_hypotheses(self, mask, actions, coms, mu):
        self.asked += len(coms)
        return super().predict_hypotheses(mask, actions, coms, mu)


def _posterior_after(likelihood, mask, action, com):
    model = _Counting()
    scoring = Scoring.build(likelihood, mask, (model,))
    pixels, prior = prior_grid(mask, None)
    post = scoring.posterior(pixels, prior)
    acts = np.asarray([action], float)
    lines = push_force_lines(pusher_contacts(mask, acts, 0.0), acts, scoring.mus)
    motion = ToyModel(length=20.0).predict_hypotheses(mask, acts, [com], 0.4)[0, 0]
    evidence, excess = push_evidence(post, scoring, mask, acts[0], lines[0], motion)
    post.update(evidence.tempered, evidence.full)
    return post, model.asked, excess


def test_on_a_finer_camera_the_lattice_asks_a_quarter_and_the_posterior_barely_moves():
    """1 mm per pixel, the default 2.5 mm spacing (stride 2) against every pixel asked."""
    image = np.zeros((60, 60), bool)
    image[8:52, 10:50] = True
    mask = comcore.Mask(image, resolution=0.001)
    action, com = (0.0, 22.0, 40.0, 22.0), (33.0, 25.0)
    likelihood = comcore.Likelihood(mu=0.4)
    lattice, asked, excess = _posterior_after(likelihood, mask, action, com)
    exact, asked_all, excess_all = _posterior_after(
        comcore.Likelihood(mu=0.4, model_spacing=0.0), mask, action, com
    )
    assert asked < 0.3 * asked_all
    p, q = lattice.marginal, exact.marginal
    assert 0.5 * np.abs(p - q).sum() < 0.01  # total variation
    np.testing.assert_allclose(lattice.mean(), exact.mean(), atol=0.1)
    assert np.isfinite(excess).all() and np.abs(excess - excess_all).max() < 0.5
    # at the model's spacing the lattice is every pixel: the same evidence to the bit
    coarse = comcore.Mask(image, resolution=0.0025)
    same, _, _ = _posterior_after(likelihood, coarse, action, com)
    every, _, _ = _posterior_after(comcore.Likelihood(mu=0.4, model_spacing=0.0), coarse, action, com)
    np.testing.assert_array_equal(same.log_w, every.log_w)
