"""Tests of comcore.estimate_posterior (comcore/_active.py): the offline active posterior."""

from __future__ import annotations

import numpy as np
import pytest

import comcore
from tests.test_active import ToyModel, _ell, _plate, _robot


@pytest.mark.parametrize("model", [None, ToyModel()])
def test_it_is_the_active_posterior_of_the_same_pushes(model):
    mask = _ell()
    active = comcore.estimate_active(mask, _robot(mask, (30.0, 24.0), 0.4), model=model, rng=3)
    offline = comcore.estimate_posterior(
        mask, active.extras["actions"], active.extras["motions"], model=model
    )
    assert offline.status == "ok" and offline.used == tuple(range(len(active.used)))
    np.testing.assert_allclose(offline.extras["posterior"], active.extras["posterior"], atol=1e-12)
    np.testing.assert_array_equal(offline.region, active.region)
    assert offline.com == pytest.approx(active.com, abs=1e-9)


def test_the_order_of_the_pushes_does_not_matter():
    mask = _plate()
    push = _robot(mask, (20.0, 15.0), 0.3)
    actions = comcore.sample_pushes(mask, 6, rng=1)
    motions = [push(comcore.Action(*a)) for a in actions]
    one = comcore.estimate_posterior(mask, actions, motions)
    other = comcore.estimate_posterior(mask, actions[::-1], motions[::-1])
    np.testing.assert_allclose(one.extras["posterior"], other.extras["posterior"], atol=1e-12)


def test_a_push_that_did_not_move_the_object_carries_no_evidence():
    mask = _plate()
    push = _robot(mask, (20.0, 15.0), 0.3)
    actions = comcore.sample_pushes(mask, 3, rng=2)
    motions = [tuple(push(comcore.Action(*a))) for a in actions]
    with_miss = comcore.estimate_posterior(mask, actions, [motions[0], (0.0, 0.0, 0.0), motions[2]])
    without = comcore.estimate_posterior(mask, actions[[0, 2]], [motions[0], motions[2]])
    assert with_miss.extras["outcomes"] == ("evidence", "miss", "evidence")
    assert with_miss.used == (0, 2)
    np.testing.assert_allclose(with_miss.extras["posterior"], without.extras["posterior"])
    only_misses = comcore.estimate_posterior(mask, actions[:1], [(0.0, 0.0, 0.0)])
    assert only_misses.status == "no_evidence" and only_misses.com == pytest.approx(mask.centroid)


@pytest.mark.parametrize(
    ("args", "kwargs", "error", "match"),
    [
        (([(0, 0, 0, 1)], [(0.1, 0, 0)]), {}, ValueError, "actions must hit the object"),
        (([(0, 20, 20, 20)], [(0.1, 0, 0)] * 2), {}, ValueError, "motions"),
        (([(0, 20, 20, 20)], [(0.1, 0, 0)]), {"max_pushes": 3}, TypeError, "chooses no pushes"),
        (([(0, 20, 20, 20)], [(0.1, 0, 0)]), {"flip_prob": 0.7}, ValueError, "flip_prob"),
        (([], []), {}, ValueError, "actions"),
    ],
)
def test_bad_arguments_are_named(args, kwargs, error, match):
    with pytest.raises(error, match=match):
        comcore.estimate_posterior(_plate(), *args, **kwargs)


def test_pushes_no_com_explains_are_inconsistent():
    mask = _ell()
    actions = comcore.sample_pushes(mask, 5, rng=0)
    honest = [_robot(mask, (30.0, 24.0), 0.4)(comcore.Action(*a)) for a in actions]
    kwargs = {"model": ToyModel()}
    assert comcore.estimate_posterior(mask, actions, honest, **kwargs).status == "ok"
    liar = [(0.1, 0.0, 0.0)] * 5
    est = comcore.estimate_posterior(mask, actions, liar, **kwargs)
    assert est.status == "inconsistent" and est.extras["excess_nats"] > 30
