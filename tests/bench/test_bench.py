"""The benchmark library: trials, seeding, registries, runners."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

pytest.importorskip("shapely")  # the bench runs the simulator (comcore[sim])
pytest.importorskip("trimesh")
pytest.importorskip("pymunk")

import comcore
from comcore import bench
from comcore.bench import (
    ESTIMATORS,
    PREDICTORS,
    ROW_FIELDS,
    BenchConfig,
    PredictorSpec,
    TrialSpec,
    register_estimator,
    run_benchmark,
    run_trial,
)
from tests.records import actions_of

TINY = {"objects": ("Obj3",), "trials": 2, "frictions": ("low",), "candidates": 8}


@pytest.fixture
def registry():
    """Let a test add estimators/predictors; restore the registries afterwards."""
    saved_e, saved_p = dict(ESTIMATORS), dict(PREDICTORS)
    yield
    ESTIMATORS.clear()
    ESTIMATORS.update(saved_e)
    PREDICTORS.clear()
    PREDICTORS.update(saved_p)


def test_trial_rng_depends_on_every_part_of_the_key():
    base = (0, "Obj1", "low", 3, "cand")
    first = bench.trial_rng(*base).random(4)
    assert np.array_equal(first, bench.trial_rng(*base).random(4))
    for i, changed in enumerate((1, "Obj2", "high", 4, "prior")):
        key = list(base)
        key[i] = changed
        assert not np.array_equal(first, bench.trial_rng(*key).random(4)), key


def test_trial_rows_are_complete_and_count_pushes_honestly():
    rows = run_trial(TrialSpec("Obj3", "high", 0, candidates=8))
    assert [r["estimator"] for r in rows] == list(bench.DEFAULT_ESTIMATORS)
    by_name = {r["estimator"]: r for r in rows}
    for r in rows:
        assert tuple(r) == ROW_FIELDS
        assert r["prior_pushes"] == 0  # the oracle needs no priors
        assert r["total_pushes"] == r["pushes_used"] + r["prior_pushes"]
        assert r["error_cm"] == pytest.approx(r["error_px"] * 0.25)
        assert 0.5 <= r["mu"] <= 0.9
        assert r["error_px"] == pytest.approx(
            np.hypot(r["est_x_px"] - r["true_x_px"], r["est_y_px"] - r["true_y_px"])
        )
    assert by_name["alg1"]["pushes_used"] == 8  # Alg. 1 uses every candidate
    assert by_name["centroid"]["pushes_used"] == 0
    assert 1 <= by_name["alg2"]["pushes_used"] <= 8


def test_trial_is_reproducible_and_keeps_its_estimates():
    spec = TrialSpec("Obj3", "low", 1, seed=5, candidates=8, estimators=("alg1", "alg2"))
    outcome = run_trial(spec, keep=True)
    assert outcome.rows == run_trial(spec)
    est = outcome.estimates["alg1"]
    assert est.heatmap.image.shape == outcome.context.mask.shape
    assert outcome.rows[0]["est_x_px"] == est.com[0]


def test_estimators_do_not_change_each_others_draws():
    """Adding an estimator leaves the other rows alone (each has its own stream)."""
    one = run_trial(TrialSpec("Obj3", "low", 0, candidates=8, estimators=("alg2",)))
    two = run_trial(TrialSpec("Obj3", "low", 0, candidates=8, estimators=("centroid", "alg2")))
    assert one[0] == two[1]


def test_results_do_not_depend_on_the_number_of_workers():
    config = BenchConfig(**TINY, estimators=("alg1", "alg2"))
    serial = run_benchmark(config, workers=1)
    parallel = run_benchmark(config, workers=2)
    assert serial.rows == parallel.rows
    assert parallel.cpu_s > 0 and serial.cpu_s > 0  # workers' CPU time is counted
    assert [(r["trial"], r["estimator"]) for r in serial.rows] == [
        (0, "alg1"), (0, "alg2"), (1, "alg1"), (1, "alg2"),
    ]  # fmt: skip


def test_dask_run_equals_local_run(dask_scheduler_address):
    config = BenchConfig(**TINY, estimators=("alg2", "centroid"))
    local = run_benchmark(config)
    remote = run_benchmark(config, dask=dask_scheduler_address)
    assert remote.rows == local.rows
    assert remote.dask == dask_scheduler_address
    assert remote.cpu_s is None  # not measurable on a cluster


def test_registered_estimator_runs_with_options_and_counts_its_own_pushes(registry):
    def poke(ctx, times=1):
        for action in ctx.candidates[:times]:
            ctx.push(comcore.Action(*action))
        return comcore.Estimate(ctx.mask.centroid, ctx.mask.centroid_m, ctx.mask.data, used=(0,))

    register_estimator("poke", poke, uses_motions=False, description="pushes, then guesses")
    rows = run_trial(TrialSpec("Obj3", "low", 0, candidates=5, estimators=("poke(times=3)",)))
    assert rows[0]["estimator"] == "poke(times=3)"
    assert rows[0]["pushes_used"] == 3  # counted calls, not len(used)
    assert rows[0]["status"] == "ok"


def test_failing_estimator_is_recorded_not_raised(registry):
    def broken(ctx):
        raise ValueError("no luck")

    register_estimator("broken", broken)
    rows = run_trial(TrialSpec("Obj3", "low", 0, candidates=4, estimators=("broken", "centroid")))
    assert rows[0]["status"] == "error" and "ValueError: no luck" in rows[0]["message"]
    assert rows[0]["error_px"] == pytest.approx(rows[1]["error_px"])  # centroid fallback
    assert rows[1]["status"] == "unchecked"  # the centroid baseline ran: it checks nothing


def test_learned_predictor_gets_twelve_prior_pushes(registry):
    seen = {}

    class Recorder:
        def predict(self, mask, actions, priors=()):
            seen["priors"] = priors
            return np.zeros((len(actions), 3))

    PREDICTORS["recorder"] = PredictorSpec("recorder", lambda ctx: Recorder(), prior_pushes=12)
    spec = TrialSpec("Obj3", "low", 0, predictor="recorder", candidates=6,
                     estimators=("alg2", "centroid"))  # fmt: skip
    rows = run_trial(spec)
    assert len(seen["priors"]) == 12
    assert isinstance(seen["priors"][0][1], comcore.Motion)
    assert rows[0]["prior_pushes"] == 12
    assert rows[0]["total_pushes"] == 12 + rows[0]["pushes_used"]
    assert rows[0]["status"] == "no_actions"  # zero predicted rotation: nothing to cut with
    assert rows[1]["prior_pushes"] == rows[1]["total_pushes"] == 0  # the centroid pushes nothing


def test_unavailable_estimators_are_skipped_and_predictors_refused(registry):
    register_estimator("future", lambda ctx: None, requires=lambda: "written on branch 'x'")
    result = run_benchmark(BenchConfig(**TINY, estimators=("future", "centroid")))
    assert result.skipped == {"future": "written on branch 'x'"}
    assert {r["estimator"] for r in result.rows} == {"centroid"}
    PREDICTORS["ghost"] = PredictorSpec("ghost", lambda ctx: None, requires=lambda: "not built")
    with pytest.raises(RuntimeError, match="predictor 'ghost' is unavailable: not built"):
        run_benchmark(BenchConfig(**TINY, predictor="ghost", estimators=("alg2",)))


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"trials": -1}, "trials must be a non-negative integer"),
        ({"frictions": ("icy",)}, "frictions must be a non-empty subset"),
        ({"predictor": "crystal-ball"}, "predictor must be one of"),
        ({"estimators": ("alg2", "alg2")}, "estimators must be distinct"),
        ({"estimators": ("alg1(threshold=)",)}, "bad options in"),
        ({"estimators": ("alg1(0.2)",)}, "only keyword arguments"),
        ({"cone": 2.0}, "cone must be in"),
    ],
)
def test_bad_configs_are_refused(changes, match):
    with pytest.raises(ValueError, match=match):
        BenchConfig(**{**TINY, **changes})


def test_bad_workers_are_refused():
    with pytest.raises(ValueError, match="workers must be a positive integer"):
        run_benchmark(BenchConfig(**TINY), workers=0)


def test_config_specs_cover_every_trial_in_order():
    cfg = BenchConfig(objects=("Obj1", "Obj2"), trials=2, frictions=("low", "high"))
    keys = [(s.object, s.friction, s.trial) for s in cfg.specs()]
    assert keys[:3] == [("Obj1", "low", 0), ("Obj1", "low", 1), ("Obj1", "high", 0)]
    assert len(keys) == len(set(keys)) == 8
    assert dataclasses.replace(cfg, seed=1).specs()[0].seed == 1


def test_active_estimator_counts_the_pushes_it_executes():
    spec = TrialSpec("Obj3", "low", 0, candidates=10, estimators=("active-vt(max_pushes=2)",))
    outcome = run_trial(spec, keep=True)
    row, est = outcome.rows[0], outcome.estimates["active-vt(max_pushes=2)"]
    assert row["status"] == est.status != "error", row["message"]
    assert row["pushes_used"] == len(est.used) <= 2
    assert row["prior_pushes"] == 0 and row["total_pushes"] == row["pushes_used"]


@pytest.mark.parametrize(
    ("label", "from_trial"),
    [("active-vt(max_pushes=2)", False), ("active-vt(max_pushes=2, candidates='trial')", True)],
)
def test_active_estimator_draws_its_own_pushes_unless_told_the_trials(label, from_trial):
    outcome = run_trial(TrialSpec("Obj3", "low", 0, candidates=10, estimators=(label,)), keep=True)
    executed = actions_of(outcome.estimates[label])
    trial = outcome.context.candidates
    assert len(executed) == 2
    in_trial = [any(np.allclose(a, c) for c in trial) for a in executed]
    assert all(in_trial) if from_trial else not any(in_trial)


def test_pushes_the_simulator_refuses_are_redrawn(registry):
    def refused(actions):
        return np.modf(np.asarray(actions)[:, 0])[0] < 0.3  # about a third of the pushes

    class Picky:
        """Refuses a batch holding a push it cannot run, like a simulator refusing a start."""

        def predict(self, mask, actions, priors=()):
            if refused(actions).any():
                raise ValueError("the pusher would start inside the object")
            return np.tile([0.1, 1.0, 0.0], (len(actions), 1))

    PREDICTORS["picky"] = PredictorSpec("picky", lambda ctx: Picky(), pushes_object=True)
    outcome = run_trial(
        TrialSpec("Obj3", "low", 0, predictor="picky", candidates=6, estimators=("alg1",)),
        keep=True,
    )
    assert outcome.context.candidates.shape == (6, 4)
    assert not refused(outcome.context.candidates).any()
    assert outcome.context.motions.shape == (6, 3)
    assert "candidate push(es) redrawn" in outcome.rows[0]["message"]
    assert outcome.rows[0]["status"] == "unchecked"  # Alg. 1 ran (it is never "ok")


def test_a_refused_simulator_draw_is_redrawn_from_the_next_stream(monkeypatch):
    import simulators

    spec = TrialSpec("Obj3", "low", 0, candidates=6, estimators=("centroid",))
    first = spec.simulator()
    assert first.com_m == spec.simulator().com_m  # the stream "simulator"
    draw, calls = simulators.random_simulator, []

    def refuse_once(*args, **kwargs):
        calls.append(1)
        if len(calls) == 1:
            raise ValueError("target is not strictly inside the support points")
        return draw(*args, **kwargs)

    monkeypatch.setattr(simulators._random, "random_simulator", refuse_once)
    outcome = run_trial(spec, keep=True)
    again = draw("Obj3", "low", rng=spec.rng("simulator#1"))
    assert outcome.context.simulator.com_m == again.com_m != first.com_m
    assert outcome.rows[0]["message"].startswith("simulator draw 0 failed (target is not")


def test_a_failing_predictor_fails_only_the_estimators_that_need_it(registry):
    def broken(ctx):
        raise RuntimeError("weights missing")

    PREDICTORS["broken"] = PredictorSpec("broken", broken)
    rows = run_trial(
        TrialSpec(
            "Obj3", "low", 0, predictor="broken", candidates=4, estimators=("alg2", "centroid")
        )
    )
    assert rows[0]["status"] == "error"
    assert "predictor 'broken' failed: RuntimeError: weights missing" in rows[0]["message"]
    assert rows[1]["status"] == "unchecked" and rows[1]["message"] == ""
