"""benchmarks/accuracy/bench_measure_motion.py runs (as a subprocess, with small arguments)."""

import re

import pytest

from tests.scripts import run_script


def test_bench_measure_motion_script_runs():
    pytest.importorskip("shapely")  # the simulator renders the masks
    args = ["--trials", "1", "--objects", "Obj5", "--resolutions", "0.005", "--per-object"]
    out = run_script("benchmarks/accuracy/bench_measure_motion.py", *args, timeout=120)
    lines = out.splitlines()
    assert lines[0].startswith(
        "resolution 5 mm/px: 2 pushes (1 objects x 2 friction classes x 1, seed 1), images"
    )
    number = r"\d+\.\d+"
    assert re.fullmatch(
        rf"  theta error, 2 unflagged: median {number} deg, p95 {number} deg, max {number} deg",
        lines[1],
    )
    assert re.fullmatch(rf"  translation error, all: median {number} px, .*", lines[2])
    assert lines[3] == "  flagged ambiguous: 0 (none)"
    assert re.fullmatch(rf"  rotation visibility: {number} \(Obj5\) to {number} \(Obj5\)", lines[4])
    assert lines[5].startswith("  pushes redrawn because the object left the camera image: ")
    assert lines[6].startswith("  symmetry reported: {1: 2}")
    assert re.fullmatch(
        rf"  time per call: median {number} ms wall \(p10 {number}, p90 {number}\), {number} ms CPU",
        lines[7],
    )
    assert lines[8].startswith("    Obj5: theta median ")
    assert len(lines) == 9


def test_bench_measure_motion_calibration_runs():
    args = ["--calibrate", "5", "--seed", "0"]
    out = run_script("benchmarks/accuracy/bench_measure_motion.py", *args, timeout=120)
    lines = out.splitlines()
    assert re.fullmatch(
        r"5 random polygons \(seed 0, 8 to 50 px\): 68th percentile of \|theta error\| \* "
        r"sqrt\(information\) \d\.\d{3} px; residual_px median \d\.\d{3}, 90th percentile \d\.\d{3} px",
        lines[0],
    )
    assert re.fullmatch(r"  theta error, \d unflagged: median .* deg, max \d+\.\d{3} deg", lines[1])
    assert re.fullmatch(r"  disc radius 6 px: visibility \d\.\d\d", lines[2])
    assert len(lines) == 9
