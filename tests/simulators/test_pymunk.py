"""The optional pymunk engine: runs, is deterministic, and agrees on clear cases."""

import numpy as np
import pytest

pytest.importorskip("pymunk")
pytest.importorskip("shapely")

import comcore
import simulators
from simulators import EngineSettings, PushSimulator

RECT = [(-0.04, -0.025), (0.04, -0.025), (0.04, 0.025), (-0.04, 0.025)]
PYMUNK = EngineSettings(engine="pymunk")


def test_normal_pushes_on_a_box():
    sim = PushSimulator.from_polygon(RECT, mu_contact=0.3, settings=PYMUNK)
    reference = PushSimulator.from_polygon(RECT, mu_contact=0.3)
    cx, cy = sim.com_px
    actions = np.array([(cx - 25, cy - k, cx - 4, cy - k) for k in (0, 3, 6, 9)], float)
    theta = sim.push_motions(actions)[:, 0]
    exact = reference.push_motions(actions)[:, 0]
    assert abs(np.degrees(theta[0])) < 0.5
    assert np.all(theta[1:] < 0) and np.all(np.diff(np.abs(theta)) > 0)
    # The same model, but the joint solver does not converge: pymunk turns the box
    # more than the exact quasi-static solution (measured: about 35 % more here).
    ratio = theta[1:] / exact[1:]
    assert np.all((ratio > 1.0) & (ratio < 2.0))


def test_pymunk_is_deterministic_whatever_came_before():
    sim = simulators.random_simulator("Obj7", rng=0, settings=PYMUNK)
    actions = comcore.sample_pushes(sim.mask, 6, cone=0.3, rng=0)
    first = sim.push_motions(actions)
    again = sim.push_motions(actions[::-1])[::-1]
    assert np.array_equal(first, again)


def test_pymunk_miss_and_record():
    sim = PushSimulator.from_polygon(RECT, settings=PYMUNK)
    cx, cy = sim.com_px
    res = sim.push((cx - 30, cy, cx - 10, cy), record=True)
    assert res.trajectory.shape[1] == 3 and np.allclose(res.trajectory[-1], res.pose)
    miss = sim.push((0, 0, 0, 5))
    assert miss.contact_px is None and tuple(miss.motion) == (0.0, 0.0, 0.0)
