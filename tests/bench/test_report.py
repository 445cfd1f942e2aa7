"""The benchmark's outputs: result files, the paper's tables, the report, the figures."""

from __future__ import annotations

import json

import pytest

from comcore.bench import ROW_FIELDS
from comcore.bench._io import paper_table, read_rows, write_rows
from comcore.bench._report import (
    ALG1_NOTE,
    group_stats,
    markdown_report,
    table_one,
    table_two,
)
from tests.extras import require_simulators


def row(estimator="alg1", obj="Obj1", friction="low", error=1.0, pushes=3, trial=0, **kw):
    base = {k: 0 for k in ROW_FIELDS}
    base.update(
        object=obj, friction=friction, trial=trial, estimator=estimator, predictor="oracle",
        status="ok", error_cm=error, error_px=error / 0.25, pushes_used=pushes,
        total_pushes=pushes, area_cm2=33.0, message="",
    )  # fmt: skip
    base.update(kw)
    return base


def test_paper_tables_hold_twenty_objects_with_the_benchmark_sizes():
    simulators = require_simulators()
    for number in (1, 2):
        table = paper_table(number)
        assert list(table) == list(simulators.BENCHMARK_OBJECTS)
        for name, values in table.items():
            assert values["size_cm2"] == simulators.BENCHMARK_AREAS_CM2[name]
    assert paper_table(2)["Obj8"]["high_push_max"] == 7
    with pytest.raises(ValueError, match="number must be 1 or 2"):
        paper_table(3)


def test_stats_use_population_std_and_sum_the_real_pushes():
    rows = [row(error=1.0, pushes=2), row(error=3.0, pushes=4, total_pushes=16)]
    s = group_stats(rows)[("alg1", "Obj1", "low")]
    assert s["error"] == {"mean": 2.0, "std": 1.0, "min": 1.0, "max": 3.0, "median": 2.0}
    assert s["pushes"]["mean"] == 3.0
    assert s["total_pushes"] == 18


def test_table_one_puts_ours_beside_the_paper_with_the_ratio():
    rows = [row(error=1.0), row(error=2.0, trial=1), row(friction="high", error=0.717)]
    text = table_one(rows)
    line = next(x for x in text.splitlines() if x.startswith("| Obj1 "))
    cells = [c.strip() for c in line.strip("|").split("|")]
    assert cells[:7] == ["Obj1", "33.0 (32.9)", "1.50 (0.742)", "0.50 (0.251)", "1.00 (0.056)",
                         "2.00 (1.691)", "2.02"]  # fmt: skip
    assert cells[-1] == "1.00"  # high friction: 0.717 / 0.717


def test_table_two_reports_errors_pushes_and_both_ratios():
    rows = [row("alg2", error=0.576, pushes=2), row("alg2", error=0.576, pushes=4, trial=1)]
    cells = [c.strip() for c in table_two(rows).splitlines()[2].strip("|").split("|")]
    assert cells[2] == "0.58 (0.576)"
    assert cells[6:10] == ["3.00 (2.688)", "1.00 (0.665)", "2 (1)", "4 (5)"]
    assert cells[10:12] == ["1.00", f"{3 / 2.688:.2f}"]


def test_objects_outside_the_paper_get_no_paper_figures():
    text = table_one([row(obj="MyMug", error=1.0)])
    assert "| MyMug | 33.0 | 1.00 | 0.00 | 1.00 | 1.00 | – |" in text


def test_report_has_the_tables_figures_and_notes():
    rows = [row("alg1"), row("alg2"), row("alg2", status="error", message="ValueError: boom")]
    rows[0]["message"] = "simulator draw 0 failed (x); "
    meta = {"command": "comcore bench --quick", "config": {"predictor": "oracle"}, "wall_s": 3.5,
            "cpu_s": 6.0, "workers": 2, "skipped": {"active": "not built"}}  # fmt: skip
    text = markdown_report(rows, meta, {"Fig. 7": "bench_fig7_pushes.png"})
    for needle in ("`comcore bench --quick`", "Wall time 3.5 s", "## Table I", "## Table II",
                   "![Fig. 7](bench_fig7_pushes.png)", "CPU time 6.0 s, 6.000 s per trial", "`active` skipped: not built",
                   "1 trial(s) redrew", "ValueError: boom"):  # fmt: skip
        assert needle in text, needle
    table_i = text[text.index("## Table I") : text.index("## Table II")]
    assert ALG1_NOTE in table_i and "docs/results/paper.md" in ALG1_NOTE
    assert ALG1_NOTE not in markdown_report(rows[1:], meta, {})  # no Alg. 1, no sentence


