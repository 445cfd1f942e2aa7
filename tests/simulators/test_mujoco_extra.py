"""Without mujoco: simulators imports, and MujocoRobot names the extra that fixes it."""

from __future__ import annotations

import sys

import pytest

pytest.importorskip("shapely", reason="the simulators need shapely: pip install comcore[sim]")

import simulators


def test_a_missing_mujoco_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # as if not installed
    sim = simulators.PushSimulator.from_polygon([(0, 0), (0.1, 0), (0.1, 0.06), (0, 0.06)])
    with pytest.raises(ImportError, match=r"pip install comcore\[mujoco\]"):
        simulators.MujocoRobot(sim)
