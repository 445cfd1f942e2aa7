"""``comcore bench`` on the command line: tiny runs, options, error messages."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("simulators")

from comcore.bench import PREDICTORS, PredictorSpec
from comcore.cli import main

TINY = ["--objects", "Obj3", "--trials", "1", "--friction", "low", "--candidates", "8",
        "--workers", "1", "--no-progress"]  # fmt: skip


def test_tiny_bench_writes_results_and_report(tmp_path, capsys):
    out = tmp_path / "run"
    args = ["bench", *TINY, "--estimators", "alg2,centroid", "--out", str(out), "--no-figures"]
    assert main(args) == 0
    printed = capsys.readouterr().out
    assert "1 trials x 2 estimators on 1 worker(s)" in printed
    assert "| alg2 | low | 1 |" in printed
    rows = [json.loads(x) for x in (out / "results.jsonl").read_text().splitlines()]
    assert [r["estimator"] for r in rows] == ["alg2", "centroid"]
    assert not (out / "results.partial.jsonl").exists()
    assert "## Table II" in (out / "report.md").read_text()
    meta = json.loads((out / "run.json").read_text())
    assert meta["config"]["objects"] == ["Obj3"] and meta["wall_s"] > 0


def test_parquet_output(tmp_path):
    pytest.importorskip("pyarrow")
    args = ["bench", *TINY, "--estimators", "centroid", "--out", str(tmp_path), "--no-figures",
            "--format", "parquet"]  # fmt: skip
    assert main(args) == 0
    assert (tmp_path / "results.parquet").exists()


def test_estimator_options_on_the_command_line(tmp_path):
    args = ["bench", *TINY, "--estimators", "alg1(threshold=0.3, length_scale=2.0),alg1",
            "--out", str(tmp_path), "--no-figures"]  # fmt: skip
    assert main(args) == 0
    rows = [json.loads(x) for x in (tmp_path / "results.jsonl").read_text().splitlines()]
    assert [r["estimator"] for r in rows] == ["alg1(threshold=0.3, length_scale=2.0)", "alg1"]


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--objects", "Obj99"], "unknown object(s) ['Obj99']"),
        (["--estimators", "alg9"], "unknown estimator 'alg9'"),
        (["--predictor", "crystal-ball"], "predictor must be one of"),
        (["--estimators", "alg1(threshold=)"], "bad options in"),
    ],
)
def test_bad_options_exit_2_with_a_message(tmp_path, capsys, extra, message):
    assert main(["bench", *TINY, "--out", str(tmp_path), *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_unavailable_predictor_is_a_clear_message(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(
        PREDICTORS, "ghost", PredictorSpec("ghost", lambda c: None, 12, lambda: "on branch 'x'")
    )
    assert main(["bench", *TINY, "--out", str(tmp_path), "--predictor", "ghost"]) == 2
    assert "predictor 'ghost' is unavailable: on branch 'x'" in capsys.readouterr().err


@pytest.mark.parametrize("text", ["0", "-2", "two"])
def test_workers_must_be_a_positive_integer(text, capsys):
    with pytest.raises(SystemExit):
        main(["bench", "--workers", text])
    assert "--workers" in capsys.readouterr().err


def test_dask_option_gives_the_local_results(tmp_path, dask_scheduler_address):
    common = ["bench", *TINY, "--estimators", "alg2", "--no-figures"]
    assert main([*common, "--out", str(tmp_path / "local")]) == 0
    dask_run = [*common, "--out", str(tmp_path / "dask"), "--dask", dask_scheduler_address]
    assert main(dask_run) == 0
    local = (tmp_path / "local" / "results.jsonl").read_text()
    assert (tmp_path / "dask" / "results.jsonl").read_text() == local
    meta = json.loads((tmp_path / "dask" / "run.json").read_text())
    assert meta["workers"].startswith("dask ") and meta["cpu_s"] is None
