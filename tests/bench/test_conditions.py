"""Realism conditions of the benchmark: parsing, the same trials, each condition's effect."""

import math

import numpy as np
import pytest

pytest.importorskip("shapely")
pytest.importorskip("trimesh")
pytest.importorskip("pymunk")

import comcore
from comcore.bench import (
    CONDITIONS,
    BenchConfig,
    TrialSpec,
    parse_condition,
    run_conditions,
    run_trial,
)
from comcore.bench._conditions import conditions_table
from comcore.bench._realism import ConditionWorld
from tests.records import actions_of

ESTIMATORS = ("alg2", "active(max_pushes=1)", "active-robot(max_pushes=1)", "centroid")
NAMES = (
    "exact",
    "pymunk",
    "pusher-error",
    "motion-noise",
    "mask-noise",
    "resolution-0.1",
    "no-reset",
)


def test_the_documented_conditions_are_registered():
    assert tuple(CONDITIONS) == NAMES
    assert CONDITIONS["pusher-error"].pusher_error == 0.003
    assert CONDITIONS["resolution-0.1"].resolution == 0.001
    assert CONDITIONS["motion-noise"].motion_noise == (math.radians(0.5), 0.0005)
    assert CONDITIONS["exact"].plain and CONDITIONS["no-reset"].plain


def test_parse_condition_options_and_errors():
    c = parse_condition("pusher-error(pusher_error=0.001)")
    assert c.pusher_error == 0.001 and c.name == "pusher-error(pusher_error=0.001)"
    with pytest.raises(ValueError, match="unknown condition 'fog'"):
        parse_condition("fog")
    with pytest.raises(ValueError, match="unknown option"):
        parse_condition("exact(colour=1)")
    with pytest.raises(ValueError, match="pusher_error"):
        parse_condition("pusher-error(pusher_error=-1.0)")
    with pytest.raises(ValueError, match="engine"):
        parse_condition("pymunk(engine='box2d')")


@pytest.fixture(scope="module")
def runs():
    config = BenchConfig(
        objects=("Obj3",), trials=1, frictions=("low",), candidates=8, estimators=ESTIMATORS
    )
    return run_conditions(config, "all", workers=1)


def test_each_condition_runs_the_same_trial(runs):
    results, unfit = runs
    assert tuple(results) == NAMES
    for name, result in results.items():
        for row in result.rows:
            assert row["condition"] == name
            assert row["status"] != "error", (name, row["estimator"], row["message"])
            assert row["mu"] == results["exact"].rows[0]["mu"]  # the same object
    assert unfit["no-reset"] == {
        e: "needs the object put back before every push" for e in ESTIMATORS[:2]
    }
    assert [r["estimator"] for r in results["no-reset"].rows] == list(ESTIMATORS[2:])


def test_exact_condition_is_the_plain_benchmark(runs):
    results, _ = runs
    plain = run_trial(TrialSpec("Obj3", "low", 0, candidates=8, estimators=ESTIMATORS))
    for a, b in zip(plain, results["exact"].rows):
        assert a["error_cm"] == b["error_cm"] and a["total_pushes"] == b["total_pushes"]


def test_rows_say_whether_the_region_holds_the_truth(runs):
    results, _ = runs
    rows = [r for res in results.values() for r in res.rows if r["estimator"].startswith("active")]
    assert all(r["credible_radius_cm"] > 0 for r in rows)
    assert all(isinstance(r["covered"], bool) for r in rows)
    assert all(r["push_failures"] == 0 for r in rows)
    centroid = [r for res in results.values() for r in res.rows if r["estimator"] == "centroid"]
    assert all(r["credible_radius_cm"] is None and r["covered"] for r in centroid)


def test_conditions_table_has_one_table_per_condition(runs):
    results, unfit = runs
    text = conditions_table(results, unfit, command="comcore bench --conditions ...")
    for name in NAMES:
        assert f"## {name}\n" in text
    assert "| `alg2` | not run: needs the object put back before every push |" in text
    assert text.count("| `active-robot(max_pushes=1)` | 1 |") == len(NAMES)
    # every status by name, and what budget means in the bench
    assert text.count("| ok > 1 cm | failed | statuses |") == len(NAMES)
    centroid = [line for line in text.splitlines() if line.startswith("| `centroid` | 1 |")]
    assert len(centroid) == len(NAMES) and all(line.endswith("| unchecked 1 |") for line in centroid)
    assert "`budget`: an active estimator spent its push budget" in text


@pytest.fixture(scope="module")
def sim():
    return TrialSpec("Obj3", "low", 0).simulator()


def _motions(name, sim, seed=0):
    world = ConditionWorld(parse_condition(name), sim, seed)
    actions = comcore.sample_pushes(world.mask, 6, rng=1)
    return world, world.push_motions(actions), world.base.push_motions(actions)


def test_pusher_error_moves_the_pushes(sim):
    _, observed, exact = _motions("pusher-error", sim)
    assert not np.allclose(observed, exact, atol=1e-3)
    _, again, _ = _motions("pusher-error", sim)
    assert np.array_equal(observed, again)


def test_motion_noise_is_small_and_seeded(sim):
    world, observed, exact = _motions("motion-noise", sim)
    d = observed - exact
    assert np.all(np.abs(d[:, 0]) < 5 * math.radians(0.5))
    assert np.all(np.abs(d[:, 1:]) < 5 * 0.0005 / world.resolution) and (d != 0).all()


