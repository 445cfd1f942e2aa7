"""Theta in degrees where every turn is small: estimate_posterior refuses it (comcore.active._posterior).

A recording in degrees whose turns are all under 3 degrees is under pi in every row, so the
check that theta is at most pi passes it; the motion model's evidence tells it (the CLI's side
is tests/cli/test_estimate.py's).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import comcore
from comcore.active._posterior import DEGREES_NATS, theta_degrees_nats
from tests.scripts import run_script

#: The user's object: an L at 5 mm per pixel, its true CoM in pixels (as tests/core/
#: test_user_mistakes.py's), pushed 3 mm at a time: every turn under 3 degrees.
RESOLUTION = 0.005
TRUE_COM = (16.0, 29.0)
MESSAGE = (
    "the motion model and the data disagree, as if theta were in degrees: if it is, "
    "multiply the column by pi/180"
)


def l_mask() -> comcore.Mask:
    image = np.zeros((46, 50), bool)
    image[8:38, 8:18] = True
    image[28:38, 8:40] = True
    return comcore.Mask(image, resolution=RESOLUTION)


@pytest.fixture(scope="module")
def small_turns():
    return small_turn_recording()


def small_turn_recording():
    """Eight 3 mm pushes on the L, motions from the user's model (not comcore's default)."""
    mask = l_mask()
    actions = comcore.sample_pushes(mask, 8, cone=0.3, travel=0.003, rng=1)
    user_model = comcore.LimitSurfaceModel(pusher_radius=0.004, pressure="peaked")
    motions = np.asarray(user_model.predict_hypotheses(mask, actions, [TRUE_COM], 0.4)[0])
    assert np.all(np.abs(motions[:, 0]) < math.radians(3))
    return mask, actions, motions


def test_a_small_turn_recording_in_degrees_is_refused_by_estimate_posterior(small_turns):
    mask, actions, motions = small_turns
    degrees = motions * [180 / math.pi, 1, 1]
    assert np.all(np.abs(degrees[:, 0]) < math.pi)  # the check that theta <= pi passes it
    honest = comcore.estimate_posterior(mask, actions, motions)
    # consistent, its 90 % region wider than the 6 mm target: "wide"
    assert honest.status == "wide" and honest.error_px(TRUE_COM) < 3
    with pytest.raises(ValueError, match=r"motions\[:, 0\]: " + MESSAGE) as e:
        comcore.estimate_posterior(mask, actions, degrees)
    assert "theta_units='deg' converts them" in str(e.value)


def test_theta_units_deg_converts_and_rad_skips_the_check(small_turns):
    mask, actions, motions = small_turns
    degrees = motions * [180 / math.pi, 1, 1]
    honest = comcore.estimate_posterior(mask, actions, motions, bootstrap=0)
    converted = comcore.estimate_posterior(mask, actions, degrees, bootstrap=0, theta_units="deg")
    assert converted.com == pytest.approx(honest.com) and converted.status == honest.status
    vouched = comcore.estimate_posterior(mask, actions, degrees, bootstrap=0, theta_units="rad")
    assert vouched.status != "ok"  # estimated as given: the model cannot explain 57x the turns
    with pytest.raises(ValueError, match=r"theta_units must be one of \('auto', 'rad', 'deg'\)"):
        comcore.estimate_posterior(mask, actions, motions, theta_units="degrees")


def test_the_gain_separates_the_units(small_turns):
    mask, actions, motions = small_turns
    assert theta_degrees_nats(mask, actions, motions) < 0 < DEGREES_NATS
    assert theta_degrees_nats(mask, actions, motions * [180 / math.pi, 1, 1]) > 10 * DEGREES_NATS


def test_without_a_model_nothing_is_checked(small_turns):
    # the Voting Theorem reads the senses alone, which the unit does not change
    mask, actions, motions = small_turns
    est = comcore.estimate_posterior(mask, actions, motions * [180 / math.pi, 1, 1], model=None)
    assert est.status in ("ok", "wide", "inconsistent", "no_evidence")


def test_the_calibration_script_runs():
    pytest.importorskip("shapely")
    args = ["--objects", "Obj3", "--seeds", "0", "--frictions", "low", "--pushes", "6"]
    lines = run_script("benchmarks/calibration/theta_units.py", *args, timeout=120).splitlines()
    assert lines[0].startswith("1 objects x seeds [0] x frictions ['low'], 6 pushes drawn")
    kinds = [line.split(" | ")[0].lstrip("| ") for line in lines[3:6]]
    assert kinds == ["radians, 3 cm", "radians, small", "degrees, small"]
    assert any(line.startswith(f"margin {DEGREES_NATS:g} nats: false alarms ") for line in lines)


def test_calibrate_model_weight_checks_each_records_unit_once(small_turns, monkeypatch):
    mask, actions, motions = small_turns
    from comcore.active import _posterior

    calls = []
    original = _posterior.scaled_gain
    monkeypatch.setattr(_posterior, "scaled_gain", lambda *a: calls.append(1) or original(*a))
    degrees = motions * [180 / math.pi, 1, 1]
    with pytest.raises(ValueError, match=r"records\[0\]: motions\[:, 0\]: " + MESSAGE):
        comcore.active.calibrate_model_weight([(mask, actions, degrees, TRUE_COM)])
    calls.clear()
    comcore.active.calibrate_model_weight([(mask, actions, motions, TRUE_COM)], powers=(0.5, 1.0))
    assert len(calls) == 1  # the first power's posterior checks it, the second does not
