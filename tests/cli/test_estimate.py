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
from comcore.cli import main
from comcore.cli.estimate import SYSTEMATIC_ERROR
from tests.scripts import run_script

HEADER = "sx,sy,ex,ey,theta,tx,ty\n"
#: --resolution, which comcore estimate requires (unless --example): the conventions' 2.5 mm.
RES = ["--resolution", "0.0025"]
# A 20 x 20 square (pixels 4..23) pushed across its rows and columns; the motions are
# comcore.LimitSurfaceModel(pusher_radius=0.004)'s for a CoM at (10.5, 10.5) and mu = 0.3 at
# 2.5 mm per pixel (the default --model and --pusher-radius), rounded to 3 decimals.
PUSHES = [
    (0, 13, 30, 13, 1.344, 12.931, -12.832),
    (13, 0, 13, 30, -1.344, -12.832, 12.931),
    (0, 8, 30, 8, -1.08, 7.821, 9.148),
    (8, 0, 8, 30, 1.08, 9.148, 7.821),
]


def write_png(path, image: np.ndarray) -> None:
    from matplotlib.image import imsave

    imsave(path, image.astype(float), cmap="gray", vmin=0, vmax=1)


@pytest.fixture
def files(tmp_path, monkeypatch):
    """The data folder (the mask and the pushes), the mask, the pushes; run from another folder."""
    pytest.importorskip("matplotlib")
    data, run = tmp_path / "data", tmp_path / "run"
    data.mkdir()
    run.mkdir()
    monkeypatch.chdir(run)
    mask = data / "object.png"
    write_png(mask, np.pad(np.ones((20, 20)), 4))
    pushes = data / "pushes.csv"
    pushes.write_text(HEADER + "".join(",".join(map(str, p)) + "\n" for p in PUSHES))
    return data, mask, pushes


def test_json_output_matches_the_library(files, capsys):
    _, mask, pushes = files
    assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json",
                 "--resolution", "0.01", "--method", "alg2"]) == 0  # fmt: skip
    result = json.loads(capsys.readouterr().out)
    m = comcore.Mask(np.pad(np.ones((20, 20), bool), 4), resolution=0.01)
    expected = comcore.estimate_progressive(m, [p[:4] for p in PUSHES], [p[4:] for p in PUSHES])
    assert result["com_px"] == pytest.approx(expected.com)
    assert result["com_m"] == pytest.approx([0.01 * v for v in expected.com])
    # consistent, its final region (radius 3.4 px = 34 mm) wider than the 6 mm target
    assert result["status"] == expected.status == "wide"
    assert result["used_lines"] == [i + 2 for i in expected.used]  # CSV lines: header is line 1
    assert result["region"]["area_px"] == int(expected.region.sum())


@pytest.mark.parametrize("method", ["posterior", "alg1", "alg2", "alg2-rotation", "centroid"])
def test_text_output_and_overlay(files, capsys, method):
    tmp, mask, pushes = files
    overlay = tmp / f"overlay-{method}.png"
    args = ["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--method", method,
            "--overlay", str(overlay)]  # fmt: skip
    assert main(args) == 0
    out = capsys.readouterr().out
    assert out.startswith("CoM: (") and f"method {method}" in out
    assert overlay.read_bytes()[:4] == b"\x89PNG"


def test_the_text_says_which_frame_the_metres_are_in(files, capsys):
    _, mask, pushes = files
    args = ["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--no-overlay",
            "--method", "centroid"]  # fmt: skip
    assert main(args) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == (
        "CoM: (13.50, 13.50) px (column, row) = (0.0338, 0.0338) m in the image's frame: from "
        "the centre of its top-left pixel, x right, y down (pixels times --resolution, not a "
        "position on the table)"
    )


def test_overlay_is_written_to_the_current_folder_by_default(files, capsys):
    data, mask, pushes = files
    assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["overlay"] == "object-overlay.png"
    assert Path("object-overlay.png").read_bytes()[:4] == b"\x89PNG"
    assert sorted(p.name for p in data.iterdir()) == ["object.png", "pushes.csv"]  # untouched


def test_no_overlay_writes_no_picture(files, capsys):
    tmp, mask, pushes = files
    assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--no-overlay"]) == 0
    assert "overlay" not in capsys.readouterr().out
    assert sorted(p.name for p in tmp.iterdir()) == ["object.png", "pushes.csv"]


