"""comcore.recordings.mit_push: the MIT push dataset's files (small files of the same layout, written here)."""

import json
import sys

import numpy as np
import pytest

import comcore
import comcore.recordings.mit_push as mp

RECT = "motion_surface=abs_shape=rect1_a=0_v=75_i=2.000_s=0.700_t=-0.349.h5"


def rect_push(rate=250.0, n=500):
    """A push on rect1's side 2 (y = -45 mm) 1.8 cm right of centre, along +y, turning CCW.

    The object sits at a world pose turned by 2.28 rad, as in the dataset's files.
    """
    pose0 = np.array([0.425, -0.084, 2.28])
    t = 1.46e9 + np.arange(n) / rate
    s = np.clip(t - t[0] - 0.2, 0.0, 0.075 * 0.8) / 0.075  # rests 0.2 s, then 6 cm at 75 mm/s
    centre = np.column_stack([0.018 + 0 * s, -0.045 - mp.PUSHER_RADIUS + 0.075 * s])
    c, sn = np.cos(pose0[2]), np.sin(pose0[2])
    world = np.column_stack(
        [c * centre[:, 0] - sn * centre[:, 1], sn * centre[:, 0] + c * centre[:, 1]]
    )
    tip = np.column_stack([t, world + pose0[:2], 0 * t])
    moving = np.clip(s - 0.002, 0.0, None)  # metres of travel past contact
    obj = np.column_stack(
        [t - 0.004, pose0[0] + 0.2 * moving, pose0[1] - 0.3 * moving, pose0[2] + 6.0 * moving]
    )
    wrench = np.column_stack([t, 0 * t, 0 * t, 0 * t])
    return obj, tip, wrench


def write_h5(path, obj, tip, wrench):
    h5py = pytest.importorskip("h5py")
    with h5py.File(path, "w") as f:
        f.create_dataset("tip_pose", data=tip)
        f.create_dataset("ft_wrench", data=wrench)
        f.create_dataset("object_pose", data=obj)


def test_h5_and_json_files_load_like_their_pose_streams(tmp_path):
    obj, tip, wrench = rect_push()
    scrambled = obj.copy()
    scrambled[[40, 41, 42]] = scrambled[[42, 40, 41]]  # out of order, as in 25 of the files
    write_h5(tmp_path / RECT, scrambled, tip, wrench)
    name_json = RECT.replace(".h5", ".json")
    data = {"tip_pose": tip.tolist(), "ft_wrench": wrench.tolist(), "object_pose": obj.tolist()}
    (tmp_path / name_json).write_text(json.dumps(data))
    read = mp.read_push(tmp_path / RECT)
    assert np.array_equal(read.object_pose, obj) and np.array_equal(read.tip_pose, tip)
    assert read.name.shape == "rect1" and read.name.speed == 0.075 and read.name.angle == -0.349
    from_h5 = mp.load_pushes([tmp_path / RECT])
    from_json = mp.load_pushes([tmp_path / name_json])
    direct = comcore.recording_from_poses(
        mp.OUTLINES["rect1"], [(obj, tip)], mp.PUSHER_RADIUS, com=(0, 0), names=[RECT]
    )
    assert from_h5.pushes == direct.pushes
    assert from_json.pushes[0][2:] == direct.pushes[0][2:]  # all but the index and name
    assert from_json.pushes[0].name == name_json
    push = from_h5.pushes[0]
    assert push.motion.theta > 0.1 and push.line_hits and from_h5.com == (25.5, 25.5)
    # The push goes up the screen (the object's +y), right of the CoM: counter-clockwise.
    con = comcore.geometry.contacts(from_h5.mask, [push.action])
    assert push.action.direction == pytest.approx((0.0, -1.0))
    sense = comcore.vt.predicted_sense(
        from_h5.com, con.point[0], con.normal[0], push.action.direction, 0.25
    )
    assert sense == 1 == push.motion.sense


def test_the_labs_json_layout_reads_like_its_h5(tmp_path):
    # The lab's analysis scripts write one JSON object per push, pretty-printed, its tables in
    # their own order and of their own lengths (the streams' rates differ), samples in the
    # order the ROS stamps came: pnpush_planning's hex-on-plywood file is written that way.
    obj, tip, wrench = rect_push()
    obj, wrench = obj[:-3], wrench[1:]
    scrambled = obj.copy()
    scrambled[[7, 8]] = scrambled[[8, 7]]
    write_h5(tmp_path / RECT, scrambled, tip, wrench)
    name = RECT.replace(".h5", ".json")
    tables = {"tip_pose": tip, "ft_wrench": wrench, "object_pose": scrambled}
    (tmp_path / name).write_text(json.dumps({k: v.tolist() for k, v in tables.items()}, indent=4))
    from_json, from_h5 = mp.read_push(tmp_path / name), mp.read_push(tmp_path / RECT)
    for field in ("object_pose", "tip_pose", "ft_wrench"):
        assert np.array_equal(getattr(from_json, field), getattr(from_h5, field))
    assert from_json.name == from_h5.name and from_json.name.repeat is None
    assert mp.load_pushes([tmp_path / name]).pushes[0].motion == (
        mp.load_pushes([tmp_path / RECT]).pushes[0].motion
    )
    no_wrench = (
        tmp_path / "motion_surface=plywood_shape=hex_a=0_v=150_i=1.000_s=0.000_t=-0.349.json"
    )
    no_wrench.write_text(json.dumps({"tip_pose": tip.tolist(), "object_pose": obj.tolist()}))
    read = mp.read_push(no_wrench)
    assert read.ft_wrench.shape == (0, 4) and read.name.shape == "hex" and read.name.side == 1
    (tmp_path / "list.json").write_text(json.dumps([tip.tolist()]))
    with pytest.raises(ValueError, match="must hold one JSON object of tables"):
        mp.read_push(tmp_path / "list.json")
    (tmp_path / "ragged.json").write_text(
        json.dumps({"tip_pose": [[0, 1, 2, 3], [0, 1]], "object_pose": obj.tolist()})
    )
    with pytest.raises(ValueError, match="'tip_pose' must be a table of numbers"):
        mp.read_push(tmp_path / "ragged.json")


