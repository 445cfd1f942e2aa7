"""benchmarks/accuracy/eval_motion_model.py and bench_motion_model.py run (subprocesses, tiny arguments)."""

import pytest

from tests.scripts import run_script

pytest.importorskip("shapely")  # both scripts run the simulator
pytest.importorskip("trimesh")


def test_eval_motion_model_runs():
    out = run_script(
        "benchmarks/accuracy/eval_motion_model.py", "--objects", "Obj19", "--trials", "1", "--pushes", "2",
        "--engines", "quasistatic", "--models", "limit-surface,ellipsoid", "--fit-scales",
        "--scales", "0.01,0.1,0.001,0.05",
    )  # fmt: skip
    assert out.startswith("2 trials x 2 pushes, seed 0")
    assert out.count("| quasistatic | low | limit-surface |") == 2  # all, and Obj19 only
    assert "fitted a=" in out and "given scales: nll/push" in out


def test_bench_motion_model_runs():
    out = run_script("benchmarks/timing/bench_motion_model.py", "--object", "Obj1", "--pushes", "1", "--repeats", "1",
              "--no-ellipsoid")  # fmt: skip
    assert "LimitSurfaceModel   one step: median" in out
