"""``comcore estimate --bag``: a robot's bag in, the same estimate as its mask PNG and CSV."""

from __future__ import annotations

import json
import sys

import numpy as np
import pytest

pytest.importorskip("rosbags")

import comcore.recordings.bag as bag
from comcore.cli import main
from comcore.cli.estimate import estimate
from tests import bags

TOPICS = ["--object-topic", "/plate/pose", "--pusher-topic", "/tip"]


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A ROS 1 bag of 6 simulated pushes, the outline's CSV, and the Recording read from it.

    Six, not twenty: the command's check of theta's unit runs the motion model on each push.
    """
    folder = tmp_path_factory.mktemp("bag")
    log = bags.simulated_log(n_pushes=6)
    path = bags.write_bag(folder / "plate.bag", "rosbag1", log, types=("/plate/pose",))
    outline = folder / "plate.csv"
    outline.write_text("x,y\n" + "".join(f"{x!r},{y!r}\n" for x, y in bags.OUTLINE.tolist()))
    rec = bag.recording_from_bag(path, "/plate/pose", "/tip", outline, bags.RADIUS)
    return path, outline, rec


def bag_args(recorded, *extra):
    path, outline, _ = recorded
    return ["estimate", "--bag", str(path), *TOPICS, "--outline", str(outline),
            "--pusher-radius", str(bags.RADIUS), *extra]  # fmt: skip


def run_json(capsys, argv):
    code = main([*argv, "--json", "--no-overlay"])
    captured = capsys.readouterr()
    return code, json.loads(captured.out) if captured.out else None, captured.err


@pytest.mark.parametrize("method", [["--model", "none"], ["--method", "alg2"]])
def test_the_bag_gives_the_estimate_of_its_mask_png_and_pushes_csv(
    recorded, tmp_path, capsys, method
):
    pytest.importorskip("matplotlib")
    from matplotlib.image import imsave

    _, _, rec = recorded
    code, from_bag, err = run_json(capsys, bag_args(recorded, *method))
    assert code == 0, err
    assert "comcore estimate: --bag: 6 pushes kept, 0 skipped" in err
    png, csv = tmp_path / "plate.png", tmp_path / "pushes.csv"
    imsave(png, rec.mask.data.astype(float), cmap="gray", vmin=0, vmax=1)
    rows = np.column_stack([rec.actions, rec.motions]).tolist()
    csv.write_text(
        "sx,sy,ex,ey,theta,tx,ty\n" + "".join(",".join(map(repr, r)) + "\n" for r in rows)
    )
    argv = ["estimate", "--mask", str(png), "--pushes", str(csv),
            "--resolution", repr(rec.mask.resolution), "--pusher-radius", str(bags.RADIUS), *method]  # fmt: skip
    code, from_csv, err = run_json(capsys, argv)
    assert code == 0, err
    com_object = from_bag.pop("com_object_m")  # only --bag knows the object's frame
    ros_bag, ros_csv = from_bag.pop("ros"), from_csv.pop("ros")  # each in its own frame
    assert from_bag == from_csv
    inertia = ros_bag["inertia_stamped"]
    assert [inertia["inertia"]["com"][a] for a in "xy"] == pytest.approx(com_object, abs=1e-12)
    assert inertia["header"]["frame_id"] == "object"
    assert ros_csv["inertia_stamped"]["header"]["frame_id"] == "comcore_mask"
    assert [ros_csv["inertia_stamped"]["inertia"]["com"][a] for a in "xy"] == from_csv["com_m"]
    cov_bag = np.reshape(ros_bag["pose_with_covariance_stamped"]["pose"]["covariance"], (6, 6))
    cov_csv = np.reshape(ros_csv["pose_with_covariance_stamped"]["pose"]["covariance"], (6, 6))
    flip = np.diag([1.0, -1.0])  # the mask's y down is the object's y up
    np.testing.assert_allclose(cov_bag[:2, :2], flip @ cov_csv[:2, :2] @ flip, atol=1e-18)
    assert com_object == rec.object_from_pixels(np.array(from_bag["com_px"]))[0].tolist()
    assert from_bag["n_pushes"] == 6 and from_bag["resolution"] == 0.0025


def test_resolution_sets_the_pixel_size_of_the_mask(recorded, capsys):
    code, result, err = run_json(
        capsys, bag_args(recorded, "--method", "centroid", "--resolution", "0.002")
    )
    assert code == 0, err
    assert result["resolution"] == 0.002


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda a: [*a, "--mask", "x.png"], "--bag replaces --mask and --pushes"),
        (lambda a: [*a, "--example"], "not --bag with --example"),
        (lambda a: [*a, "--roi", "0,0,5,5"], "not --bag with --roi"),
        (
            lambda a: [*a, "--theta-units", "deg"],
            "--theta-units deg: the rotations read from --bag are radians",
        ),
        (
            lambda a: a[: a.index("--outline")] + a[a.index("--outline") + 2 :],
            "--outline required with --bag",
        ),
        (
            lambda a: a[: a.index("--object-topic")] + a[a.index("--object-topic") + 2 :],
            "--object-topic required with --bag",
        ),
        (lambda a: [x if x != "/tip" else "/nope" for x in a], "--bag: topic '/nope' is not in"),
        (
            lambda a: [*a, "--object-child-frame", "plate"],
            "--bag: child_frame is for topics of transforms",
        ),
    ],
)
def test_bad_bag_options_exit_2_with_one_line(recorded, capsys, change, message):
    code = main([*change(bag_args(recorded)), "--no-overlay"])
    captured = capsys.readouterr()
    assert code == 2 and captured.out == ""
    assert message in captured.err and captured.err.count("\n") == 1, captured.err


def test_bag_options_without_bag_and_a_missing_outline(recorded, tmp_path, capsys):
    assert main(["estimate", "--example", "--object-topic", "/plate", "--no-overlay"]) == 2
    assert "--object-topic need --bag" in capsys.readouterr().err
    argv = bag_args(recorded)
    argv[argv.index("--outline") + 1] = str(tmp_path / "none.csv")
    assert main([*argv, "--no-overlay"]) == 2
    assert "--outline: path: no such file" in capsys.readouterr().err


def test_without_rosbags_the_message_says_what_to_install(recorded, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "rosbags.highlevel", None)
    assert main([*bag_args(recorded), "--no-overlay"]) == 2
    assert (
        "--bag: reading ROS bags needs rosbags: pip install comcore[ros]" in capsys.readouterr().err
    )


def test_the_ros_frame_is_the_object_child_frame_or_the_one_named(recorded, capsys):
    code, result, err = run_json(capsys, bag_args(recorded, "--method", "centroid"))
    assert code == 0, err
    assert result["ros"]["inertia_stamped"]["header"]["frame_id"] == "object"
    code, result, err = run_json(
        capsys, bag_args(recorded, "--method", "centroid", "--frame-id", "plate")
    )
    assert result["ros"]["pose_with_covariance_stamped"]["header"]["frame_id"] == "plate"


def test_travel_sets_the_push_window_and_a_longer_one_skips_every_push(recorded, capsys):
    path, outline, _ = recorded
    code, result, err = run_json(capsys, bag_args(recorded, "--model", "none", "--travel", "0.02"))
    assert code == 0, err
    rec = bag.recording_from_bag(path, "/plate/pose", "/tip", outline, bags.RADIUS, travel=0.02)
    expected = estimate(
        rec.mask, rec.actions, rec.motions, "posterior", model="none", pusher_radius=bags.RADIUS
    )
    assert result["com_px"] == list(expected.com)
    _, default, _ = run_json(capsys, bag_args(recorded, "--model", "none"))
    assert default["com_px"] != result["com_px"]  # another window, other motions
    assert main([*bag_args(recorded, "--travel", "0.04"), "--no-overlay"]) == 2
    assert "less than the window's 40.0 mm" in capsys.readouterr().err
    assert main([*bag_args(recorded, "--travel", "25"), "--no-overlay"]) == 2
    assert "--travel 25 m is implausible" in capsys.readouterr().err
    assert main(["estimate", "--example", "--travel", "0.02", "--no-overlay"]) == 2
    assert "--travel needs --bag" in capsys.readouterr().err


def test_the_ros_stamp_is_the_bags_time_at_the_end_of_the_last_push(recorded, capsys):
    _, _, rec = recorded
    code, result, err = run_json(capsys, bag_args(recorded, "--method", "centroid"))
    assert code == 0, err
    log = bags.simulated_log(n_pushes=6)
    end = bags.bag_start_ns(log, types=("/plate/pose",)) + round(rec.pushes[-1].end_time * 1e9)
    expected = {"sec": end // 10**9, "nanosec": end % 10**9}
    for message in ("inertia_stamped", "pose_with_covariance_stamped"):
        assert result["ros"][message]["header"]["stamp"] == expected
    assert expected["sec"] > bags.START_NS // 10**9
