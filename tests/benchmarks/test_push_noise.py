"""benchmarks/realdata/push_noise.py, run as a user runs it, on repeats written here.

The "recorded" repeats are the exact simulator's own trajectories of one push made from
slightly different places, in the dataset's layout and names, so the replay through the
same simulator must give the recorded outcomes back.
"""

import importlib.util
import json
import shutil
import subprocess

import numpy as np
import pytest

from tests.scripts import ROOT, run_script

RADIUS = 0.00475
SIDE = 0.045
RECT = [(SIDE, SIDE), (-SIDE, SIDE), (-SIDE, -SIDE), (SIDE, -SIDE)]
NAME = "motion_surface=delrin_shape=rect1_a=0_v=20_i=0.000_s=0.700_t=0.000_rep={:04d}.h5"


def write_repeats(folder, h5py, simulators, n=6):
    """``n`` repeats of a normal push onto the top side 18 mm left of centre, 16 s apart."""
    sim = simulators.PushSimulator.from_polygon(RECT, mu_contact=0.3, pusher_radius=RADIUS)
    d = np.array([0.0, -1.0])
    offsets = 0.0002 * np.arange(n) - 0.0005
    for rep, dx in enumerate(offsets):
        contact = np.array([-0.018 + dx, SIDE])
        action = sim.to_pixels(np.array([contact - 0.01 * d, contact + 0.04 * d])).ravel()
        traj = sim.push(action, record=True).trajectory
        t = 1.456e9 + 16.0 * rep + np.arange(len(traj)) * (0.04 / (len(traj) - 1)) / 0.02
        centre = contact - RADIUS * d + 0.02 * (t - t[0])[:, None] * d
        with h5py.File(folder / NAME.format(rep), "w") as f:
            f.create_dataset("tip_pose", data=np.column_stack([t, centre, 0 * t]))
            f.create_dataset("object_pose", data=np.column_stack([t, traj]))
            f.create_dataset("ft_wrench", data=np.zeros((len(t), 4)))
    return offsets


def test_push_noise_on_simulated_repeats(tmp_path):
    h5py = pytest.importorskip("h5py")
    simulators = pytest.importorskip("simulators")
    folder = tmp_path / "repeats"
    folder.mkdir()
    offsets = write_repeats(folder, h5py, simulators)
    out = tmp_path / "noise.json"
    stdout = run_script(
        "benchmarks/realdata/push_noise.py", str(folder), "--travel", "0.02,0.03",
        "--window", "3", "--sims", "exact", "--sim-samples", "4", "--mu-contact", "0.3",
        "--json", str(out),
    )  # fmt: skip
    assert "## 3 cm of pusher travel after contact: 6 repeats kept of 6" in stdout
    assert "| `motion_noise` (the tracker's) | 0.50 | 0.50 |" in stdout
    res = json.loads(out.read_text())["travels"]["0.03"]
    real, scales = res["real"], res["scales"]
    assert real["offset_mm"]["median"] == pytest.approx(18.0 - 1e3 * np.median(offsets), abs=0.05)
    assert real["direction_deg"]["median"] == pytest.approx(-90.0, abs=0.01)
    assert real["rotation_deg"]["median"] > 1.0  # left of the CoM, pushed down: it turns CCW
    assert len(real["rotation_deg"]["window_medians"]) == 2
    # the replay of the recorded actions through the simulator that made them: the same push
    replay = res["sims"]["exact"]["replay"]
    assert replay["rotation_deg"]["median"] == pytest.approx(
        real["rotation_deg"]["median"], abs=0.1
    )
    assert replay["along_mm"]["median"] == pytest.approx(real["along_mm"]["median"], abs=0.2)
    assert scales["lever_mm"] == pytest.approx(real["offset_mm"]["median"], abs=0.05)
    assert scales["scored_theta_deg"] >= scales["model_theta_deg"] > 0
    assert scales["dtheta_deg_per_mm"] != 0
    # the model's own rotation is the simulator's, roughly (the same uniform plate)
    assert scales["lsm_rotation_deg"] == pytest.approx(real["rotation_deg"]["median"], rel=0.3)


def _module():
    spec = importlib.util.spec_from_file_location(
        "push_noise", ROOT / "benchmarks" / "realdata" / "push_noise.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_repeats_read_from_a_git_directory_and_the_errors(tmp_path):
    h5py = pytest.importorskip("h5py")
    simulators = pytest.importorskip("simulators")
    if shutil.which("git") is None:
        pytest.skip("needs git")
    work = tmp_path / "work"
    (work / "pushdata").mkdir(parents=True)
    write_repeats(work / "pushdata", h5py, simulators, n=3)
    (work / "pushdata" / "notes.txt").write_text("not a push")
    git = ["git", "-C", str(work), "-c", "user.name=t", "-c", "user.email=t@t"]
    subprocess.run([*git, "init", "-q"], check=True)
    subprocess.run([*git, "add", "."], check=True)
    subprocess.run([*git, "commit", "-qm", "repeats"], check=True)
    commit = subprocess.run(
        [*git, "rev-parse", "HEAD"], capture_output=True, text=True, check=True
    ).stdout.strip()
    noise = _module()
    dest = tmp_path / "dest"
    dest.mkdir()
    files = noise.files_from_git(str(work / ".git"), commit, "pushdata", str(dest), limit=2)
    assert [p.split("/")[-1] for p in files] == [NAME.format(0), NAME.format(1)]
    assert noise.repeat_files(str(work / "pushdata"))[-1].endswith(NAME.format(2))
    with pytest.raises(ValueError, match="repeats must be a folder"):
        noise.repeat_files(str(tmp_path / "nowhere"))
    with pytest.raises(ValueError, match="no .h5 or .json files"):
        noise.repeat_files(str(dest / ".."))
    with pytest.raises(SystemExit):
        noise.main([str(dest), "--git-dir", str(work / ".git")])
