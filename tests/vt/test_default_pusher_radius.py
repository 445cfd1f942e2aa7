"""Every entry point defaults to the one pusher radius of comcore.conventions."""

import inspect

import numpy as np
import pytest

import comcore
from comcore import vt
from comcore.conventions import DEFAULT_PUSHER_RADIUS
from tests.extras import require_simulators


@pytest.mark.parametrize(
    "entry",
    [vt.region, comcore.estimate_progressive, comcore.estimate_posterior],
    ids=lambda f: f.__name__,
)
def test_entry_points_default_to_the_conventions_pusher_radius(entry):
    default = inspect.signature(entry).parameters["pusher_radius"].default
    assert default == DEFAULT_PUSHER_RADIUS


def test_the_corner_push_holds_the_true_com_with_the_defaults():
    # Obj1, low friction, a 15.6 mm push in a 0.625 rad cone: the disc touches the corner
    # before the leading point would, and the sense the point pusher reads excludes the CoM.
    simulators = require_simulators()
    sim = simulators.random_simulator("Obj1", "low", rng=4769)
    action = comcore.sample_pushes(sim.mask, 1, cone=0.625, travel=0.0156, rng=4769)[0]
    theta = float(sim.push(action).motion[0])
    col, row = np.round(sim.com_px).astype(int)
    assert not vt.region(sim.mask, action, theta, mu=None, pusher_radius=0.0)[row, col]
    assert vt.region(sim.mask, action, theta, mu=None)[row, col]