def test_overlay_and_no_overlay_exclude_each_other(files, capsys):
    _, mask, pushes = files
    with pytest.raises(SystemExit) as e:
        main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--overlay", "a.png",
              "--no-overlay"])  # fmt: skip
    assert e.value.code == 2 and "not allowed with argument" in capsys.readouterr().err


def test_without_matplotlib_the_default_overlay_is_skipped_with_a_note(files, capsys, monkeypatch):
    pytest.importorskip("cv2")  # reads the mask when matplotlib is gone
    tmp, mask, pushes = files
    monkeypatch.setitem(sys.modules, "matplotlib.figure", None)
    monkeypatch.delitem(sys.modules, "comcore.plot", raising=False)
    assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["overlay"] is None
    assert "no overlay written" in captured.err and "pip install comcore[plot]" in captured.err
    assert not Path("object-overlay.png").exists() and not (tmp / "object-overlay.png").exists()
    asked = ["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--overlay", "o.png"]
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
        return ["--mask", str(tmp / "black.png"), "--pushes", str(pushes)], "black.png: "
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
    if name == "centimetres for metres":
        args = ["--mask", str(mask), "--pushes", str(pushes), "--resolution", "2.5"]
        return args, "--resolution 2.5 m per pixel is implausible"
    if name == "zero-length push":
        pushes.write_text(HEADER + "0,13,30,13,0.1,3,0\n5,5,5,5,0.1,3,0\n")
        return ["--mask", str(mask), "--pushes", str(pushes)], "line 3: the push has zero length"
    if name == "line after a blank line":
        pushes.write_text(HEADER + "0,13,30,13,0.1,3,0\n\n0,13,30,13,0.1,inf,0\n")
        return ["--mask", str(mask), "--pushes", str(pushes)], "line 4, column tx: 'inf'"
    if name == "no push hits":
        pushes.write_text(HEADER + "0,1,30,1,0.1,3,0\n")  # along row 1, above the object
        return ["--mask", str(mask), "--pushes", str(pushes)], "no push hits the object"
    if name == "negative bootstrap":
        args = ["--mask", str(mask), "--pushes", str(pushes), "--bootstrap", "-1"]
        return args, "--bootstrap must be 0 to 10000 resamplings, got -1"
    if name == "example and files":
        return ["--example", "--mask", str(mask)], "--example replaces --mask and --pushes"
    if name == "no input":
        return ["--mask", str(mask)], "--pushes required (or --example, or --bag)"
    raise AssertionError(name)


CASES = ["missing mask", "not an image", "empty mask", "missing column", "NaN", "not a number",
         "no rows", "binary csv", "bad resolution", "centimetres for metres", "zero-length push",
         "line after a blank line", "no push hits", "negative bootstrap", "example and files",
         "no input"]  # fmt: skip


@pytest.mark.parametrize("name", CASES)
def test_bad_files_exit_2_with_one_clear_line(files, capsys, name):
    args, message = bad_case(files[0], name)
    assert main(["estimate", *RES, *args]) == 2
    captured = capsys.readouterr()
    assert message in captured.err and captured.out == ""
    assert captured.err.startswith("comcore estimate: ") and captured.err.count("\n") == 1


# Pushes that give no contact, each on the CSV line it gets below: a graze past the
# square's top edge (pixel centres from row 4: the path at y = 3.49 misses them by 0.01 px),
# a miss far away, and a start inside the object.
BAD_PUSHES = {
    4: ((0, 0.5, 30, 0.5, 0.1, 3, 0), "misses the object"),
    6: ((0, 1, 30, 1, 0.1, 3, 0), "misses the object"),
    7: ((10, 10, 30, 10, 0.1, 3, 0), "starts inside the object"),
}


def with_bad_pushes(path):
    rows = list(PUSHES)
    for line in sorted(BAD_PUSHES):
        rows.insert(line - 2, BAD_PUSHES[line][0])
    path.write_text(HEADER + "".join(",".join(map(str, p)) + "\n" for p in rows))


def test_pushes_without_contact_are_dropped_with_one_warning_naming_their_lines(files, capsys):
    _, mask, pushes = files
    args = ["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json", "--no-overlay"]
    assert main(args) == 0
    clean = json.loads(capsys.readouterr().out)
    with_bad_pushes(pushes)
    assert main(args) == 0
    captured = capsys.readouterr()
    result = json.loads(captured.out)
    assert result["com_px"] == clean["com_px"] and result["n_pushes"] == 7
    assert result["dropped_lines"] == {str(k): why for k, (_, why) in BAD_PUSHES.items()}
    assert captured.err.count("\n") == 1
    assert "dropped 3 of 7 pushes" in captured.err and "CSV line(s) 4, 6, 7" in captured.err


