"""benchmarks/timing/bench_core.py runs (as a subprocess, with small arguments)."""

import re

from tests.scripts import run_script


def test_bench_core_script_runs():
    args = ["--repeats", "2", "--actions", "10", "--size", "60"]
    out = run_script("benchmarks/timing/bench_core.py", *args, timeout=120)
    lines = out.splitlines()
    assert lines[0] == "mask (60, 60) with 1792 object pixels, 10 actions"
    for name, line in zip(
        ["estimate_heatmap (Alg. 1)", "estimate_progressive (Alg. 2)"], lines[1:]
    ):
        assert line.startswith(name)
        assert re.search(r"median +\d+\.\d\d ms +\(p10 \d+\.\d\d, p90 \d+\.\d\d, n=2\)$", line)
    assert len(lines) == 3
