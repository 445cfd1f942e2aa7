"""``comcore estimate``: the CoM from a user's mask image and pushes CSV; bad files."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import comcore
from comcore._cli import main

HEADER = "sx,sy,ex,ey,theta,tx,ty\n"
# A 20 x 20 square (pixels 4..23) pushed across its rows and columns; the
# signs follow the Voting Theorem for a CoM at (10.5, 10.5).
PUSHES = [
    (0, 13, 30, 13, 0.2, 3, 0),
    (13, 0, 13, 30, -0.2, 0, 3),
    (0, 8, 30, 8, -0.3, 3, 0),
    (8, 0, 8, 30, 0.3, 0, 3),
]


def write_png(path, image: np.ndarray) -> None:
    from matplotlib.image import imsave

    imsave(path, image.astype(float), cmap="gray", vmin=0, vmax=1)


@pytest.fixture
def files(tmp_path):
    pytest.importorskip("matplotlib")
    mask = tmp_path / "object.png"
    write_png(mask, np.pad(np.ones((20, 20)), 4))
    pushes = tmp_path / "pushes.csv"
    pushes.write_text(HEADER + "".join(",".join(map(str, p)) + "\n" for p in PUSHES))
    return tmp_path, mask, pushes


def test_json_output_matches_the_library(files, capsys):
    _, mask, pushes = files
    assert main(["estimate", "--mask", str(mask), "--pushes", str(pushes), "--json",
                 "--resolution", "0.01"]) == 0  # fmt: skip
    result = json.loads(capsys.readouterr().out)
    m = comcore.Mask(np.pad(np.ones((20, 20), bool), 4), resolution=0.01)
    expected = comcore.estimate_progressive(m, [p[:4] for p in PUSHES], [p[4:] for p in PUSHES])
    assert result["com_px"] == pytest.approx(expected.com)
    assert result["com_m"] == pytest.approx([0.01 * v for v in expected.com])
    assert result["status"] == "ok" and result["used"] == list(expected.used)


@pytest.mark.parametrize("method", ["alg1", "alg2", "alg2-rotation", "centroid"])
def test_text_output_and_overlay(files, capsys, method):
    tmp, mask, pushes = files
    overlay = tmp / f"overlay-{method}.png"
    args = ["estimate", "--mask", str(mask), "--pushes", str(pushes), "--method", method,
            "--overlay", str(overlay)]  # fmt: skip
    assert main(args) == 0
    out = capsys.readouterr().out
    assert out.startswith("CoM: (") and " px = (" in out and f"method {method}" in out
    assert overlay.read_bytes()[:4] == b"\x89PNG"


def test_overlay_is_written_next_to_the_mask_by_default(files, capsys):
    tmp, mask, pushes = files
    assert main(["estimate", "--mask", str(mask), "--pushes", str(pushes), "--json"]) == 0
    default = tmp / "object-overlay.png"
    assert json.loads(capsys.readouterr().out)["overlay"] == str(default)
    assert default.read_bytes()[:4] == b"\x89PNG"


def test_no_overlay_writes_no_picture(files, capsys):
    tmp, mask, pushes = files
    assert main(["estimate", "--mask", str(mask), "--pushes", str(pushes), "--no-overlay"]) == 0
    assert "overlay" not in capsys.readouterr().out
    assert sorted(p.name for p in tmp.iterdir()) == ["object.png", "pushes.csv"]


def test_overlay_and_no_overlay_exclude_each_other(files, capsys):
    _, mask, pushes = files
    with pytest.raises(SystemExit) as e:
        main(["estimate", "--mask", str(mask), "--pushes", str(pushes), "--overlay", "a.png",
              "--no-overlay"])  # fmt: skip
    assert e.value.code == 2 and "not allowed with argument" in capsys.readouterr().err


def test_without_matplotlib_the_default_overlay_is_skipped_with_a_note(files, capsys, monkeypatch):
    pytest.importorskip("cv2")  # reads the mask when matplotlib is gone
    tmp, mask, pushes = files
    monkeypatch.setitem(sys.modules, "matplotlib.figure", None)
    assert main(["estimate", "--mask", str(mask), "--pushes", str(pushes), "--json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["overlay"] is None
    assert "no overlay written" in captured.err and "pip install comcore[plot]" in captured.err
    assert not (tmp / "object-overlay.png").exists()
    asked = ["estimate", "--mask", str(mask), "--pushes", str(pushes), "--overlay", "o.png"]
    assert main(asked) == 2
    assert "pip install comcore[plot]" in capsys.readouterr().err


def bad_case(tmp, name):
    mask, pushes = tmp / "object.png", tmp / "pushes.csv"
    if name == "missing mask":
        return ["--mask", str(tmp / "nope.png"), "--pushes", str(pushes)], "no such file"
    if name == "not an image":
        (tmp / "text.png").write_text("hello")
        return ["--mask", str(tmp / "text.png"), "--pushes", str(pushes)], "cannot read"
    if name == "empty mask":
        write_png(tmp / "black.png", np.zeros((10, 10)))
        return ["--mask", str(tmp / "black.png"), "--pushes", str(pushes)], "at least one object"
    if name == "missing column":
        pushes.write_text("sx,sy,ex,ey,theta,tx\n0,13,30,13,0.2,3\n")
        return ["--mask", str(mask), "--pushes", str(pushes)], "lacks column(s) ty"
    if name == "NaN":
        pushes.write_text(HEADER + "0,13,30,13,nan,3,0\n")
        return ["--mask", str(mask), "--pushes", str(pushes)], "column theta: 'nan' is not finite"
    if name == "not a number":
        pushes.write_text(HEADER + "0,13,30,13,0.1,3,0\n0,x,30,13,0.1,3,0\n")
        return ["--mask", str(mask), "--pushes", str(pushes)], "line 3, column sy: 'x'"
    if name == "no rows":
        pushes.write_text(HEADER)
        return ["--mask", str(mask), "--pushes", str(pushes)], "holds no push"
    if name == "binary csv":
        return ["--mask", str(mask), "--pushes", str(mask)], "cannot read"
    if name == "bad resolution":
        return ["--mask", str(mask), "--pushes", str(pushes), "--resolution", "-1"], "resolution"
    raise AssertionError(name)


CASES = ["missing mask", "not an image", "empty mask", "missing column", "NaN", "not a number",
         "no rows", "binary csv", "bad resolution"]  # fmt: skip


@pytest.mark.parametrize("name", CASES)
def test_bad_files_exit_2_with_one_clear_line(files, capsys, name):
    args, message = bad_case(files[0], name)
    assert main(["estimate", *args]) == 2
    captured = capsys.readouterr()
    assert message in captured.err and captured.out == ""
    assert captured.err.startswith("comcore estimate: ") and captured.err.count("\n") == 1


def test_pushes_that_miss_the_object_exit_1(files, capsys):
    _, mask, pushes = files
    pushes.write_text(HEADER + "0,1,30,1,0.1,3,0\n")  # along row 1, above the object
    assert main(["estimate", "--mask", str(mask), "--pushes", str(pushes)]) == 1
    assert "the pushes do not fit the mask" in capsys.readouterr().err


def test_the_real_entry_point_never_prints_a_traceback(files):
    tmp, mask, _ = files
    (tmp / "nan.csv").write_text(HEADER + "0,13,30,13,0.1,nan,0\n")
    cmd = [sys.executable, "-m", "comcore", "estimate", "--mask", str(mask), "--pushes",
           str(tmp / "nan.csv")]  # fmt: skip
    root = str(Path(__file__).resolve().parent.parent)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([root, os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp, env=env)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "column tx: 'nan' is not finite" in done.stderr
