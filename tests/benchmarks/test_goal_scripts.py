"""benchmarks/accuracy/goal_bench.py and benchmarks/figures/goal_figure.py run, with small arguments."""

from __future__ import annotations

import json

import pytest

from tests.scripts import run_script

pytest.importorskip("shapely")


def test_goal_bench_runs_and_writes_a_row_per_trial_and_strategy(tmp_path):
    out = tmp_path / "rows.jsonl"
    args = ["--objects", "Obj8", "--friction", "low", "--kinds", "translation"]
    args += ["--strategies", "centroid", "oracle", "--timing", "--out", str(out)]
    table = run_script("benchmarks/accuracy/goal_bench.py", *args)
    rows = [json.loads(line) for line in out.read_text().splitlines()]
    assert [r["strategy"] for r in rows] == ["centroid", "oracle"]
    assert all(r["lower_bound"] == 4 and r["kind"] == "translation" for r in rows)
    assert all(r["status"] in ("reached", "budget", "stuck", "lost") for r in rows)
    assert "| translation | oracle | 1 |" in table and "planning step: median" in table
    assert "largest turn on the way deg (median / max)" in table
    # a translation's largest turn is a |orientation - start| reached: within the summed turns
    assert all(0 <= r["largest_turn_deg"] <= r["turned_deg"] + 1e-9 for r in rows)


def test_goal_bench_bounds_the_turn_with_max_turn(tmp_path):
    out = tmp_path / "rows.jsonl"
    args = ["--objects", "Obj8", "--friction", "low", "--kinds", "pose", "--strategies", "oracle"]
    run_script("benchmarks/accuracy/goal_bench.py", *args, "--max-turn", "10", "--out", str(out))
    (row,) = [json.loads(line) for line in out.read_text().splitlines()]
    assert row["status"] in ("reached", "budget", "stuck", "lost") and row["largest_turn_deg"] >= 0


def test_goal_figure_draws_a_run(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "goal.png"
    title = run_script(
        "benchmarks/figures/goal_figure.py", "--distance", "0.05", "--turn", "10", "--out", str(out)
    )
    assert out.stat().st_size > 10_000 and "pushes" in title


def test_goal_model_error_tabulates_the_rotation_error():
    args = ["--objects", "Obj8", "--friction", "low", "--directions", "2", "--travels", "0.01"]
    table = run_script("benchmarks/accuracy/goal_model_error.py", *args)
    assert table.startswith("24 pushes; rotation error (deg)")
    assert "| 1.00 | 0.00-0.25 |" not in table  # 10 pushes: too few for a bin
    assert "too few pushes to fit" in table