def test_a_repeats_name_says_its_number():
    base = "motion_surface=delrin_shape=rect1_a=0_v=20_i=0.000_s=0.700_t=0.000"
    name = mp.parse_name(base + "_rep=0042.h5")
    assert name.repeat == 42 and name.surface == "delrin" and name.speed == 0.02
    assert name._replace(repeat=None) == mp.parse_name(base + ".h5")
    with pytest.raises(ValueError, match="not named like"):
        mp.parse_name(base + "_rep=x.h5")


def test_a_longer_window_and_a_finer_mask(tmp_path):
    obj, tip, wrench = rect_push()
    write_h5(tmp_path / RECT, obj, tip, wrench)
    short = mp.load_pushes([tmp_path / RECT], travel=0.02).pushes[0]
    long = mp.load_pushes([tmp_path / RECT], travel=0.05, resolution=0.001).pushes[0]
    assert long.motion.theta > short.motion.theta > 0
    assert long.action.length * 0.001 == pytest.approx(0.05 + 0.01, abs=1e-9)
    too_long = mp.load_pushes([tmp_path / RECT], travel=0.07)
    assert too_long.pushes == () and too_long.skipped[0].reason == "short"


def test_file_errors(tmp_path, monkeypatch):
    obj, tip, wrench = rect_push()
    write_h5(tmp_path / RECT, obj, tip, wrench)
    butter = RECT.replace("rect1", "butter")
    write_h5(tmp_path / butter, obj, tip, wrench)
    with pytest.raises(ValueError, match="of one plate, got shapes"):
        mp.load_pushes([tmp_path / RECT, tmp_path / butter])
    with pytest.raises(ValueError, match="outline is needed for shape 'butter'"):
        mp.load_pushes([tmp_path / butter])
    assert mp.load_pushes([tmp_path / butter], outline=mp.OUTLINES["rect1"]).pushes
    with pytest.raises(ValueError, match="at least one file"):
        mp.load_pushes([])
    (tmp_path / "bad.json").write_text(json.dumps({"tip_pose": tip.tolist()}))
    with pytest.raises(ValueError, match="has no 'object_pose' table"):
        mp.read_push(tmp_path / "bad.json")
    (tmp_path / "bad2.json").write_text(
        json.dumps({"tip_pose": tip[:, :3].tolist(), "object_pose": []})
    )
    with pytest.raises(ValueError, match=r"'tip_pose' must have shape \(n, 4\)"):
        mp.read_push(tmp_path / "bad2.json")
    with pytest.raises(ValueError, match="not named like the MIT push dataset"):
        mp.parse_name("push_07.h5")
    monkeypatch.setitem(sys.modules, "h5py", None)
    with pytest.raises(ImportError, match=r"pip install comcore\[real\]"):
        mp.read_push(tmp_path / RECT)


def test_outlines_are_the_dataset_plates():
    # Areas from shape_db.py's shapes (rect 90 x 90 mm; circle r 52.5 mm; ellipse 52.5 x 78.5
    # mm; hexagon of circumradius 60.5 mm), each centred on the origin.
    def area(p):
        return 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])

    expected = {
        "rect1": 0.0081,
        "ellip1": np.pi * 0.0525**2,
        "ellip3": np.pi * 0.0525 * 0.0785,
        "hex": 1.5 * np.sqrt(3) * 0.0605**2,
    }
    for shape, a in expected.items():
        outline = mp.OUTLINES[shape]
        assert area(outline) == pytest.approx(a, rel=1e-4)  # counter-clockwise
        assert np.abs(outline.mean(axis=0)).max() < 1e-12
        assert not outline.flags.writeable


def test_import_comcore_does_not_load_h5py_or_this_module():
    import subprocess

    code = "import sys, comcore; print('h5py' in sys.modules, 'comcore.recordings.mit_push' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


@pytest.mark.parametrize("name, text", [("x.h5", "not hdf5"), ("x.txt", "x"), ("x.mcap", "")])
def test_a_file_that_is_not_hdf5_is_refused_naming_it(tmp_path, name, text):
    pytest.importorskip("h5py")
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(ValueError, match=f"cannot read '.*{name}' as HDF5"):
        mp.read_push(path)
    with pytest.raises(ValueError, match=f"cannot read '.*{name}' as HDF5"):
        mp.load_pushes([path])


def test_a_json_file_that_is_not_json_is_refused_naming_it(tmp_path):
    path = tmp_path / "x.json"
    path.write_text("{not json")
    with pytest.raises(ValueError, match="cannot read '.*x.json' as JSON"):
        mp.read_push(path)
