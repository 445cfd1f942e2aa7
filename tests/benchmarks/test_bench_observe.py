"""benchmarks/timing/bench_observe.py runs (as a subprocess, with small arguments)."""

import re

from tests.extras import require_simulators
from tests.scripts import run_script


def test_bench_observe_script_prints_a_row_per_resolution():
    require_simulators()
    args = ["--resolutions", "2.5", "--objects", "Obj3", "--pushes", "1", "--repeats", "1"]
    lines = run_script("benchmarks/timing/bench_observe.py", *args, timeout=120).splitlines()
    assert lines[0].startswith("load average before: ")
    assert lines[1] == "camera 1280 x 720, objects Obj3, 1 pushes, 1 repeats"
    assert re.fullmatch(r"\| 2\.5 \| 1 \| \d+ \| \d+ \| \d+ \|", lines[4])
    assert lines[5].startswith("load average after: ")
