"""The MuJoCo benchmark scripts run, small (needs comcore[mujoco] and comcore[sim])."""

from __future__ import annotations

import re

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


def test_the_push_frames_benchmark_runs_on_mujoco():
    out = run_script(
        "benchmarks/timing/bench_push_frames.py", "--robots", "mujoco", "--pushes", "1",
        "--travel", "0.005", "--rate", "4", "--camera", "80x60",
    )  # fmt: skip
    lines = out.splitlines()
    row = r"\| mujoco \| 80 x 60 rendered, 178 x 175 grid \| 0\.01 \| [1-9]\d* \|"
    assert re.match(row, lines[3])
    assert lines[4].startswith("mujoco: the pusher in the picture changes a frame's mask by")


def test_the_push_frames_benchmark_compares_a_smaller_shadow_map():
    out = run_script(
        "benchmarks/timing/bench_push_frames.py", "--robots", "mujoco", "--pushes", "1",
        "--travel", "0.005", "--rate", "4", "--camera", "80x60", "--shadow-size", "512",
    )  # fmt: skip
    line = out.splitlines()[5]
    assert re.fullmatch(
        r"mujoco: with a 512 shadow map the masks after the pushes differ from the 4096 "
        r"map's by \[\d+\] px",
        line,
    )
