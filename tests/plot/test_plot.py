"""comcore.plot: a picture of every estimator's Estimate (Agg backend, no pyplot)."""

from __future__ import annotations

import importlib
import subprocess
import sys

import numpy as np
import pytest

import comcore
from tests.scripts import run_script

pytest.importorskip("matplotlib")

import comcore.plot
from tests.extras import require_simulators
from tests.records import actions_of, outcomes_of

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


def behind_start(point, push) -> bool:
    """Whether ``point`` lies on the push's line, before its start (where numbers go)."""
    start, end = np.asarray(push[:2], float), np.asarray(push[2:], float)
    unit = (end - start) / np.hypot(*(end - start))
    offset = np.asarray(point, float) - start
    return abs(offset[0] * unit[1] - offset[1] * unit[0]) < 1e-6 and offset @ unit < 0


def toy_push(action):
    c = comcore.geometry.contacts(MASK, action)
    sense = comcore.vt.predicted_sense(TRUE_COM, c.point[0], c.normal[0], action.direction, 0.3)
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
    values = np.asarray(getattr(est, key).image, float)
    expected = values / values.max()
    assert np.allclose(shown[MASK.data], expected[MASK.data])
    assert shown.mask[~MASK.data].all()  # the background stays uncoloured


def test_the_used_pushes_of_alg2_are_numbered_in_the_order_used():
    est = comcore.estimate_progressive(MASK, ACTIONS, MOTIONS)
    ax = comcore.plot.plot_estimate(MASK, est, actions=ACTIONS)
    red = arrows(ax, comcore.plot.COLORS["used"])
    assert red == [(tuple(a[:2]), tuple(a[2:])) for a in ACTIONS[list(est.used)]]
    marks = numbers(ax)
    assert sorted(marks, key=int) == [str(k + 1) for k in range(len(est.used))]
    for k, push in enumerate(ACTIONS[list(est.used)]):
        assert behind_start(marks[str(k + 1)], push), k


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
    marks = numbers(ax)
    assert sorted(marks, key=int) == [str(k + 1) for k in range(len(executed))]
    assert all(behind_start(marks[str(k + 1)], push) for k, push in enumerate(executed))


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


@pytest.fixture(scope="module")
def camera_session():
    """An ActiveSession on a SimulatedRobot's wide camera frame (the README's loop)."""
    simulators = require_simulators()
    robot = simulators.SimulatedRobot(simulators.random_simulator("Obj2", "low", rng=0), rng=0)
    first = robot.camera_mask()
    session = comcore.ActiveSession(first, pusher_radius=0.004, rng=0)
    while not session.done:
        robot.execute(session.next_push())
        session.observe(robot.camera_mask())
    return first, session.estimate(), robot.true_com_px


def test_a_camera_frame_session_is_framed_on_the_object(camera_session):
    # The user's case: the object drawn small in a large empty axes.
    first, est, truth = camera_session
    rows, cols = np.nonzero(first.data)
    assert first.data.mean() < 0.02  # the object fills under 2 % of the camera frame
    ax = comcore.plot.plot_estimate(first, est, truth=truth)
    (x0, x1), (y1, y0) = ax.get_xlim(), ax.get_ylim()
    assert x0 < cols.min() and cols.max() < x1 and y0 < rows.min() and rows.max() < y1
    size = max(np.ptp(cols), np.ptp(rows)) + 1
    assert max(x1 - x0, y1 - y0) < 3 * size  # the object and its pushes, with a margin
    whole = comcore.plot.plot_estimate(first, est, truth=truth, view="image")
    assert whole.get_xlim() == (-0.5, first.shape[1] - 0.5)
    with pytest.raises(ValueError, match="view must be 'object' or 'image', got 'camera'"):
        comcore.plot.plot_estimate(first, est, view="camera")


def test_push_numbers_sit_off_the_object_and_apart(camera_session):
    first, est, truth = camera_session
    ax = comcore.plot.plot_estimate(first, est, truth=truth)
    marks = numbers(ax)
    executed = actions_of(est)
    assert sorted(marks, key=int) == [str(k + 1) for k in range(len(executed))]
    points = np.array([marks[str(k + 1)] for k in range(len(executed))])
    assert not first.contains(points).any()  # never over the object, the region or the markers
    gaps = np.hypot(*(points[:, None] - points[None]).transpose(2, 0, 1))
    assert (gaps[np.triu_indices(len(points), 1)] > 1.0).all()