def test_a_graze_the_pushers_disc_touches_is_kept_by_the_posterior_and_dropped_by_alg2(
    files, capsys
):
    # 0.01 px above the square's top edge: the leading point's line misses, the 4 mm disc
    # (1.6 px) touches; the posterior scores the disc's contact, Alg. 2 a point pusher's.
    _, mask, pushes = files
    rows = [*PUSHES, (0, 3.49, 30, 3.49, 0.1, 3, 0)]
    pushes.write_text(HEADER + "".join(",".join(map(str, p)) + "\n" for p in rows))
    base = ["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json", "--no-overlay"]
    assert main([*base, "--model", "none"]) == 0
    assert json.loads(capsys.readouterr().out)["dropped_lines"] == {}
    assert main([*base, "--method", "alg2"]) == 0
    dropped = json.loads(capsys.readouterr().out)["dropped_lines"]
    assert dropped == {str(len(rows) + 1): "misses the object"}


def test_used_pushes_are_named_by_csv_line_after_drops(files, capsys):
    _, mask, pushes = files
    with_bad_pushes(pushes)
    assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json",
                 "--method", "alg2"]) == 0  # fmt: skip
    used = json.loads(capsys.readouterr().out)["used_lines"]
    kept_lines = [2, 3, 5, 8]  # the lines of PUSHES once the bad ones are in
    m = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    expected = comcore.estimate_progressive(m, [p[:4] for p in PUSHES], [p[4:] for p in PUSHES])
    assert used == [kept_lines[i] for i in expected.used]


def test_strict_refuses_pushes_without_contact(files, capsys):
    _, mask, pushes = files
    with_bad_pushes(pushes)
    assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--strict"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "--strict: 3 push(es)" in captured.err
    assert "CSV line(s) 4, 6, 7" in captured.err


