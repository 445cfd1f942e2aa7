"""benchmarks/accuracy/fuzz_api.py: its classifier on known cases, its plan, and a tiny run."""

from __future__ import annotations

import importlib.util
import json
import math
import sys

import pytest

from tests.scripts import ROOT, run_script

SCRIPT = "benchmarks/accuracy/fuzz_api.py"


@pytest.fixture(scope="module")
def fuzz():
    spec = importlib.util.spec_from_file_location("fuzz_api", ROOT / SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules["fuzz_api"] = module  # its dataclasses look their module up there
    try:
        spec.loader.exec_module(module)
        yield module
    finally:
        del sys.modules["fuzz_api"]


def test_a_clear_refusal_names_the_argument_singular_or_plural(fuzz):
    assert fuzz.names_argument("n must be a whole number >= 1, got 2.5", ("n",))
    assert fuzz.names_argument("actions must have shape (n, 4), got (3,)", ("action",))
    assert not fuzz.names_argument("could not convert string to float: 'abc'", ("travel",))
    assert not fuzz.names_argument("maximum travelled too far", ("travel",))  # a whole word only


def test_the_classes_of_known_outcomes(fuzz):
    classify = fuzz.classify
    clear = dict(clear_type=True, names=("x",), raised_in="comcore._checks")
    assert classify("raised", fuzz.R, message="x must be finite", **clear) == "refused_clearly"
    assert classify("raised", fuzz.R, message="bad input", **clear) == "unclear_error"
    numpy_raised = dict(clear, raised_in="numpy.core.shape_base")
    assert classify("raised", fuzz.R, message="x: broadcast", **numpy_raised) == "unclear_error"
    assert (
        classify("raised", fuzz.A, message="x", clear_type=False, names=("x",)) == "unclear_error"
    )
    assert classify("raised", fuzz.VALID, message="x", **clear) == "baseline_failed"
    assert classify("returned", fuzz.R) == "silent"
    assert classify("returned", fuzz.A) == "accepted"
    assert classify("returned", fuzz.A, problem="NaN or inf at result.com") == "silent"
    assert classify("timeout", fuzz.A) == "hang"
    assert classify("died", fuzz.A) == "crash"


def test_nonfinite_values_are_found_with_their_path(fuzz):
    from collections import namedtuple

    import numpy as np

    motion = namedtuple("motion", "theta tx ty")
    assert fuzz.find_nonfinite(motion(0.1, math.nan, 0.0)) == "result.tx"
    assert fuzz.find_nonfinite({"a": [1.0, np.array([0.0, np.inf])]}) == "result['a'][1]"
    assert fuzz.find_nonfinite((1.0, "nan", None, True)) is None


def test_the_plan_is_a_function_of_the_seed_and_n(fuzz):
    targets = fuzz.api_targets()
    first = fuzz.plan(targets, 0, 300)
    assert first == fuzz.plan(targets, 0, 300)
    assert first[:100] == fuzz.plan(targets, 0, 100)  # a case id is the same for every n
    assert first != fuzz.plan(targets, 1, 300)
    assert [c.arg for c in first[: len(targets)]] == [None] * len(targets)  # baselines first
    every = fuzz.plan(targets, 0, None)
    assert len(every) == len(targets) + sum(len(a.catalogue()) for t in targets for a in t.args)


def test_every_catalogue_value_is_labelled(fuzz):
    for target in fuzz.api_targets():
        for arg in target.args:
            for odd in arg.catalogue():
                assert odd.verdict in (fuzz.R, fuzz.A), (target.name, arg.name, odd.label)


def test_the_toy_targets_land_in_their_classes_through_the_pool(tmp_path):
    out = tmp_path / "rows.json"
    args = ["--targets", "toy", "--timeout", "2", "--memory-gb", "2", "--json", str(out)]
    text = run_script(SCRIPT, *args, timeout=60)
    rows = json.loads(out.read_text())["rows"]
    baselines = [r for r in rows if r["argument"] == "(baseline)"]
    assert {r["class"] for r in baselines} == {"accepted"}
    mutated = {r["function"]: r for r in rows if r["argument"] != "(baseline)"}
    expected = {
        "toy_index_error": "unclear_error",  # an IndexError
        "toy_nan": "silent",  # a NaN back for a must_refuse NaN
        "toy_nan_for_odd": "silent",  # a NaN back for a may_accept value
        "toy_sleep": "hang",
        "toy_clear": "refused_clearly",  # a ValueError naming x
        "toy_vague": "unclear_error",  # a ValueError naming nothing
        "toy_numpy_error": "unclear_error",  # numpy's broadcast error
        "toy_accepts": "accepted",
        "toy_silent": "silent",  # a must_refuse 1e300 returned
        "toy_mutates": "accepted",
        "toy_dies": "crash",
        "toy_allocates": "unclear_error",  # MemoryError under the address-space limit
    }
    assert {name: r["class"] for name, r in mutated.items()} == expected
    assert mutated["toy_mutates"]["mutated"] and not mutated["toy_accepts"]["mutated"]
    assert mutated["toy_allocates"]["exception"] == "MemoryError"
    assert "| hang | 1 |" in text and "| crash | 1 |" in text and "| mutated an input | 1 |" in text


def test_a_tiny_api_run_reports_and_replays(tmp_path):
    out = tmp_path / "rows.json"
    functions = "Mask,Motion,sample_pushes,checks.check_positive"
    text = run_script(SCRIPT, "--n", "30", "--functions", functions, "--json", str(out), timeout=60)
    assert text.startswith("30 calls of 4 functions (seed 0, ")
    rows = json.loads(out.read_text())["rows"]
    assert len(rows) == 30 and {r["function"] for r in rows} == set(functions.split(","))
    assert all(r["class"] not in ("baseline_failed", "harness_error") for r in rows)
    replayed = run_script(SCRIPT, "--functions", functions, "--replay", "7")
    row = json.loads(replayed)
    assert row["case"] == 7 and row["class"] == rows[7]["class"]
