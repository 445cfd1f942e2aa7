"""Tests of the active estimator's options (comcore/active/_options.py, _stop.py, _choice.py)."""

from __future__ import annotations

import ast
import dataclasses
import inspect
from pathlib import Path

import numpy as np
import pytest

import comcore
from comcore import conventions
from comcore.active import _options
from comcore.bench import option_groups

ROOT = Path(__file__).resolve().parents[2]
GROUPS = (comcore.Likelihood, comcore.StopRule, comcore.PushChoice)
FIELDS = {f.name for cls in GROUPS for f in dataclasses.fields(cls)}
ENTRY_POINTS = (
    comcore.estimate_active,
    comcore.ActiveSession,
    comcore.estimate_posterior,
    comcore.calibrate_model_weight,
    comcore.GoalSession,
)
#: The modules of the active estimator: options reach them as groups, never as defaults.
ACTIVE_MODULES = (
    *sorted((ROOT / "comcore" / "active").glob("*.py")),
    ROOT / "comcore" / "camera" / "_pose_tracking.py",
)


#: The group fields an entry point takes as keywords of its own: those it reads, and only them.
OWN_FIELDS = {
    "estimate_active": set(),
    "ActiveSession": set(),
    "estimate_posterior": {"target_radius"},
    "calibrate_model_weight": set(),
    "GoalSession": {"max_pushes", "travel"},
}


@pytest.mark.parametrize("entry", ENTRY_POINTS, ids=lambda f: f.__name__)
def test_an_entry_point_takes_a_field_as_its_own_keyword_only_where_it_reads_it_alone(entry):
    params = inspect.signature(entry).parameters
    assert FIELDS & set(params) == OWN_FIELDS[entry.__name__]
    takes_groups = {"stop", "choice"} & set(params)
    assert not (takes_groups and OWN_FIELDS[entry.__name__]), "a field and its group both"


def test_estimate_posterior_s_target_radius_is_the_stop_rule_s():
    params = inspect.signature(comcore.estimate_posterior).parameters
    assert params["target_radius"].default is comcore.StopRule().target_radius
    with pytest.raises(ValueError, match="target_radius"):
        comcore.estimate_posterior(comcore.Mask(np.ones((4, 4), bool)), pushes=(), target_radius=-1)


def test_estimate_active_takes_the_session_s_keywords():
    """Written once: estimate_active hands its options to ActiveSession."""
    params = inspect.signature(comcore.estimate_active).parameters
    assert [p.kind for p in params.values()][-1] is inspect.Parameter.VAR_KEYWORD
    with pytest.raises(TypeError, match="max_pushes"):
        comcore.estimate_active(comcore.Mask(np.ones((4, 4), bool)), print, max_pushes=3)


@pytest.mark.parametrize(
    ("name", "default"),
    [
        ("pusher_radius", conventions.DEFAULT_PUSHER_RADIUS),
        ("credible", _options.DEFAULT_CREDIBLE),
    ],
)
def test_shared_keywords_take_their_default_from_one_place(name, default):
    for entry in ENTRY_POINTS:
        params = inspect.signature(entry).parameters
        if name in params:
            assert params[name].default is default, f"{entry.__name__}({name}=...)"


@pytest.mark.source
def test_no_function_of_the_active_estimator_defaults_a_grouped_option():
    """A default written in a signature would be a second copy of the group's."""
    assert len(ACTIVE_MODULES) > 10  # the glob found the modules
    for path in ACTIVE_MODULES:
        module = path.relative_to(ROOT)
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            args = node.args
            with_defaults = args.args[len(args.args) - len(args.defaults) :] + [
                a for a, d in zip(args.kwonlyargs, args.kw_defaults) if d is not None
            ]
            named = {a.arg for a in with_defaults} & FIELDS
            if node.name == "estimate_posterior" and named == {"target_radius"}:
                continue  # its own keyword, the stop rule's default (tested above)
            assert not named, f"{module}.{node.name} defaults {sorted(named)}"


def _literals(tree) -> list:
    """Literal numbers and tuples of numbers in code (docstrings are strings: not counted)."""
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Tuple) and node.elts:
            try:
                out.append(ast.literal_eval(node))
            except ValueError:
                pass
    return out