def test_help_shows_the_defaults_and_the_unit(capsys):
    with pytest.raises(SystemExit):
        main(["estimate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--resolution METRES_PER_PIXEL required (unless --example or --bag): the size of one " \
        "image pixel on the table, in METRES per pixel" in text
    # no default for a camera's scale; with --bag it is the drawn mask's pixel, which has one
    assert "[1e-05, 0.05] are refused. With --bag: the pixel size of the mask drawn from " \
        "--outline (default 0.0025)" in text and text.count("default 0.0025") == 1
    assert "estimator (default posterior)" in text and "(default auto:" in text


def test_the_overlay_says_when_it_replaces_a_file(files, capsys):
    _, mask, pushes = files
    args = ["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--method", "centroid"]
    assert main(args) == 0
    assert "replaced" not in capsys.readouterr().out
    assert main(args) == 0
    assert "overlay: object-overlay.png (replaced the existing file)" in (
        capsys.readouterr().out
    )
    assert main([*args, "--json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["overlay_replaced"] is True
    assert "overwrote the existing file" in captured.err


def estimate_json(capsys, mask, pushes, *extra):
    args = ["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json", "--no-overlay",
            "--method", "alg2", *extra]  # fmt: skip
    code = main(args)
    captured = capsys.readouterr()
    return code, (json.loads(captured.out) if captured.out else None), captured.err


def test_an_inverted_mask_gives_the_same_object(files, capsys):
    tmp, mask, pushes = files
    write_png(tmp / "inverted.png", 1 - np.pad(np.ones((20, 20)), 4))
    _, clean, _ = estimate_json(capsys, mask, pushes)
    for side in ("auto", "dark"):
        code, result, err = estimate_json(capsys, tmp / "inverted.png", pushes, "--object", side)
        assert code == 0, err
        assert result["com_px"] == clean["com_px"]


def test_the_wrong_object_side_is_a_message_about_the_image(files, capsys):
    tmp, _, pushes = files
    write_png(tmp / "inverted.png", 1 - np.pad(np.ones((20, 20)), 4))
    code, _, err = estimate_json(capsys, tmp / "inverted.png", pushes, "--object", "bright")
    assert code == 2 and err.startswith(f"comcore estimate: --mask: {tmp / 'inverted.png'}: ")
    assert "must start outside" not in err and err.count("\n") == 1


def test_a_colour_photo_of_the_object_gives_its_mask(files, capsys):
    tmp, mask, pushes = files
    photo = np.zeros((28, 28, 3))
    photo[..., 1] = 0.8  # green table
    photo[4:24, 4:24] = (0.9, 0.1, 0.1)  # red object
    from matplotlib.image import imsave

    imsave(tmp / "photo.png", photo)
    _, clean, _ = estimate_json(capsys, mask, pushes)
    code, result, err = estimate_json(capsys, tmp / "photo.png", pushes)
    assert code == 0, err
    assert result["com_px"] == clean["com_px"]


def test_the_shipped_example_runs_and_beats_the_centroid(tmp_path, monkeypatch, capsys):
    pytest.importorskip("cv2")  # reads the example's PNG
    monkeypatch.chdir(tmp_path)
    from comcore.cli.estimate import example_files

    files = example_files()
    truth = json.loads(files["truth"].read_text())
    errors = {}
    for method in ("centroid", "alg2"):
        assert main(["estimate", "--example", "--json", "--no-overlay", "--method", method]) == 0
        result = json.loads(capsys.readouterr().out)
        # Alg. 2's final region (14 mm) is wider than the 6 mm target: consistent, "wide"
        assert result["status"] == {"centroid": "unchecked", "alg2": "wide"}[method]
        assert result["dropped_lines"] == {}
        errors[method] = float(np.hypot(*np.subtract(result["com_px"], truth["com_px"])))
    assert errors["alg2"] < errors["centroid"] / 2
    assert errors["alg2"] * truth["resolution"] < 0.02  # within 2 cm
    assert list(tmp_path.iterdir()) == []


def test_the_example_overlay_goes_to_the_current_folder(tmp_path, monkeypatch, capsys):
    pytest.importorskip("matplotlib")
    monkeypatch.chdir(tmp_path)
    assert main(["estimate", "--example"]) == 0
    assert "overlay: example-overlay.png" in capsys.readouterr().out
    assert (tmp_path / "example-overlay.png").read_bytes()[:4] == b"\x89PNG"


def test_posterior_method_reports_its_credible_region(files, capsys):
    _, mask, pushes = files
    assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json",
                 "--method", "posterior", "--no-overlay"]) == 0  # fmt: skip
    result = json.loads(capsys.readouterr().out)
    m = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    floor = comcore.Likelihood(systematic_error=SYSTEMATIC_ERROR)  # the CLI's default
    expected = comcore.estimate_posterior(m, [p[:4] for p in PUSHES], [p[4:] for p in PUSHES],
                                          credible=0.9, likelihood=floor)  # fmt: skip
    assert result["com_px"] == pytest.approx(expected.com)
    assert result["region"]["area_px"] == int(expected.region.sum())
    assert result["region"]["credible_radius_px"] == pytest.approx(
        expected.posterior.credible_radius_px
    )
    assert result["region"]["bootstrap"] == comcore.active.RECORDED_BOOTSTRAP == 200
    # --bootstrap 0: the posterior's own region, not the bagged one (estimate_posterior's)
    assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json",
                 "--bootstrap", "0", "--no-overlay"]) == 0  # fmt: skip
    plain = comcore.estimate_posterior(m, [p[:4] for p in PUSHES], [p[4:] for p in PUSHES],
                                       credible=0.9, likelihood=floor, bootstrap=0)  # fmt: skip
    result = json.loads(capsys.readouterr().out)
    assert result["region"]["area_px"] == int(plain.region.sum())
    assert result["region"]["bootstrap"] == 0
    assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--method",
                 "posterior", "--no-overlay"]) == 0  # fmt: skip
    assert "credible region:" in (out := capsys.readouterr().out)
    assert "(bagged: 200 resamplings of the pushes)" in out


