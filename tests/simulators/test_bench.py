"""The simulator benchmark script runs (with small arguments)."""

import pytest

from tests.scripts import run_script

pytest.importorskip("pymunk")
pytest.importorskip("shapely")


def test_bench_sim_speed_runs():
    out = run_script("benchmarks/timing/bench_sim.py", "--pushes", "4", "--repeats", "1")
    assert "pushes/s/core" in out
    assert out.count("median") == 7  # 4 batch sizes, --pushes, push(), pymunk


def test_sim_fidelity_runs():
    out = run_script("benchmarks/accuracy/sim_fidelity.py", "--pushes", "3", "--objects", "Obj1", "--seeds", "1")
    lines = out.splitlines()
    assert sum("returned motion" in line for line in lines) == 4  # 2 engines x 2 cones
    assert "normal push through the CoM" in out
    assert "bit-identical on repeat True" in out
    assert "growing with the lever arm: True" in out


def test_bench_push_frames_runs():
    out = run_script(
        "benchmarks/timing/bench_push_frames.py", "--robots", "quasistatic,pymunk", "--pushes", "1",
        "--repeats", "1", "--travel", "0.01",
    )  # fmt: skip
    lines = out.splitlines()
    assert lines[1].startswith("| robot | camera | speed (m/s) | frames per push |")
    assert lines[3].startswith("| quasistatic | 178 x 175 mask | 0.02 | 10 |")  # 2 cm in 1 s
    assert lines[4].startswith("| pymunk | 178 x 175 mask | 0.02 | 10 |")
