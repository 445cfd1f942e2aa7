"""benchmarks/realdata/real_pushes.py, run as a user runs it, on a small data folder written here.

The "recorded" pushes are the exact simulator's own trajectories written in the dataset's
layout, so the real world and the pool-matched simulation must agree exactly.
"""

import json

import numpy as np
import pytest

from tests.scripts import run_script

RADIUS = 0.00475
SIDE = 0.045
RECT = [(SIDE, SIDE), (-SIDE, SIDE), (-SIDE, -SIDE), (SIDE, -SIDE)]
MU = 0.3


def write_pushes(folder, h5py, simulators):
    """Four pushes of a uniform 9 cm square along face normals, written as h5 files."""
    sim = simulators.PushSimulator.from_polygon(RECT, mu_contact=MU, pusher_radius=RADIUS)
    pushes = [  # leading point on the face, direction (along the inward normal), file fields
        ((0.02, -SIDE), (0.0, 1.0), "i=2.000_s=0.278_t=0.000"),
        ((-0.015, -SIDE), (0.0, 1.0), "i=2.000_s=0.667_t=0.000"),
        ((SIDE, 0.025), (-1.0, 0.0), "i=3.000_s=0.222_t=0.000"),
        ((SIDE, -0.01), (-1.0, 0.0), "i=3.000_s=0.611_t=0.000"),
    ]
    for contact, d, fields in pushes:
        contact, d = np.array(contact), np.array(d)
        action = sim.to_pixels(np.array([contact - 0.01 * d, contact + 0.04 * d])).ravel()
        traj = sim.push(action, record=True).trajectory
        t = 1.46e9 + np.arange(len(traj)) * (0.04 / (len(traj) - 1)) / 0.05
        centre = contact - RADIUS * d + 0.05 * (t - t[0])[:, None] * d
        name = f"motion_surface=abs_shape=rect1_a=0_v=50_{fields}.h5"
        with h5py.File(folder / name, "w") as f:
            f.create_dataset("tip_pose", data=np.column_stack([t, centre, 0 * t]))
            f.create_dataset("object_pose", data=np.column_stack([t, traj]))
            f.create_dataset("ft_wrench", data=np.zeros((len(t), 4)))


def data_folder(tmp_path):
    """A dataset folder (abs/train, shapes.json) with :func:`write_pushes`' four pushes."""
    h5py = pytest.importorskip("h5py")
    simulators = pytest.importorskip("simulators")
    data = tmp_path / "data"
    (data / "abs" / "train").mkdir(parents=True)
    (data / "shapes.json").write_text(json.dumps({"shapes": {"rect1": {"polygon_m": RECT}}}))
    write_pushes(data / "abs" / "train", h5py, simulators)
    return data


def test_real_pushes_script_on_simulated_recordings(tmp_path):
    pytest.importorskip("matplotlib")
    data = data_folder(tmp_path)
    out = tmp_path / "out"
    stdout = run_script(
        "benchmarks/realdata/real_pushes.py", str(data), "--out", str(out), "--objects", "rect1",
        "--worlds", "real,exact", "--models", "vt,lsm", "--ks", "2", "--subsets", "2",
        "--pools", "1", "--mu-contact", str(MU),
    )  # fmt: skip
    assert "## The issue's table, re-measured" in stdout
    assert "| pushes kept (of) | 4 (4) |" in stdout
    assert (out / "report.md").exists() and (out / "error_vs_k.png").stat().st_size > 1000
    res = json.loads((out / "results.json").read_text())["results"]["rect1"]
    assert res["real"]["vt_agreement"] == res["exact"]["vt_agreement"] == [4, 4]
    assert res["exact"]["turn_ratio_real_over_sim"] == pytest.approx(1.0, abs=1e-6)
    for model in ("vt", "lsm"):
        real, sim = res["real"][model], res["exact"][model]
        assert real["all"]["error_cm"] == pytest.approx(sim["all"]["error_cm"], abs=1e-6)
        assert real["2"]["error_cm"] == pytest.approx(sim["2"]["error_cm"], abs=1e-6)
        assert real["active"]["error_cm"] == pytest.approx(sim["active"]["error_cm"], abs=1e-6)
    # four normal pushes from two sides pin the CoM of a uniform square
    assert res["real"]["lsm"]["all"]["error_cm"] < 0.5 and res["real"]["lsm"]["all"]["holds"]
    # The leading line's contacts (the paper's point pusher): head on they are the disc's
    # (the estimators' default above), to a pixel.
    disc_out = tmp_path / "line"
    run_script(
        "benchmarks/realdata/real_pushes.py", str(data), "--out", str(disc_out), "--objects", "rect1",
        "--worlds", "real", "--models", "vt", "--ks", "2", "--subsets", "2", "--pools", "1",
        "--contacts", "line", "--no-figure",
    )  # fmt: skip
    disc = json.loads((disc_out / "results.json").read_text())["results"]["rect1"]["real"]
    assert disc["vt_agreement"] == [4, 4]
    assert disc["vt"]["all"]["error_cm"] == pytest.approx(
        res["real"]["vt"]["all"]["error_cm"], abs=0.1
    )


def test_theta_units_real_on_simulated_recordings(tmp_path):
    """Radians as recorded: no false alarm; the table has a row per k and all pushes."""
    data = data_folder(tmp_path)
    stdout = run_script(
        "benchmarks/realdata/theta_units_real.py", str(data), "--objects", "rect1", "--ks", "2",
        "--subsets", "2",
    )  # fmt: skip
    assert "| rect1 | 2 | 2 |" in stdout and "| rect1 | all | 1 |" in stdout
    assert "total: 0 false alarms in 3 honest recordings" in stdout


def test_real_pushes_frames_reach_the_active_replay(tmp_path):
    """--frame-rate: the pose streams during each push go to the posteriors and the
    active replay's session too (each changes; the estimate stays as good)."""
    data = data_folder(tmp_path)
    results = {}
    for label, extra in (("end", []), ("frames", ["--frame-rate", "50"])):
        out = tmp_path / label
        run_script(
            "benchmarks/realdata/real_pushes.py", str(data), "--out", str(out), "--objects",
            "rect1", "--worlds", "real", "--models", "lsm", "--ks", "2", "--subsets", "2",
            "--pools", "1", "--no-figure", *extra,
        )  # fmt: skip
        results[label] = json.loads((out / "results.json").read_text())["results"]["rect1"]
    end, framed = (results[k]["real"]["lsm"] for k in ("end", "frames"))
    for cell in ("all", "active"):
        assert framed[cell]["error_cm"] != pytest.approx(end[cell]["error_cm"], abs=1e-6)
        assert framed[cell]["error_cm"] < 0.5
