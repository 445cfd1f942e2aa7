"""read_outline: an object's outline from a polygon CSV or a mesh."""

import numpy as np
import pytest

from comcore.recordings import read_outline

RECT = [[-0.03, -0.02], [0.03, -0.02], [0.03, 0.02], [-0.03, 0.02]]


@pytest.mark.parametrize(
    "text",
    [
        "x,y\n-0.03,-0.02\n0.03,-0.02\n0.03,0.02\n-0.03,0.02\n",
        "-0.03, -0.02\n0.03, -0.02\n\n0.03, 0.02\n-0.03, 0.02\n-0.03, -0.02\n",  # closed, no header
    ],
)
def test_a_csv_with_or_without_header(tmp_path, text):
    path = tmp_path / "plate.csv"
    path.write_text(text)
    outline = read_outline(path)
    assert outline.tolist() == RECT and not outline.flags.writeable


def test_csv_errors_say_the_line(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("x,y\n0,0\n0.1,zero\n")
    with pytest.raises(ValueError, match="line 3: '0.1, zero' is not two numbers"):
        read_outline(path)
    path.write_text("0,0,0\n")
    with pytest.raises(ValueError, match="line 1: expected two numbers"):
        read_outline(path)
    path.write_text("0,0\n1,0\n")
    with pytest.raises(ValueError, match="non-zero area"):
        read_outline(path)
    with pytest.raises(ValueError, match="no such file"):
        read_outline(tmp_path / "none.csv")


def test_a_mesh_gives_its_footprint_in_its_own_frame(tmp_path):
    pytest.importorskip("shapely")
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.box(extents=(0.06, 0.04, 0.02))
    box.apply_translation((0.01, -0.005, 0.01))  # stands on z = 0, off the origin
    path = tmp_path / "block.stl"
    box.export(path)
    outline = read_outline(path)
    lo, hi = outline.min(axis=0), outline.max(axis=0)
    assert np.allclose(lo, (-0.02, -0.025), atol=1e-9) and np.allclose(hi, (0.04, 0.015), atol=1e-9)


def test_a_mesh_without_faces_is_refused_by_name(tmp_path):
    pytest.importorskip("shapely")
    pytest.importorskip("trimesh")
    path = tmp_path / "point.obj"
    path.write_text("v 0 0 0\n")
    with pytest.raises(ValueError, match=r"point\.obj: the mesh has no faces"):
        read_outline(path)
