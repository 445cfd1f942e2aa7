"""The simulator benchmark script runs (with small arguments)."""

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("pymunk")
pytest.importorskip("shapely")

ROOT = Path(__file__).resolve().parents[1]


def _run_script(name, *args):
    """Run benchmarks/<name> with small arguments; its stdout."""
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / name), *args],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={"PYTHONPATH": str(ROOT), "PATH": ""},
        timeout=120,
        check=True,
    )
    return out.stdout


def test_bench_sim_speed_runs():
    out = _run_script("bench_sim.py", "--pushes", "4", "--repeats", "1")
    assert "pushes/s/core" in out
    assert out.count("median") == 7  # 4 batch sizes, --pushes, push(), pymunk


def test_sim_fidelity_runs():
    out = _run_script("sim_fidelity.py", "--pushes", "3", "--objects", "Obj1", "--seeds", "1")
    lines = out.splitlines()
    assert sum("returned motion" in line for line in lines) == 4  # 2 engines x 2 cones
    assert "normal push through the CoM" in out
    assert "bit-identical on repeat True" in out
    assert "growing with the lever arm: True" in out
