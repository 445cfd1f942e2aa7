"""Tests of the option groups from flat names (comcore/bench/_registry.py: option_groups)."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import comcore
from comcore.bench import option_groups

GROUPS = {"likelihood": comcore.Likelihood, "stop": comcore.StopRule, "choice": comcore.PushChoice}


def test_no_field_name_belongs_to_two_groups():
    """Otherwise a flat name could not say which group it sets."""
    names = [f.name for cls in GROUPS.values() for f in dataclasses.fields(cls)]
    assert len(names) == len(set(names))
    assert not set(names) & set(GROUPS)  # nor is a group's keyword a field's name


def test_each_flat_name_lands_in_its_group_and_the_rest_keep_their_defaults():
    groups = option_groups(flip_prob=0.1, n_mu=4, min_pushes=1, selection="model", cone=0.2)
    assert set(groups) == {"likelihood", "stop", "choice"}
    assert groups["likelihood"] == comcore.Likelihood(flip_prob=0.1, n_mu=4)
    assert groups["stop"] == comcore.StopRule(min_pushes=1)
    assert groups["choice"] == comcore.PushChoice(selection="model", cone=0.2)
    assert type(groups["likelihood"]) is comcore.Likelihood


def test_a_group_turned_into_flat_names_comes_back_the_same():
    built = {
        "likelihood": comcore.Likelihood(mu=(0.2, 0.8), n_mu=3, model_weight=(0.5, 1.0),
                                         systematic_error=0.001),
        "stop": comcore.StopRule(max_pushes=9, target_radius=0.004),
        "choice": comcore.PushChoice(n_candidates=50, travel=0.02),
    }  # fmt: skip
    for keyword, group in built.items():
        assert option_groups(**dataclasses.asdict(group)) == {keyword: group}
    flat = {k: v for group in built.values() for k, v in dataclasses.asdict(group).items()}
    assert option_groups(**flat) == built


@settings(max_examples=40)
@given(
    max_pushes=st.none() | st.integers(0, 30),
    flip_prob=st.none() | st.floats(1e-3, 0.45),
    n_candidates=st.none() | st.integers(1, 500),
)
def test_only_the_groups_named_are_built(max_pushes, flip_prob, n_candidates):
    flat = {k: v for k, v in (("max_pushes", max_pushes), ("flip_prob", flip_prob),
                              ("n_candidates", n_candidates)) if v is not None}  # fmt: skip
    groups = option_groups(**flat)
    expected = {"stop": "max_pushes", "likelihood": "flip_prob", "choice": "n_candidates"}
    assert set(groups) == {g for g, name in expected.items() if name in flat}
    for keyword, group in groups.items():
        assert getattr(group, expected[keyword]) == flat[expected[keyword]]


def test_the_groups_can_be_passed_to_an_entry_point():
    mask = comcore.Mask(np.pad(np.ones((12, 12), bool), 6))
    session = comcore.ActiveSession(
        mask, model=None, rng=0, **option_groups(max_pushes=0, n_candidates=10)
    )
    assert session.status == "budget" and session.done


def test_building_the_groups_warns_of_nothing():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        option_groups(max_pushes=3, pusher_error=0.002, cone=0.1)


@pytest.mark.parametrize(
    ("flat", "error", "match"),
    [
        ({"max_push": 3}, TypeError, r"unknown option\(s\) \['max_push'\]; the options are \[.*'max_pushes'"),
        ({"likelihood": comcore.Likelihood()}, TypeError, r"unknown option\(s\) \['likelihood'\]"),
        ({"flip_prob": 0.7}, ValueError, r"flip_prob must be in \(0, 0.5\), got 0.7"),
        ({"max_pushes": 2.5}, TypeError, "max_pushes must be an int, got float"),
        ({"selection": "rotation"}, ValueError, "selection must be one of"),
    ],
)
def test_a_bad_flat_name_or_value_is_named(flat, error, match):
    with pytest.raises(error, match=match):
        option_groups(**flat)


def test_every_unknown_name_is_listed_sorted():
    with pytest.raises(TypeError, match=r"unknown option\(s\) \['a', 'b'\]"):
        option_groups(b=1, a=2, max_pushes=3)