def test_every_used_push_is_numbered_for_every_method():
    # Numbers used to stop at 15 pushes: a 40-push recording's posterior had none.
    actions = comcore.sample_pushes(MASK, 40, cone=0.3, rng=0)
    lever = comcore.geometry.signed_line_distance([TRUE_COM], actions)[0]
    motions = np.column_stack([0.01 * lever, np.zeros(40), np.zeros(40)])
    for est in (comcore.estimate_heatmap(MASK, actions, motions),
                comcore.estimate_posterior(MASK, actions, motions)):  # fmt: skip
        executed, _ = comcore.plot.executed_pushes(est, actions)
        ax = comcore.plot.plot_estimate(MASK, est, actions=actions, truth=TRUE_COM)
        marks = numbers(ax)
        assert sorted(marks, key=int) == [str(k + 1) for k in range(len(executed))]
        assert len(executed) >= 30
        assert all(behind_start(marks[str(k + 1)], push) for k, push in enumerate(executed))


def test_the_credible_region_is_outlined_and_named():
    from matplotlib.collections import LineCollection

    est = comcore.estimate_posterior(MASK, ACTIONS, MOTIONS)
    ax = comcore.plot.plot_estimate(MASK, est, actions=ACTIONS)
    outlines = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert len(outlines) == 1
    drawn = np.asarray(outlines[0].get_segments())
    assert np.array_equal(drawn, comcore.plot.region_outline(est.region))
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "90 % credible region" in labels  # the level, as comcore estimate's text says


def test_the_legend_names_the_regions_level_not_its_share_of_the_unblurred_posterior():
    # The region is read from the bagged, blurred posterior (region_image): in the posterior
    # itself it holds more than its 90 % (97 % here), which the legend once said.
    est = comcore.estimate_posterior(MASK, ACTIONS, MOTIONS, model=None)
    raw = est.posterior.image[est.region].sum() / est.posterior.image.sum()
    read = est.posterior.region_image[est.region].sum() / est.posterior.region_image.sum()
    assert f"{100 * raw:.0f}" != "90" and f"{100 * read:.0f}" == "90"
    for credible, expected in ((None, "90 % credible region"), (0.8, "80 % credible region")):
        ax = comcore.plot.plot_estimate(MASK, est, actions=ACTIONS, credible=credible)
        assert expected in [t.get_text() for t in ax.get_legend().get_texts()]


def test_numbers_replace_the_push_order_and_must_match_the_pushes():
    est = comcore.estimate_progressive(MASK, ACTIONS, MOTIONS)
    lines = [10 + i for i in est.used]
    ax = comcore.plot.plot_estimate(MASK, est, actions=ACTIONS, numbers=lines)
    assert sorted(numbers(ax), key=int) == [str(v) for v in sorted(lines)]
    with pytest.raises(ValueError, match=r"numbers must hold one number per push drawn numbered"):
        comcore.plot.plot_estimate(MASK, est, actions=ACTIONS, numbers=[1])


def test_region_outline_runs_along_pixel_edges():
    region = np.zeros((4, 5), bool)
    region[1:3, 1:4] = True  # 3 x 2 pixels: a 3 x 2 rectangle of unit edges
    segments = comcore.plot.region_outline(region)
    assert len(segments) == 2 * (3 + 2)
    ends = segments.reshape(-1, 2)
    assert ends[:, 0].min() == 0.5 and ends[:, 0].max() == 3.5
    assert ends[:, 1].min() == 0.5 and ends[:, 1].max() == 2.5
    assert np.allclose(np.hypot(*(segments[:, 1] - segments[:, 0]).T), 1.0)


def test_numbers_step_back_from_each_other_and_from_the_markers():
    pushes = [(0, 0, 10, 0)] * 3
    placed = comcore.plot.number_positions(pushes, size=2.0, avoid=[(-1.0, 0.0)])
    assert placed.tolist() == [[-3.0, 0.0], [-5.0, 0.0], [-7.0, 0.0]]


def test_a_status_other_than_ok_is_in_the_title():
    est = comcore.estimate_heatmap(MASK, ACTIONS, MOTIONS)
    ax = comcore.plot.plot_estimate(MASK, est, actions=ACTIONS)
    assert ax.get_title().endswith(", status unchecked")


def test_the_robot_figure_of_docs_is_made_by_its_script(tmp_path):
    require_simulators()
    path = tmp_path / "robot_session.png"
    out = run_script("docs/figures/make_robot_figure.py", str(path))
    assert out.startswith(f"saved {path}: status ")
    assert path.read_bytes()[:4] == b"\x89PNG"
