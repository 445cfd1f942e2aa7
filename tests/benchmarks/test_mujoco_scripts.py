"""The MuJoCo benchmark scripts run, small (needs comcore[mujoco] and comcore[sim])."""

from __future__ import annotations

import pytest

from tests.scripts import run_script

pytest.importorskip("shapely", reason="the simulators need shapely: pip install comcore[sim]")
pytest.importorskip("pymunk", reason="the simulators need pymunk: pip install comcore[sim]")
pytest.importorskip("mujoco", reason="the MuJoCo robot needs mujoco: pip install comcore[mujoco]")


def test_the_engine_check_runs():
    out = run_script(
        "benchmarks/mujoco/mujoco_engine_check.py", "--objects", "Obj1", "--pushes", "2", "--no-sweep"
    )
    assert "rotation sense" in out and "mj-exact" in out and "pushes/s" in out


def test_the_active_benchmark_runs():
    out = run_script(
        "benchmarks/mujoco/mujoco_active.py", "--objects", "Obj2", "--friction", "low", "--trials", "1",
        "--engines", "mujoco", "exact",
    )  # fmt: skip
    assert "| mujoco | 1 |" in out and "| exact | 1 |" in out


def test_the_hop_check_runs():
    out = run_script("benchmarks/mujoco/mujoco_hop.py")
    assert out.count("feet down") == 4
