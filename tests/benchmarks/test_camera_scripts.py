"""The camera benchmarks run (as subprocesses, with small arguments)."""

import re

import pytest

from tests.extras import require_simulators
from tests.scripts import run_script

NUMBER = r"\d+\.\d+"


def test_bench_mask_from_image_script_runs():
    args = ["--frames", "2", "--seed", "3", "--conditions", "gradient 60,empty table",
            "--options", "default,otsu,roi", "--width", "320", "--height", "240",
            "--share", "0.02", "--failures"]  # fmt: skip
    lines = run_script("benchmarks/accuracy/bench_mask_from_image.py", *args, timeout=120).splitlines()
    assert lines[0].startswith("mask_from_image: 2 frames per condition, 320 x 240 px, object 2 %")
    assert lines[1] == "| condition | default | otsu | roi |"
    assert re.fullmatch(rf"\| gradient 60 \| 2/2 \({NUMBER}\) \| \d/2 \({NUMBER}\) \| 2/2 \({NUMBER}\) \|", lines[3])
    assert lines[4] == "| empty table | 2/2 | 0/2 | 2/2 |"
    assert lines[5].startswith("cells: frames found / frames")
    for line, option in zip(lines[6:9], ("default", "otsu", "roi")):
        assert re.fullmatch(rf"time per call, {option}: median {NUMBER} ms wall, {NUMBER} ms CPU", line)
    assert "  miss, otsu: empty table: touches the image border x2" in lines[9:]


def test_bench_mask_from_image_refuses_an_unknown_condition():
    with pytest.raises(AssertionError, match="unknown condition 'fog'"):
        run_script("benchmarks/accuracy/bench_mask_from_image.py", "--conditions", "fog")


def test_bench_first_observe_script_runs():
    args = ["--objects", "1", "--repeats", "2", "--width", "200", "--height", "160", "--share", "0.05"]
    lines = run_script("benchmarks/timing/bench_first_observe.py", *args, "--crop", "30", timeout=120)
    lines = lines.splitlines()
    assert re.fullmatch(
        r"first push of 2 sessions \(1 objects x 2, seed 1\): masks \d+-\d+ x \d+-\d+ px, .*",
        lines[0],
    )
    steps = ("ActiveSession(mask)", "next_push()", "observe(mask)", "all three")
    for line, step in zip(lines[1:], steps):
        assert re.fullmatch(rf"  {re.escape(step)}: median \d+ ms wall, \d+ ms CPU", line)
    assert len(lines) == 5


def test_bench_measure_motion_in_a_wide_frame():
    require_simulators()  # the simulator renders the masks
    args = ["--trials", "1", "--objects", "Obj5", "--resolutions", "0.005", "--frame", "400x300"]
    lines = run_script("benchmarks/accuracy/bench_measure_motion.py", *args, timeout=120).splitlines()
    assert lines[0].endswith("images [300, 400] to [300, 400] px")
    assert "  in the camera frame against the masks alone: largest difference of a motion component 0" in lines


def test_bench_tags_script_runs():
    pytest.importorskip("cv2")  # the tags are drawn and found with cv2.aruco
    args = ["--trials", "2", "--tag-sizes", "30", "--frame", "320x240", "--area", "60"]
    lines = run_script("benchmarks/accuracy/bench_tags.py", *args, timeout=120).splitlines()
    assert lines[0].startswith("tag 30 mm (3.75 px per cell) on a star of 60 cm^2, 1 mm/px")
    for line, name in zip(lines[1:5], ("tags", "OpenCV's corners", "exact masks", "masks from")):
        assert line.startswith(f"  {name}")
        assert re.search(rf"rotation median {NUMBER} deg, p90 {NUMBER} deg; translation", line)
    lost = r"  lost frames: 0 of 4; masks flagged ambiguous: .* ms per frame"
    assert re.fullmatch(lost, lines[5])
    assert "mask_from_image refused: 0" in lines[5]


def test_bench_observe_frames_script_runs():
    pytest.importorskip("shapely")
    args = ["--objects", "Obj3", "--repeats", "1", "--resolution", "0.0025", "--margin", "0.1"]
    lines = run_script("benchmarks/timing/bench_observe_frames.py", *args, timeout=120)
    rows = [line for line in lines.splitlines() if line.startswith("| Obj3")]
    assert len(rows) == 1
    assert re.fullmatch(r"\| Obj3 \| \d+ x \d+ \| \d+ / [1-8] \| \d+ \| \d+ \|", rows[0])