def test_mask_noise_measures_motions_from_noisy_masks():
    sim = TrialSpec("Obj2", "low", 0).simulator()  # no rotational symmetry
    world, observed, exact = _motions("mask-noise", sim)
    assert not np.array_equal(world.mask.data, world.base.mask.data)
    assert world.mask.shape != sim.mask.shape  # the camera frame keeps the pushed object in view
    assert np.allclose(observed[:, 0], exact[:, 0], atol=0.05)


def test_pymunk_and_resolution_rebuild_the_same_object(sim):
    pym = ConditionWorld(CONDITIONS["pymunk"], sim, 0)
    fine = ConditionWorld(CONDITIONS["resolution-0.1"], sim, 0)
    assert pym.settings.engine == "pymunk" and fine.resolution == 0.001
    assert np.allclose(pym.com_m, sim.com_m) and np.allclose(fine.com_m, sim.com_m)
    assert abs(fine.mask.area_m2 - sim.mask.area_m2) < 0.05 * sim.mask.area_m2


def test_world_refuses_a_start_pose(sim):
    world = ConditionWorld(CONDITIONS["pusher-error"], sim, 0)
    with pytest.raises(ValueError, match="pose"):
        world.push_many(comcore.sample_pushes(world.mask, 1, rng=0), pose=(0.0, 0.0, 0.0))


def test_run_conditions_bad_input():
    config = BenchConfig(objects=("Obj3",), trials=1, frictions=("low",), estimators=("centroid",))
    with pytest.raises(ValueError, match="distinct"):
        run_conditions(config, "exact,exact")
    with pytest.raises(ValueError, match="at least one"):
        run_conditions(config, "")


@pytest.mark.parametrize("observe", ["mask", "consecutive", "video", "motion"])
def test_active_robot_counts_the_robots_pushes(observe):
    label = f"active-robot(max_pushes=2, observe={observe!r})"
    outcome = run_trial(TrialSpec("Obj2", "low", 0, candidates=4, estimators=(label,)), keep=True)
    row, est = outcome.rows[0], outcome.estimates[label]
    assert row["status"] in ("ok", "budget"), row["message"]
    assert row["total_pushes"] == row["pushes_used"] == len(actions_of(est)) == 2
    assert row["push_failures"] == 0 and row["credible_radius_cm"] > 0


def test_active_robot_refuses_an_unknown_observation():
    label = "active-robot(observe='psychic')"
    row = run_trial(TrialSpec("Obj2", "low", 0, candidates=4, estimators=(label,)))[0]
    assert row["status"] == "error" and "observe must be" in row["message"]


def test_command_line_writes_conditions_md(tmp_path, capsys):
    from comcore.cli import main

    out = tmp_path / "run"
    args = ["bench", "--objects", "Obj3", "--trials", "1", "--friction", "low", "--candidates",
            "4", "--workers", "1", "--no-progress", "--estimators", "alg2,centroid",
            "--conditions", "exact,no-reset", "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    text = (out / "conditions.md").read_text()
    assert "## exact\n" in text and "## no-reset\n" in text
    rows = (out / "conditions.jsonl").read_text().splitlines()
    assert len(rows) == 3 and not (out / "conditions.partial.jsonl").exists()
    assert "conditions.md" in capsys.readouterr().out
    assert main([*args[:-4], "--conditions", "fog", "--out", str(out)]) == 2
    assert "unknown condition 'fog'" in capsys.readouterr().err


def test_video_tracking_sees_past_a_rotational_symmetry():
    import simulators
    from comcore.bench._builtins import _tracked_motion

    # Obj3 is a regular hexagon: a 3 cm push turns this instance by about 1 rad, more
    # than half its symmetry angle, so two masks alone give the wrong rotation.
    robot = simulators.SimulatedRobot(simulators.random_simulator("Obj3", "high", rng=1), rng=0)
    first = robot.camera_mask()
    push = robot.execute(comcore.sample_pushes(first, 1, rng=0)[0], frames=8)
    assert abs(push.motion.theta) > math.pi / 6
    tracked = _tracked_motion(first, push.frames)
    assert abs(tracked.theta - push.motion.theta) < 0.02
    assert np.hypot(tracked.tx - push.motion.tx, tracked.ty - push.motion.ty) < 0.5
    two_masks = comcore.measure_motion(first, push.frames[-1])
    assert abs(two_masks.motion.theta - push.motion.theta) > 0.5  # flagged or not, not seen


def test_friction_table_ratios_to_the_baseline(runs, tmp_path):
    import json

    from comcore.bench import friction_table

    rows = runs[0]["exact"].rows
    path = tmp_path / "rows.jsonl"
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))
    text = friction_table(path, baseline="alg2")
    alg2, centroid = (
        next(r["error_cm"] for r in rows if r["estimator"] == e) for e in ("alg2", "centroid")
    )
    assert f"| `centroid` | both | {centroid:.3f} ({centroid / alg2:.2f} x) |" in text
    with pytest.raises(ValueError, match="baseline"):
        friction_table(rows, baseline="alg9")


def test_a_failed_robot_run_is_scored_at_the_centroid_of_its_own_camera():
    label = "active-robot(colour=1)"  # the session refuses it, after the robot was built
    row = run_trial(TrialSpec("Obj2", "low", 0, candidates=4, estimators=(label, "centroid")))
    assert row[0]["status"] == "error"
    assert abs(row[0]["error_cm"] - row[1]["error_cm"]) < 0.05  # the same centroid, its frame
