"""``comcore estimate --frames``: the frames a camera saw during a recording's pushes."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

import comcore
from comcore.active._options import DEFAULT_PUSHER_RADIUS, DEFAULT_TARGET_RADIUS
from comcore.cli import main
from comcore.cli.estimate import BOOTSTRAP, CREDIBLE, SYSTEMATIC_ERROR

simulators = pytest.importorskip("simulators")
pytest.importorskip("shapely")
pytest.importorskip("matplotlib")

PUSHES_HEADER = "sx,sy,ex,ey,theta,tx,ty\n"
FRAMES_HEADER = "push,px,py,theta,tx,ty\n"
#: A push along the image's left edge, far from the object: screening drops it.
MISS = (1.0, 1.0, 1.0, 30.0)


@pytest.fixture(scope="module")
def recording():
    """Five pushes of Obj3 from the pose of its first mask, each with its frames at 10 Hz."""
    sim = simulators.random_simulator("Obj3", friction="high", rng=1)
    robot = simulators.SimulatedRobot(sim, camera_margin=0.04, rng=1)
    first = robot.camera_mask()
    pushes = []
    for action in comcore.sample_pushes(first, 5, rng=0):
        robot.place()  # every push from the pose of the mask, as the pushes CSV's are
        pushes.append(robot.execute(action, frame_rate=10.0))
    assert all(p.hit and p.path for p in pushes)
    return first, pushes


def _number(value: float) -> str:
    return repr(float(value))


def write_recording(folder, first, pushes, *, degrees=False, miss_at=None):
    """The mask, pushes and frames files of ``pushes``; ``miss_at``: a missing push there.

    The frames are each push's ``path`` (the pusher) with the robot's true pose then (the
    motion since the push began: every push starts from the mask's pose). ``degrees``:
    every theta, of the pushes and the frames, in degrees.
    """
    from matplotlib.image import imsave

    mask = folder / "object.png"
    imsave(mask, first.data.astype(float), cmap="gray", vmin=0, vmax=1)
    scale = 180 / math.pi if degrees else 1.0
    rows, frame_rows = [], []
    for p in pushes:
        theta, tx, ty = p.motion
        rows.append([*p.commanded, theta * scale, tx, ty])
        frame_rows.append([(*f.pusher, m.theta * scale, m.tx, m.ty)
                           for f, m in zip(p.path, p.path_poses)])  # fmt: skip
    if miss_at is not None:  # three frames along it, the object unmoved
        rows.insert(miss_at, [*MISS, 0.0, 0.0, 0.0])
        frame_rows.insert(miss_at, [(1.0, y, 0.0, 0.0, 0.0) for y in (5.0, 10.0, 15.0)])
    pushes_csv, frames_csv = folder / "pushes.csv", folder / "frames.csv"
    pushes_csv.write_text(PUSHES_HEADER + "".join(",".join(map(_number, r)) + "\n" for r in rows))
    frames_csv.write_text(FRAMES_HEADER + "".join(
        f"{k},{','.join(map(_number, f))}\n" for k, fs in enumerate(frame_rows, 1) for f in fs
    ))  # fmt: skip
    return mask, pushes_csv, frames_csv


def run_json(capsys, mask, pushes_csv, *extra):
    args = ["estimate", "--mask", str(mask), "--pushes", str(pushes_csv), "--resolution",
            "0.0025", "--json", "--no-overlay", *extra]  # fmt: skip
    code = main(args)
    captured = capsys.readouterr()
    return code, (json.loads(captured.out) if captured.out else None), captured.err


def direct(first, pushes, frames=True):
    """``comcore.estimate_posterior`` with the command's options, the frames as motions."""
    given = None
    if frames:
        given = [[comcore.PushFrame(f.pusher, m) for f, m in zip(p.path, p.path_poses)]
                 for p in pushes]  # fmt: skip
    return comcore.estimate_posterior(
        first, [p.commanded for p in pushes], [p.motion for p in pushes], credible=CREDIBLE,
        pusher_radius=DEFAULT_PUSHER_RADIUS,
        likelihood=comcore.Likelihood(systematic_error=SYSTEMATIC_ERROR), bootstrap=BOOTSTRAP,
        target_radius=DEFAULT_TARGET_RADIUS, theta_units="rad",
        frames=given,
    )  # fmt: skip


@pytest.fixture(scope="module")
def expected(recording):
    first, pushes = recording
    return direct(first, pushes)


@pytest.fixture
def files(recording, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return write_recording(tmp_path, *recording)


def test_the_command_is_estimate_posterior_with_the_frames(recording, expected, files, capsys):
    _, pushes = recording
    mask, pushes_csv, frames_csv = files
    code, result, _ = run_json(capsys, mask, pushes_csv, "--frames", str(frames_csv))
    assert code == 0
    assert result["com_px"] == pytest.approx(expected.com, abs=1e-9)
    assert result["region"]["credible_radius_px"] == pytest.approx(
        expected.posterior.credible_radius_px, abs=1e-9
    )
    assert result["n_frames"] == sum(len(p.path) for p in pushes)
    # per push, the frames the records dropped, named by their frames CSV line (header: 1)
    first_line = np.cumsum([2] + [len(p.path) for p in pushes])
    want = [
        {"push": k + 1, "line": k + 2,
         "frames": [{"line": int(first_line[k]) + j, "reason": why} for j, why in r.dropped_frames]}
        for k, r in enumerate(expected.pushes) if r.dropped_frames
    ]  # fmt: skip
    assert result["dropped_frames"] == want and want
    scored = sum(len(r.path) for r in expected.pushes)
    assert scored > 0
    assert result["n_frames"] == scored + sum(len(p["frames"]) for p in want)


def test_the_frames_change_the_estimate(expected, files, capsys):
    mask, pushes_csv, _ = files
    code, plain, _ = run_json(capsys, mask, pushes_csv)
    assert code == 0 and plain["n_frames"] == 0 and plain["dropped_frames"] == []
    assert np.hypot(*np.subtract(plain["com_px"], expected.com)) > 1e-3


def test_the_text_output_counts_the_frames(recording, expected, files, capsys):
    mask, pushes_csv, frames_csv = files
    assert main(["estimate", "--mask", str(mask), "--pushes", str(pushes_csv), "--resolution",
                 "0.0025", "--no-overlay", "--frames", str(frames_csv)]) == 0  # fmt: skip
    n_read = sum(len(p.path) for p in recording[1])
    scored = sum(len(r.path) for r in expected.pushes)
    line = f"frames: {n_read} read, {scored} scored along their pushes, {n_read - scored} not"
    assert line in capsys.readouterr().out


def test_theta_units_deg_applies_to_the_frames_theta(recording, expected, tmp_path, capsys):
    mask, pushes_csv, frames_csv = write_recording(tmp_path, *recording, degrees=True)
    code, result, _ = run_json(capsys, mask, pushes_csv, "--frames", str(frames_csv),
                               "--theta-units", "deg")  # fmt: skip
    assert code == 0
    assert result["com_px"] == pytest.approx(expected.com, abs=1e-9)


def test_the_frames_of_a_dropped_push_are_dropped_with_it(recording, tmp_path, capsys):
    first, pushes = recording
    mask, pushes_csv, frames_csv = write_recording(tmp_path, first, pushes, miss_at=1)
    code, result, err = run_json(capsys, mask, pushes_csv, "--frames", str(frames_csv))
    assert code == 0
    # push 2 (pushes CSV line 3) misses; its frames are the frames CSV's lines after push 1's
    lines = [2 + len(pushes[0].path) + j for j in range(3)]
    assert "dropped 1 of 6 pushes" in err and "CSV line(s) 3 " in err
    assert f"their 3 frame(s) are dropped with them: --frames line(s) {lines[0]}, " in err
    assert result["dropped_lines"] == {"3": "misses the object"}
    entry = result["dropped_frames"][1]
    assert entry == {
        "push": 2,
        "line": 3,
        "frames": [{"line": line, "reason": "push_dropped: misses the object"} for line in lines],
    }
    # the other pushes and their frames as without the missing push
    assert result["com_px"] == pytest.approx(direct(first, pushes).com, abs=1e-9)
    code, _, err = run_json(capsys, mask, pushes_csv, "--frames", str(frames_csv), "--strict")
    assert code == 2 and "--strict: 1 push(es) miss the object" in err


def test_the_frames_of_a_push_that_did_not_move_the_object_are_not_read(recording, files, capsys):
    _, pushes = recording
    mask, pushes_csv, frames_csv = files
    _rewrite(pushes_csv, lambda ls: [*ls[:3], ",".join([*ls[3].split(",")[:4], "0", "0", "0"]),
                                     *ls[4:]])  # fmt: skip
    code, result, _ = run_json(capsys, mask, pushes_csv, "--frames", str(frames_csv))
    assert code == 0
    first_line = 2 + len(pushes[0].path) + len(pushes[1].path)
    (entry,) = [e for e in result["dropped_frames"] if e["push"] == 3]
    assert entry["line"] == 4
    assert entry["frames"] == [
        {"line": first_line + j, "reason": "push_miss: the object moved less than the noise"}
        for j in range(len(pushes[2].path))
    ]


def _rewrite(path, edit) -> None:
    lines = path.read_text().splitlines()
    path.write_text("\n".join(edit(lines)) + "\n")


def _set(line: int, column: int, value: str):
    def edit(lines):
        cells = lines[line - 1].split(",")
        cells[column] = value
        lines[line - 1] = ",".join(cells)
        return lines

    return edit


#: name: (extra options, or an edit of the frames CSV's lines), what the one-line error says
REFUSED = {
    "with --example": (["--example"], "--frames goes with --mask and --pushes, not --example"),
    "with --bag": (["--bag", "x.bag"], "--frames goes with --mask and --pushes, not --bag"),
    "without --pushes": (["no pushes"], "--frames needs --pushes"),
    "with alg2": (["--method", "alg2"], "--frames needs --method posterior (the default): alg2"),
    "with model none": (["--model", "none"], "--frames needs --model limit-surface"),
    "missing column": (lambda ls: [ls[0].replace(",ty", "")] + [c.rsplit(",", 1)[0]
                                                             for c in ls[1:]],
                       "frames.csv lacks column(s) ty; expected push, px, py, theta, tx, ty"),
    "extra column": (lambda ls: [ls[0] + ",time"] + [c + ",0" for c in ls[1:]],
                     "frames.csv has column(s) time that are not frame columns"),
    "column twice": (lambda ls: [ls[0] + ",px"] + [c + ",0" for c in ls[1:]],
                     "frames.csv has column(s) px twice"),
    "a short row": (lambda ls: [*ls[:3], ls[3].rsplit(",", 1)[0], *ls[4:]],
                    "frames.csv line 4: 5 values, the header has 6"),
    "not a number": (_set(3, 1, "x"), "frames.csv line 3, column px: 'x' is not a number"),
    "not finite": (_set(5, 3, "inf"), "frames.csv line 5, column theta: 'inf' is not finite"),
    "push 0": (_set(2, 0, "0"), "frames.csv line 2, column push: '0' is not a push of the "
               "pushes CSV: its 5 pushes are numbered 1 to 5 in the order of its rows (push 1 "
               "is its first data row, line 2)"),
    "push past the last": (_set(7, 0, "6"), "line 7, column push: '6' is not a push"),
    "push not an integer": (_set(2, 0, "1.5"), "line 2, column push: '1.5' is not a push"),
    # push 1's 20 frames reversed: each 0.8 px behind the one before, refused past 1 px
    "out of order": (lambda ls: [ls[0], *reversed(ls[1:21]), *ls[21:]],
                     r"frames.csv push 1 \(pushes CSV line 2\): line 4's pusher is [\d.]+ px "
                     "behind the frame before it along the push: frames must be given in the "
                     "order they were taken"),
    "off the path": (_set(30, 2, "90.0"), r"frames.csv push 2 \(pushes CSV line 3\): line 30's "
                     r"pusher \[.*\] lies [\d.]+ px off the push's path"),
}  # fmt: skip


@pytest.mark.parametrize("name", list(REFUSED))
def test_bad_frames_and_options_are_refused_in_one_line(files, capsys, name):
    mask, pushes_csv, frames_csv = files
    change, message = REFUSED[name]
    args = ["estimate", "--mask", str(mask), "--pushes", str(pushes_csv), "--resolution",
            "0.0025", "--no-overlay", "--frames", str(frames_csv)]  # fmt: skip
    if callable(change):
        _rewrite(frames_csv, change)
    elif change == ["no pushes"]:
        args.remove("--pushes")
        args.remove(str(pushes_csv))
    else:
        if change[0] in ("--example", "--bag"):
            args = args[:1] + args[5:]  # their own inputs, without --mask and --pushes
        args += change
    assert main(args) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("comcore estimate: ")
    assert re.search(message if "\\" in message else re.escape(message), lines[0]), lines[0]