def test_the_real_entry_point_never_prints_a_traceback(files):
    tmp, mask, _ = files
    (tmp / "nan.csv").write_text(HEADER + "0,13,30,13,0.1,nan,0\n")
    cmd = [sys.executable, "-m", "comcore", "estimate", *RES, "--mask", str(mask), "--pushes",
           str(tmp / "nan.csv")]  # fmt: skip
    root = str(Path(__file__).resolve().parents[2])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([root, os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp, env=env)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "column tx: 'nan' is not finite" in done.stderr


def test_the_methods_benchmark_script_runs():
    pytest.importorskip("shapely")
    args = ["--objects", "Obj3", "--seeds", "0", "--pushes", "12", "--flips", "0,1"]
    lines = run_script("benchmarks/accuracy/estimate_methods.py", *args, timeout=120).splitlines()
    assert lines[0].startswith("1 recordings (1 objects x seeds [0]), 12 pushes each")
    rows = [line.split(" | ")[0].lstrip("| ") for line in lines[3:] if line.startswith("| ")]
    expected = ["posterior", "alg2", "alg1", "centroid"]
    assert rows == [m for m in expected for _ in (0, 1)]
    assert lines[-4].startswith("time per estimate (median): ")
    assert lines[-3].startswith("comcore estimate's sign check: 0 wrong: flagged 0 of 1")
    assert lines[-2].startswith("posterior status: 0 wrong: ")
    assert lines[-1].startswith("alg2 status: 0 wrong: ")


def test_a_status_other_than_ok_is_a_warning_saying_what_it_means(files, capsys):
    _, mask, pushes = files
    # Both pushes cross the square left to right, the upper one turning it counter-clockwise
    # (CoM above row 8) and the lower one clockwise (CoM below row 18): no CoM is both.
    pushes.write_text(HEADER + "0,8,30,8,0.2,3,0\n0,18,30,18,-0.2,3,0\n")
    code, result, err = estimate_json(capsys, mask, pushes)
    assert code == 3 and result["status"] == "inconsistent"  # printed, not to be used
    assert "warning: status inconsistent: no CoM explains the observed motions well" in err
    assert "(Alg. 2: some pushes contradict the others" in err
    pushes.write_text(HEADER + "".join(",".join(map(str, p)) + "\n" for p in PUSHES))
    code, result, err = estimate_json(capsys, mask, pushes)
    # consistent, the region wider than the target: usable, explained in the output, no warning
    assert code == 0 and result["status"] == "wide" and err == ""


# -- camera frames: --threshold, --background, --roi ------------------------------------------
# The square of PUSHES, moved to (70, 50) in a 160 x 120 photo of a table lit from the left:
# the table runs from 0.2 to 0.8 (153 grey levels across), the object is dark, 2 % of the frame.
OFFSET = np.array([70, 50])


def lit_photo(tmp, with_object=True, name="lit.png"):
    table = np.tile(np.linspace(0.2, 0.8, 160), (120, 1))
    image = table.copy()
    if with_object:
        image[54:74, 74:94] = 0.05
    write_png(tmp / name, image)
    return tmp / name


def shifted_pushes(tmp):
    path = tmp / "shifted.csv"
    rows = [(*(np.array(p[:2]) + OFFSET), *(np.array(p[2:4]) + OFFSET), *p[4:]) for p in PUSHES]
    path.write_text(HEADER + "".join(",".join(map(str, r)) + "\n" for r in rows))
    return path


def test_a_lit_photo_needs_no_option_but_one_grey_level_fails(files, capsys):
    tmp, mask, pushes = files
    photo, shifted = lit_photo(tmp), shifted_pushes(tmp)
    _, clean, _ = estimate_json(capsys, mask, pushes)
    code, result, err = estimate_json(capsys, photo, shifted)
    assert code == 0, err
    assert result["com_px"] == pytest.approx(list(np.add(clean["com_px"], OFFSET)))
    code, _, err = estimate_json(capsys, photo, shifted, "--threshold", "otsu")
    assert code == 2 and "touches the image border" in err and "--threshold auto fits the light" in err


@pytest.mark.parametrize("option", ["--background", "--roi"])
def test_background_and_roi_are_passed_through(files, capsys, option):
    tmp, mask, pushes = files
    photo, shifted = lit_photo(tmp), shifted_pushes(tmp)
    value = str(lit_photo(tmp, False, "empty.png")) if option == "--background" else "60,40,110,90"
    _, clean, _ = estimate_json(capsys, mask, pushes)
    for threshold in ("auto", "otsu", "0.25" if option == "--background" else "100"):
        code, result, err = estimate_json(capsys, photo, shifted, option, value, "--threshold", threshold)
        assert code == 0, (threshold, err)
        assert result["com_px"] == pytest.approx(list(np.add(clean["com_px"], OFFSET)))


def test_an_empty_table_says_no_object(files, capsys):
    tmp, _, _ = files
    empty, shifted = lit_photo(tmp, False, "empty.png"), shifted_pushes(tmp)
    code, _, err = estimate_json(capsys, empty, shifted)
    assert code == 2 and "no object: the image matches the table" in err
    code, _, err = estimate_json(capsys, empty, shifted, "--background", str(empty))
    assert code == 2 and "no object: the image matches the background image" in err


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--threshold", "high"], "argument --threshold: expected auto, otsu or a grey level"),
        (["--roi", "1,2,3"], "argument --roi: expected x0,y0,x1,y1 (four integers, pixels)"),
    ],
)
def test_bad_camera_option_values_are_argparse_errors(files, capsys, extra, message):
    _, mask, pushes = files
    with pytest.raises(SystemExit) as e:
        estimate_json(capsys, mask, pushes, *extra)
    assert e.value.code == 2 and message in capsys.readouterr().err


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--roi", "0,0,2,2"], "roi (0, 0, 2, 2) leaves less than 3 x 3 pixels of the 28 x 28"),
        (["--background", "nowhere.png"], "--background: no such file: nowhere.png"),
        (["--roi", "0,0,15,28"], "touches the edge of roi (right): part of it may be outside"),
    ],
)
def test_bad_camera_options_exit_2_with_one_line(files, capsys, extra, message):
    _, mask, pushes = files
    code, _, err = estimate_json(capsys, mask, pushes, *extra)
    assert code == 2 and message in err and err.count("\n") == 1