@pytest.mark.source
def test_the_distinctive_defaults_are_written_once_in_comcore():
    distinctive = [
        comcore.Likelihood().theta_noise,
        comcore.Likelihood().translation_error,
        comcore.Likelihood().model_weight,
    ]
    for path in sorted((ROOT / "comcore").rglob("*.py")):
        if path.name in ("_options.py", "_likelihood.py"):  # the groups' own modules
            continue
        found = [v for v in _literals(ast.parse(path.read_text())) if v in distinctive]
        assert not found, f"{path.relative_to(ROOT)} repeats the default(s) {found}"


def test_option_groups_takes_every_field_and_refuses_another_listing_them():
    for keyword, cls in zip(("likelihood", "stop", "choice"), GROUPS):
        for f in dataclasses.fields(cls):
            assert option_groups(**{f.name: f.default}) == {keyword: cls()}
    with pytest.raises(TypeError, match=r"unknown option\(s\) \['max_push'\]; the options are"):
        option_groups(max_push=3)


def test_option_groups_builds_only_the_groups_named():
    groups = option_groups(max_pushes=3, pusher_error=0.002)
    assert groups == {
        "likelihood": comcore.Likelihood(pusher_error=0.002),
        "stop": comcore.StopRule(max_pushes=3),
    }
    assert option_groups() == {}


def test_groups_are_frozen_and_normalised():
    likelihood = comcore.Likelihood(model_weight=0.6, theta_noise=[0.02, 0.1], n_mu=np.int64(4))
    assert likelihood.model_weight == (0.6,) and likelihood.theta_noise == (0.02, 0.1)
    assert type(likelihood.n_mu) is int
    with pytest.raises(dataclasses.FrozenInstanceError):
        likelihood.flip_prob = 0.1  # type: ignore[misc]
    assert comcore.Likelihood(model_weight=[0.5, 1.0]) == comcore.Likelihood(model_weight=(0.5, 1))


@pytest.mark.parametrize(
    ("cls", "kwargs", "error", "match"),
    [
        (comcore.StopRule, {"max_pushes": -1}, ValueError, "max_pushes must be >= 0"),
        (comcore.StopRule, {"min_pushes": 1.5}, TypeError, "min_pushes must be an int"),
        (comcore.StopRule, {"target_radius": -0.01}, ValueError, "target_radius"),
        (comcore.PushChoice, {"n_candidates": 0}, ValueError, "n_candidates must be >= 1"),
        (comcore.PushChoice, {"n_candidates": "200"}, TypeError, "n_candidates must be an int"),
        (comcore.PushChoice, {"travel": float("nan")}, ValueError, "travel"),
        (comcore.Likelihood, {"mu": (1.0, 0.5)}, ValueError, "mu range must have lo <= hi"),
        (comcore.Likelihood, {"model_scales": ()}, ValueError, "model_scales must be positive"),
        (comcore.Likelihood, {"model_scales": "ab"}, TypeError, "model_scales must be a sequence"),
        (comcore.Likelihood, {"theta_tol": -1.0}, ValueError, "theta_tol"),
    ],
)
def test_a_bad_field_is_named_when_the_group_is_built(cls, kwargs, error, match):
    with pytest.raises(error, match=match):
        cls(**kwargs)


def test_a_count_fails_the_same_way_in_every_group():
    """A float count is a TypeError and a negative one a ValueError, whichever option."""
    for cls, name in ((comcore.StopRule, "max_pushes"), (comcore.Likelihood, "n_mu"),
                      (comcore.PushChoice, "n_candidates")):  # fmt: skip
        with pytest.raises(TypeError, match=f"{name} must be an int"):
            cls(**{name: 2.0})
        with pytest.raises(ValueError, match=f"{name} must be >= "):
            cls(**{name: -1})


def test_the_friction_values_are_the_likelihood_s():
    mus = comcore.Likelihood().mus
    assert len(mus) == comcore.Likelihood().n_mu and np.all(np.diff(mus) > 0)
    assert comcore.Likelihood(mu=0.3).mus.tolist() == [0.3]  # known: one value


def test_the_model_error_scales_widen_near_the_force_line():
    likelihood = comcore.Likelihood()
    near, far = likelihood.model_error_scales([0.0, 0.2], [0.01, 0.01])[0]
    absolute, extra = likelihood.theta_noise
    assert near == pytest.approx(absolute + extra) and absolute < far < near
    # a smaller error is more probable, and a wider scale makes a large error less surprising
    small, large = likelihood.model_error_log_density([0.01, 0.2], [0.05] * 2, [0.001] * 2, [0.02] * 2)
    assert small > large
    wide = comcore.Likelihood(theta_noise=(0.1, 0.13))
    assert wide.model_error_log_density([0.2], [0.05], [0.001], [0.02])[0] > large
