"""``comcore bench`` on the command line: tiny runs, options, error messages."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("shapely")  # the bench runs the simulator (comcore[sim])
pytest.importorskip("trimesh")

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


def test_an_estimator_option_typo_is_refused_before_the_first_trial(tmp_path, capsys, monkeypatch):
    import comcore.bench._runner as runner

    def no_trial(spec):
        raise AssertionError("a trial ran")

    monkeypatch.setattr(runner, "run_trial", no_trial)
    args = ["bench", *TINY, "--out", str(tmp_path), "--estimators", "alg2(min_scor=0.5)"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "alg2 has no option min_scor (did you mean min_score?)" in err
    assert "Traceback" not in err and not (tmp_path / "results.partial.jsonl").exists()


@pytest.mark.parametrize(
    ("label", "message"),
    [
        ("alg1(threshold=2)", "threshold must be in [0, 1], got 2.0"),
        ("alg2(min_score=5)", "min_score must be in [0, 1], got 5.0"),
        ("alg2-rotation(mu=-1)", "mu must be >= 0, got -1.0"),
        ("active(target_radius=-1)", "target_radius must be a finite number > 0"),
        ("active(model='crystal')", "model must be one of"),
        ("active-robot(observe='sonar')", "observe must be one of"),
    ],
)
def test_a_bad_option_value_is_refused_before_the_first_trial(
    tmp_path, capsys, monkeypatch, label, message
):
    import comcore.bench._runner as runner

    def no_trial(spec):
        raise AssertionError("a trial ran")

    monkeypatch.setattr(runner, "run_trial", no_trial)
    args = ["bench", *TINY, "--out", str(tmp_path), "--estimators", label]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert f"estimators: {label!r}: {message}" in err
    assert "Traceback" not in err and not (tmp_path / "results.partial.jsonl").exists()


@pytest.mark.parametrize("extra", [[], ["--conditions", "exact"]])
def test_an_unwritable_out_folder_is_one_line_not_a_traceback(tmp_path, capsys, extra):
    blocker = tmp_path / "file.txt"
    blocker.write_text("a file where the folder should go")
    args = ["bench", *TINY, "--estimators", "centroid", "--no-figures",
            "--out", str(blocker / "run"), *extra]  # fmt: skip
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"comcore bench: --out {blocker / 'run'}: cannot write there (")
    assert err.count("\n") == 1


@pytest.mark.parametrize(
    ("module", "extra", "alternative"),
    [("tqdm", "bench", "--no-progress"), ("shapely", "sim", None), ("matplotlib", "plot", "--no-figures")],
)
def test_a_missing_extra_is_named_with_its_install(tmp_path, capsys, monkeypatch, module, extra, alternative):
    monkeypatch.setitem(sys.modules, module, None)
    args = ["bench", "--objects", "Obj3", "--trials", "1", "--out", str(tmp_path)]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert f"needs {module}, not installed: pip install comcore[{extra}]" in err
    assert (alternative in err) if alternative else "(or pass" not in err
    assert not list(tmp_path.iterdir())


def test_without_a_progress_bar_tqdm_is_not_needed(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    args = ["bench", *TINY, "--estimators", "centroid", "--no-figures", "--out", str(tmp_path)]
    assert main(args) == 0


def test_demo_without_the_simulator_extra_names_it(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "shapely", None)
    assert main(["demo", "--pushes", "5"]) == 2
    err = capsys.readouterr().err
    assert "pip install comcore[sim]" in err and "Traceback" not in err


@pytest.mark.parametrize(
    ("option", "value", "message"),
    [("--pushes", "-1", "expected a positive integer, got -1"),
     ("--object", "Obj99", "unknown object 'Obj99'"),
     ("--cone", "nan", "expected radians in [0, pi/2), got nan"),
     ("--cone", "2", "expected radians in [0, pi/2), got 2"),
     ("--seed", "-3", "expected an integer >= 0, got -3")],
)  # fmt: skip
def test_demo_bad_options_are_argparse_errors_naming_the_option(capsys, option, value, message):
    with pytest.raises(SystemExit) as e:
        main(["demo", option, value])
    err = capsys.readouterr().err
    assert e.value.code == 2 and f"argument {option}: {message}" in err and "Traceback" not in err


RESUMABLE = ["bench", "--objects", "Obj3", "--trials", "5", "--friction", "low", "--candidates",
             "8", "--workers", "1", "--no-progress", "--estimators", "alg2,centroid",
             "--no-figures"]  # fmt: skip


def test_resume_finishes_an_interrupted_run_with_the_rows_of_a_whole_run(tmp_path, monkeypatch, capsys):
    import comcore.bench._runner as runner

    whole = tmp_path / "whole"
    assert main([*RESUMABLE, "--out", str(whole)]) == 0
    real, calls = runner.run_trial, []

    def interrupted_at_trial_3(spec):
        if spec.trial == 3:
            raise KeyboardInterrupt
        calls.append(spec.trial)
        return real(spec)

    monkeypatch.setattr(runner, "run_trial", interrupted_at_trial_3)
    out = tmp_path / "cut"
    assert main([*RESUMABLE, "--out", str(out)]) == 130
    err = capsys.readouterr().err
    assert "interrupted after 3 of 5 trials" in err and "--resume" in err
    assert (out / "results.partial.jsonl").read_text().count("\n") == 6
    assert not (out / "results.jsonl").exists()

    def counted(spec):
        calls.append(spec.trial)
        return real(spec)

    monkeypatch.setattr(runner, "run_trial", counted)
    calls.clear()
    assert main([*RESUMABLE, "--out", str(out), "--resume"]) == 0
    assert calls == [3, 4]  # only the trials the first run did not finish
    assert "(6 rows kept from the interrupted run)" in capsys.readouterr().out
    assert (out / "results.jsonl").read_text() == (whole / "results.jsonl").read_text()
    assert not (out / "results.partial.jsonl").exists() and not (out / "run.partial.json").exists()


def test_resume_refuses_other_options_or_nothing_to_resume(tmp_path, monkeypatch, capsys):
    import comcore.bench._runner as runner

    real = runner.run_trial

    def interrupted_at_trial_1(spec):
        if spec.trial == 1:
            raise KeyboardInterrupt
        return real(spec)

    monkeypatch.setattr(runner, "run_trial", interrupted_at_trial_1)
    assert main([*RESUMABLE, "--out", str(tmp_path / "a")]) == 130
    capsys.readouterr()
    assert main([*RESUMABLE, "--out", str(tmp_path / "a"), "--resume", "--seed", "1"]) == 2
    assert "--resume: the run in" in capsys.readouterr().err
    assert main([*RESUMABLE, "--out", str(tmp_path / "b"), "--resume"]) == 2
    assert "--resume: no interrupted run in" in capsys.readouterr().err


def test_ctrl_c_stops_local_workers_at_once_and_keeps_the_finished_rows(tmp_path):
    out = tmp_path / "run"
    cmd = [sys.executable, "-m", "comcore", "bench", "--objects", "Obj3", "--trials", "60",
           "--friction", "low", "--candidates", "8", "--estimators", "alg2,centroid",
           "--workers", "2", "--out", str(out), "--no-figures", "--no-progress"]  # fmt: skip
    root = str(Path(__file__).resolve().parents[2])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([root, os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    partial = out / "results.partial.jsonl"
    deadline = time.monotonic() + 60
    while not (partial.exists() and partial.read_text().count("\n") >= 2):
        assert proc.poll() is None and time.monotonic() < deadline, "no row came"
        time.sleep(0.05)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    assert time.monotonic() - sent < 2.0
    assert proc.returncode == 130 and "Traceback" not in err
    assert "--resume finishes the run" in err
    rows = [json.loads(x) for x in partial.read_text().splitlines()]
    assert rows and len(rows) % 2 == 0  # whole trials only: a row per estimator
    assert len(rows) < 120  # it stopped: the queued trials were not all run


def test_version_is_printed(capsys):
    import comcore

    with pytest.raises(SystemExit) as e:
        main(["--version"])
    assert e.value.code == 0
    assert capsys.readouterr().out.strip() == f"comcore {comcore.__version__}"


def test_demo_runs_a_whole_session_and_prints_the_estimate_its_region_and_the_truth(capsys):
    import simulators

    assert main(["demo", "--seed", "0"]) == 0
    out = capsys.readouterr().out.splitlines()
    pushes = [line for line in out if line.startswith("  push ")]
    assert 1 <= len(pushes) <= 5  # the session's default budget
    estimate, region, truth = out[-3:]
    assert estimate.startswith("estimate: CoM (") and f"after {len(pushes)} pushes" in estimate
    assert region.startswith("90 % region: ") and " cm^2 (radius " in region
    sim = simulators.random_simulator("Obj7", friction="low", rng=np.random.default_rng(0))
    x, y = simulators.SimulatedRobot(sim).true_com_px  # in the camera's first frame
    assert truth.startswith(f"true CoM: ({x:.1f}, {y:.1f}) px; the estimate is ")


def test_demo_compare_shows_the_active_estimator_beside_the_papers_and_alg1_is_not_ok(capsys):
    from comcore.bench._report import ALG1_NOTE

    assert main(["demo", "--compare", "--pushes", "20", "--seed", "1"]) == 0
    out = capsys.readouterr().out
    table = [line for line in out.splitlines() if line.startswith("  ") and " CoM (" in line]
    lines = {line.split(" CoM (")[0].strip(): line for line in table}
    assert list(lines) == ["centroid (baseline)", "Alg. 1 heat map", "Alg. 2 progressive",
                           "active (its own pushes)"]  # fmt: skip
    assert lines["Alg. 1 heat map"].endswith("status unchecked")
    assert "status unchecked: Alg. 1 has no test of its evidence" in out
    assert lines["centroid (baseline)"].endswith("status baseline")
    active_pushes = int(lines["active (its own pushes)"].split(" pushes ")[1].split()[0])
    assert 1 <= active_pushes <= 5  # the active estimator's default budget
    assert ALG1_NOTE in out and "docs/results/paper.md" in ALG1_NOTE


def test_bench_help_lists_every_estimator_with_its_options(capsys):
    from comcore.bench import ESTIMATORS

    with pytest.raises(SystemExit) as e:
        main(["bench", "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    listing = out[out.index("estimators (--estimators") :]
    for name in ESTIMATORS:
        assert f"\n  {name}: " in listing, name
    alg1 = listing[listing.index("\n  alg1: ") :].split("\n  alg2: ")[0]
    assert "options: length_scale, threshold" in alg1
    active = " ".join(listing[listing.index("\n  active: ") :].split("\n  active-robot:")[0].split())
    assert "max_pushes" in active and "target_radius" in active
    assert "rng" not in active.split("options:")[1].replace(",", " ").split()  # the bench sets it
    assert "predictors (--predictor" in listing and "oracle, ellipsoid, anp" in listing


def test_quick_runs_the_active_estimator_beside_the_papers_unless_told_otherwise():
    from comcore.bench._trial import DEFAULT_ESTIMATORS
    from comcore.bench.command import _config
    from comcore.cli import build_parser

    parse = build_parser().parse_args
    quick = _config(parse(["bench", "--quick"]))
    assert quick.estimators == (*DEFAULT_ESTIMATORS, "active") and quick.trials == 20
    assert _config(parse(["bench"])).estimators == DEFAULT_ESTIMATORS
    chosen = _config(parse(["bench", "--quick", "--estimators", "alg2,centroid"]))
    assert chosen.estimators == ("alg2", "centroid")