@pytest.mark.parametrize("suffix", [".jsonl", ".parquet"])
def test_rows_round_trip(tmp_path, suffix):
    if suffix == ".parquet":
        pytest.importorskip("pyarrow")
    rows = [row(error=0.5), row("alg2", error=1.25, trial=3)]
    path = write_rows(rows, tmp_path / f"results{suffix}")
    assert read_rows(path) == rows
    with pytest.raises(ValueError, match="path must end with one of"):
        write_rows(rows, tmp_path / "results.csv")


def test_jsonl_is_one_object_per_line(tmp_path):
    path = write_rows([row(), row(trial=1)], tmp_path / "r.jsonl")
    lines = path.read_text().splitlines()
    assert len(lines) == 2 and json.loads(lines[1])["trial"] == 1


def test_save_benchmark_writes_results_figures_and_report(tmp_path):
    require_simulators()
    pytest.importorskip("matplotlib")
    from comcore.bench import BenchConfig, run_benchmark
    from comcore.bench._outputs import save_benchmark

    config = BenchConfig(objects=("Obj3",), trials=2, frictions=("low",), candidates=8,
                         estimators=("alg1", "alg2", "alg2-rotation"))  # fmt: skip
    result = run_benchmark(config)
    paths = save_benchmark(result, tmp_path, command="comcore bench (test)")
    for key in ("results", "meta", "report", "fig5", "fig6", "fig7", "errors"):
        assert paths[key].exists() and paths[key].stat().st_size > 0, key
    assert paths["fig5"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    report = paths["report"].read_text()
    assert "(bench_fig5_heatmap.png)" in report and "comcore bench (test)" in report
    meta = json.loads(paths["meta"].read_text())
    assert meta["config"]["candidates"] == 8 and meta["rows"] == 6
    assert read_rows(paths["results"]) == result.rows


def test_the_summary_counts_every_status_by_name():
    # "Status not ok 3 (budget 2, exhausted 1)" read as failures; a budget stop is a usable
    # estimate. The column names every status with its count, ok included.
    from comcore.bench._report import summary_table

    rows = [row("alg1", status="unchecked", trial=t) for t in range(3)]
    rows += [row("active", status=s, trial=t) for t, s in enumerate(["ok", "budget", "budget",
                                                                      "exhausted"])]  # fmt: skip
    table = summary_table(rows).splitlines()
    assert table[0].split("|")[-3].strip() == "Statuses" and "not ok" not in table[0]
    lines = {line.split("|")[1].strip(): line for line in table[2:]}
    assert lines["alg1"].rstrip(" |").split("|")[-2].strip() == "unchecked 3"
    assert lines["active"].rstrip(" |").split("|")[-2].strip() == "budget 2, ok 1, exhausted 1"
    assert group_stats(rows, keys=("estimator",))[("active",)]["statuses"] == {
        "budget": 2, "ok": 1, "exhausted": 1,
    }  # fmt: skip


def test_the_report_says_what_budget_means():
    rows = [row("active", status=s, trial=t) for t, s in enumerate(["ok", "budget"])]
    text = markdown_report(rows, {"config": {}}, {})
    assert "| ok 1, budget 1 |" in text and "not ok" not in text
    assert "`budget`: an active estimator spent its push budget" in text
    assert "a usable estimate, its region wider, not a failure" in text


def test_the_friction_table_counts_every_status_by_name():
    from comcore.bench import friction_table

    rows = [row("alg2", status=s, trial=t, covered=True, push_failures=0)
            for t, s in enumerate(["wide", "wide", "ok", "inconsistent"])]  # fmt: skip
    header, _, low, both = friction_table(rows).splitlines()
    assert header.rstrip(" |").endswith("| statuses")
    assert low.endswith("| wide 2, ok 1, inconsistent 1 |") and both.endswith("| wide 2, ok 1, inconsistent 1 |")


def test_trials_that_raised_give_no_error_figures():
    from comcore.bench._report import summary_table

    rows = [row("alg1", status="error", error=9.0, trial=t) for t in range(2)]
    rows += [row("alg2", status="error", error=9.0, trial=0), row("alg2", error=1.0, trial=1)]
    stats = group_stats(rows, keys=("estimator",))
    assert stats[("alg1",)]["error"] == dict.fromkeys(("mean", "std", "min", "max", "median"))
    assert stats[("alg2",)]["error"]["mean"] == 1.0 and stats[("alg2",)]["errors"] == 1
    lines = {line.split("|")[1].strip(): line for line in summary_table(rows).splitlines()[2:]}
    cells = [c.strip() for c in lines["alg1"].split("|")[1:-1]]
    assert cells[3:7] == ["–"] * 4 and cells[-1] == "2"
    assert "9.000" not in lines["alg2"] and "| 1.000 |" in lines["alg2"]
    assert "| – (" in table_one(rows, "alg1")
