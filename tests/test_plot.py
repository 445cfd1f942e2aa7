"""comcore.plot: a picture of every estimator's Estimate (Agg backend, no pyplot)."""

from __future__ import annotations

import importlib
import subprocess
import sys

import numpy as np
import pytest

import comcore

pytest.importorskip("matplotlib")

import comcore.plot

from .records import actions_of, outcomes_of

MASK = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
ACTIONS = np.array([(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)], float)
MOTIONS = np.array([(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)], float)
TRUE_COM = np.array([10.5, 10.5])


def arrows(ax, *colors):
    """(start, end) of the arrows drawn in one of ``colors``, in drawing order."""
    from matplotlib.text import Annotation

    return [
        (tuple(a.xyann), tuple(a.xy))
        for a in ax.texts
        if isinstance(a, Annotation) and a.arrowprops and a.arrowprops["color"] in colors
    ]


def numbers(ax):
    """The push numbers drawn, as {number: position}."""
    return {t.get_text(): t.get_position() for t in ax.texts if t.get_text().isdigit()}


def toy_push(action):
    c = comcore.contacts(MASK, action)
    sense = comcore.vt.rotation_sense(TRUE_COM, c.point[0], c.normal[0], action.direction, 0.3)
    return comcore.Motion(0.1 * sense, 0.0, 0.0)


def estimates():
    return {
        "alg1": comcore.estimate_heatmap(MASK, ACTIONS, MOTIONS),
        "alg2": comcore.estimate_progressive(MASK, ACTIONS, MOTIONS),
        "centroid": comcore.Estimate(MASK.centroid, MASK.centroid_m, MASK.data),
        "active": comcore.estimate_active(MASK, toy_push, rng=0, stop=comcore.StopRule(max_pushes=4)),
        "posterior": comcore.estimate_posterior(MASK, ACTIONS, MOTIONS),
    }


@pytest.mark.parametrize("name", ["alg1", "alg2", "centroid", "active", "posterior"])
def test_every_estimate_renders_to_a_png(name, tmp_path):
    est = estimates()[name]
    candidates = None if name == "active" else ACTIONS
    ax = comcore.plot.plot_estimate(MASK, est, actions=candidates, truth=TRUE_COM)
    path = tmp_path / f"{name}.png"
    ax.figure.savefig(path)
    assert path.read_bytes()[:4] == b"\x89PNG"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert f"estimate ({est.com[0]:.1f}, {est.com[1]:.1f})" in labels
    assert "true CoM (10.5, 10.5)" in labels


@pytest.mark.parametrize(
    ("name", "key"), [("alg1", "heatmap"), ("active", "posterior"), ("posterior", "posterior")]
)
def test_a_heat_map_or_posterior_colours_the_object(name, key):
    est = estimates()[name]
    ax = comcore.plot.plot_estimate(MASK, est, actions=None if name == "active" else ACTIONS)
    shown = ax.images[-1].get_array()
    values = np.asarray(est.extras[key], float)
    expected = values / values.max()
    assert np.allclose(shown[MASK.data], expected[MASK.data])
    assert shown.mask[~MASK.data].all()  # the background stays uncoloured


def test_the_used_pushes_of_alg2_are_numbered_in_the_order_used():
    est = comcore.estimate_progressive(MASK, ACTIONS, MOTIONS)
    ax = comcore.plot.plot_estimate(MASK, est, actions=ACTIONS)
    red = arrows(ax, comcore.plot.COLORS["used"])
    assert red == [(tuple(a[:2]), tuple(a[2:])) for a in ACTIONS[list(est.used)]]
    marks = numbers(ax)
    assert [marks[str(k + 1)] for k in range(len(est.used))] == [r[0] for r in red]


def test_an_active_estimate_shows_its_executed_pushes_not_candidates_by_index():
    # estimate_active drew its own candidates: est.used indexes them, not the caller's
    # pushes. The executed pushes are its records (Estimate.pushes), in order.
    est = comcore.estimate_active(MASK, toy_push, rng=0, stop=comcore.StopRule(max_pushes=4))
    executed = np.asarray(actions_of(est))
    assert len(executed) > 1
    ax = comcore.plot.plot_estimate(MASK, est, actions=ACTIONS)
    colors = comcore.plot.COLORS
    drawn = arrows(ax, colors["used"], colors["no_evidence"])
    assert drawn == [(tuple(a[:2]), tuple(a[2:])) for a in executed]
    evidence = [o == "evidence" for o in outcomes_of(est)]
    red = arrows(ax, colors["used"])
    assert red == [(tuple(a[:2]), tuple(a[2:])) for a, e in zip(executed, evidence) if e]
    blue = arrows(ax, colors["other"])
    assert len(blue) == len(ACTIONS)  # the caller's pushes were none of them executed
    assert numbers(ax)["1"] == tuple(executed[0, :2])


def test_it_draws_into_a_given_axes():
    from matplotlib.figure import Figure

    ax = Figure().add_subplot()
    est = comcore.estimate_progressive(MASK, ACTIONS, MOTIONS)
    assert comcore.plot.plot_estimate(MASK, est, actions=ACTIONS, ax=ax, title="t") is ax
    assert ax.get_title() == "t"


def test_bad_input_is_named():
    est = comcore.estimate_progressive(MASK, ACTIONS, MOTIONS)
    with pytest.raises(TypeError, match="estimate must be a comcore.Estimate"):
        comcore.plot.plot_estimate(MASK, est.com)
    small = comcore.Mask(np.ones((5, 5), bool))
    with pytest.raises(ValueError, match="estimate.region has shape"):
        comcore.plot.plot_estimate(small, est)
    with pytest.raises(ValueError, match="beyond the 1 actions given"):
        comcore.plot.plot_estimate(MASK, est, actions=ACTIONS[:1])
    with pytest.raises(ValueError, match="truth"):
        comcore.plot.plot_estimate(MASK, est, truth=(np.nan, 1.0))


def test_without_matplotlib_the_import_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib.figure", None)
    monkeypatch.delitem(sys.modules, "comcore.plot")
    with pytest.raises(ImportError, match=r"pip install comcore\[plot\]"):
        importlib.import_module("comcore.plot")


def test_import_comcore_does_not_import_the_plotting_module():
    code = "import sys, comcore; print('matplotlib' in sys.modules, 'comcore.plot' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.stdout.split() == ["False", "False"], done.stderr