# -- the status and the exit code ------------------------------------------------------------


def test_a_consistent_but_wide_region_is_wide_not_ok(files, capsys):
    # Two pushes of a recording leave a 90 % region some centimetres across: "ok" said the
    # answer was as good as an active session's 6 mm stop; it is consistent, and wide.
    _, mask, pushes = files
    pushes.write_text(HEADER + "".join(",".join(map(str, p)) + "\n" for p in PUSHES[:2]))
    code, result, err = estimate_json(capsys, mask, pushes, "--method", "posterior")
    assert code == 0 and err == ""
    assert result["region"]["radius_m"] > result["target_radius_m"] == 0.006
    assert result["status"] == "wide" and result["estimator_status"] == "wide"
    assert "consistent, but the region is wider than --target-radius (6 mm)" in (
        result["status_meaning"]
    )
    # a target as wide as the region makes the same answer "ok"
    target = str(result["region"]["radius_m"] * 1.01)
    code, wider, _ = estimate_json(capsys, mask, pushes, "--method", "posterior",
                                   "--target-radius", target)  # fmt: skip
    assert code == 0 and wider["status"] == "ok" and wider["com_px"] == result["com_px"]
    assert wider["target_radius_m"] == float(target)


def test_the_text_output_explains_the_status(files, capsys):
    _, mask, pushes = files
    assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--method",
                 "alg2", "--no-overlay"]) == 0  # fmt: skip
    out = capsys.readouterr().out
    assert "status wide: the pushes are consistent, but the region is wider than " in out


@pytest.mark.parametrize(
    ("rows", "extra", "code", "status"),
    [
        (PUSHES, (), 0, "wide"),  # Alg. 2's final region (8.5 mm) wider than 6 mm
        (PUSHES, ("--target-radius", "0.01"), 0, "ok"),
        ([(0, 8, 30, 8, 0.2, 3, 0), (0, 18, 30, 18, -0.2, 3, 0)], (), 3, "inconsistent"),
    ],
)
def test_the_exit_code_says_whether_to_use_the_answer(files, capsys, rows, extra, code, status):
    _, mask, pushes = files
    pushes.write_text(HEADER + "".join(",".join(map(str, p)) + "\n" for p in rows))
    got, result, _ = estimate_json(capsys, mask, pushes, *extra)
    assert (got, result["status"]) == (code, status)  # the JSON is printed either way


def test_the_help_documents_the_statuses_and_exit_codes(capsys):
    with pytest.raises(SystemExit) as e:
        main(["estimate", "--help"])
    out = capsys.readouterr().out
    assert e.value.code == 0 and "--target-radius" in out
    assert "exit codes:\n  0  an answer to use: ok, wide," in out
    assert "\n  3  status inconsistent: the answer is printed, but do not use it" in out
    assert "\n  wide          consistent, but the region is wider than --target-radius" in out


@pytest.mark.parametrize("value", ["0", "-0.01", "6"])
def test_a_bad_target_radius_is_refused(files, capsys, value):
    _, mask, pushes = files
    code, result, err = estimate_json(capsys, mask, pushes, "--target-radius", value)
    assert code == 2 and result is None and "--target-radius" in err


def test_the_centroid_baseline_says_it_checks_nothing(files, capsys):
    # its status is an Estimate's default; the meaning printed must not vouch for the pushes
    _, mask, pushes = files
    _, result, _ = estimate_json(capsys, mask, pushes, "--method", "centroid")
    assert result["status_meaning"] == "the area centroid, a baseline that uses no push: nothing is checked"


# -- theta in degrees where every turn is small (--theta-units) --------------------------------
DEGREES = (
    "the motion model and the data disagree, as if theta were in degrees: if it is, multiply "
    "the column by pi/180; if not, the theta of the model is wrong: check its sign and unit "
    "against a push whose turn you know"
)


@pytest.fixture(scope="module")
def small_turn_files(tmp_path_factory):
    """The L of tests/active/test_theta_units.py as an image, its pushes in radians and in degrees."""
    pytest.importorskip("matplotlib")
    from tests.active.test_theta_units import small_turn_recording

    mask, actions, motions = small_turn_recording()
    tmp = tmp_path_factory.mktemp("small-turns")
    image = tmp / "l.png"
    write_png(image, mask.data)
    files = {}
    for unit, factor in (("rad", 1.0), ("deg", 180 / np.pi)):
        rows = [",".join(f"{v:.6g}" for v in (*a, m[0] * factor, *m[1:]))
                for a, m in zip(actions, motions)]  # fmt: skip
        files[unit] = tmp / f"pushes-{unit}.csv"
        files[unit].write_text(HEADER + "\n".join(rows) + "\n")
    return image, files, mask.resolution


METHOD_ARGS = [("--method", m) for m in ("alg1", "alg2", "alg2-rotation", "centroid")]


@pytest.mark.parametrize("extra", [(), ("--model", "none"), *METHOD_ARGS])
def test_small_turns_in_degrees_are_refused_for_every_method(small_turn_files, capsys, extra):
    image, files, resolution = small_turn_files
    base = ["estimate", "--mask", str(image), "--resolution", str(resolution), "--json",
            "--no-overlay", *extra]  # fmt: skip
    assert main([*base, "--pushes", str(files["rad"])]) == 0
    honest = capsys.readouterr()
    assert json.loads(honest.out)["mistake"] is None and DEGREES not in honest.err
    assert main([*base, "--pushes", str(files["deg"])]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    assert captured.err.startswith(f"comcore estimate: --pushes: column theta: {DEGREES} (")
    assert "--theta-units deg converts it" in captured.err


def test_theta_units_deg_converts_and_rad_warns(small_turn_files, capsys):
    image, files, resolution = small_turn_files
    base = ["estimate", "--mask", str(image), "--resolution", str(resolution), "--json",
            "--no-overlay", "--method", "alg2"]  # fmt: skip
    assert main([*base, "--pushes", str(files["rad"])]) == 0
    honest = json.loads(capsys.readouterr().out)
    assert main([*base, "--pushes", str(files["deg"]), "--theta-units", "deg"]) == 0
    converted = json.loads(capsys.readouterr().out)
    assert converted["com_px"] == pytest.approx(honest["com_px"])
    assert converted["status"] == honest["status"] and converted["mistake"] is None
    # rad: estimated, reported inconsistent: exit 3, the answer not to be used
    assert main([*base, "--pushes", str(files["deg"]), "--theta-units", "rad"]) == 3
    captured = capsys.readouterr()
    vouched = json.loads(captured.out)
    assert vouched["status"] == "inconsistent" and vouched["mistake"].startswith(DEGREES)
    assert f"warning: status inconsistent: {DEGREES}" in captured.err
    with pytest.raises(SystemExit):
        main([*base, "--pushes", str(files["rad"]), "--theta-units", "degrees"])
    assert "invalid choice: 'degrees'" in capsys.readouterr().err


def test_without_resolution_the_error_says_what_it_is_and_how_to_measure_it(files, capsys):
    _, mask, pushes = files
    assert main(["estimate", "--mask", str(mask), "--pushes", str(pushes)]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    assert captured.err.startswith("comcore estimate: --resolution required (or --example, or --bag): ")
    assert "METRES per pixel" in captured.err and "photograph a ruler" in captured.err


def test_the_overlay_numbers_pushes_by_csv_line_as_the_text_does(files, capsys, monkeypatch):
    _, mask, pushes = files
    with_bad_pushes(pushes)  # CSV lines 2, 3, 5, 8 kept
    drawn = {}
    import comcore.plot

    plot = comcore.plot.plot_estimate

    def spy(*args, **kwargs):
        ax = plot(*args, **kwargs)
        drawn["numbers"] = sorted(int(t.get_text()) for t in ax.texts if t.get_text().isdigit())
        drawn["legend"] = [t.get_text() for t in ax.get_legend().get_texts()]
        return ax

    monkeypatch.setattr(comcore.plot, "plot_estimate", spy)
    for method in ("alg2", "posterior"):
        assert main(["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json",
                     "--method", method, "--overlay", f"{method}.png"]) == 0  # fmt: skip
        result = json.loads(capsys.readouterr().out)
        assert drawn["numbers"] == sorted(result["used_lines"]) and result["used_lines"]
        if method == "posterior":
            assert "90 % credible region" in drawn["legend"]


def test_json_carries_the_estimate_as_ros_messages(files, capsys):
    _, mask, pushes = files
    args = ["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--json",
            "--method", "posterior", "--model", "none", "--no-overlay"]  # fmt: skip
    assert main([*args, "--frame-id", "table_cam"]) == 0
    result = json.loads(capsys.readouterr().out)
    ros = result["ros"]
    com = ros["inertia_stamped"]["inertia"]["com"]
    assert [com["x"], com["y"]] == pytest.approx(result["com_m"])
    assert ros["inertia_stamped"]["header"]["frame_id"] == "table_cam"
    assert ros["status"] == result["status"]
    cov = np.reshape(ros["pose_with_covariance_stamped"]["pose"]["covariance"], (6, 6))
    np.testing.assert_allclose(cov[:2, :2], 0.0025**2 * np.array(result["covariance_px2"]))
    assert main(args) == 0  # the default frame: the mask's
    assert json.loads(capsys.readouterr().out)["ros"]["inertia_stamped"]["header"]["frame_id"] == (
        "comcore_mask"
    )


def test_an_empty_frame_id_is_refused(files, capsys):
    _, mask, pushes = files
    args = ["estimate", *RES, "--mask", str(mask), "--pushes", str(pushes), "--frame-id", " ",
            "--no-overlay"]  # fmt: skip
    assert main(args) == 2
    assert "--frame-id" in capsys.readouterr().err


def zoomed_recording(folder: Path, zoom: float) -> tuple[Path, Path]:
    """The shipped example's first 12 pushes, each starting 4 px before the object, and the
    example's mask taken at ``zoom`` times the pushes' scale (about the object's centroid)."""
    from matplotlib.image import imread
    from scipy import ndimage

    from comcore.cli._inputs import read_pushes
    from comcore.cli.estimate import example_files

    files = example_files()
    image = np.pad(imread(files["mask"]), 30) > 0.5
    recorded = read_pushes(files["pushes"])
    actions, motions = recorded.actions[:12] + 30, recorded.motions[:12]
    mask = comcore.Mask(image)
    found = comcore.geometry.contacts(mask, actions)
    direction = actions[:, 2:] - actions[:, :2]
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    rows = np.hstack([found.point - 4 * direction, actions[:, 2:], motions])
    pushes = folder / "pushes.csv"
    pushes.write_text(HEADER + "".join(",".join(f"{v:.3f}" for v in r) + "\n" for r in rows))
    centre = np.array(mask.centroid)[::-1]  # (row, column)
    zoomed = ndimage.affine_transform(
        image.astype(float), np.eye(2) / zoom, offset=centre - centre / zoom, order=1
    )
    path = folder / f"mask-{zoom}.png"
    write_png(path, zoomed > 0.5)
    return path, pushes


def test_a_mask_at_another_scale_than_the_pushes_is_refused_naming_the_scale(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    same, pushes = zoomed_recording(tmp_path, 1.0)
    args = ["estimate", *RES, "--pushes", str(pushes), "--json", "--no-overlay"]
    assert main([*args, "--mask", str(same), "--model", "none"]) == 0
    assert json.loads(capsys.readouterr().out)["dropped_lines"] == {}
    zoomed, _ = zoomed_recording(tmp_path, 1.25)
    assert main([*args, "--mask", str(zoomed), "--model", "none"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert "--mask and --pushes: 3 of 12 pushes miss the object or start inside it" in captured.err
    assert "the pushes fit the mask scaled by 0.8" in captured.err
    assert "the mask's scale disagrees with the pushes'" in captured.err


def test_a_scale_hint_needs_a_scale_that_fits(tmp_path):
    from comcore.cli._mistakes import scale_mistake

    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    rows = np.array([p[:4] for p in PUSHES], float)
    assert scale_mistake(mask, rows, 0) is None  # nothing dropped: nothing asked
    around = np.array([(0, 2, 30, 2), (0, 25, 30, 25), (2, 0, 2, 30), (25, 0, 25, 30)], float)
    assert "scaled by 1.16 about its centroid (4 of 4" in scale_mistake(mask, around, 4)
    centre = np.array([(13.5, 13.5, 30, 13.5), (0, 13, 30, 13)], float)
    assert scale_mistake(mask, centre, 1) is None  # starts at the centroid: no scale mends it
