"""Footprints: polygon validation, ObjectShape and loading from files (trimesh)."""

import numpy as np
import pytest

pytest.importorskip("pymunk")
trimesh = pytest.importorskip("trimesh")
shapely = pytest.importorskip("shapely")

import simulators  # noqa: E402
from simulators import ObjectShape, check_polygon, load_shape  # noqa: E402

SQUARE = [(0, 0), (0.05, 0), (0.05, 0.05), (0, 0.05)]
L_SHAPE = [(0, 0), (0.06, 0), (0.06, 0.02), (0.02, 0.02), (0.02, 0.05), (0, 0.05)]


def test_check_polygon_orients_counter_clockwise_and_drops_duplicates():
    v = check_polygon([*SQUARE[::-1], SQUARE[-1]])
    assert v.shape == (4, 2)
    x, y = v[:, 0], v[:, 1]
    assert np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y) > 0
    assert not v.flags.writeable


@pytest.mark.parametrize(
    ("vertices", "message"),
    [
        ([(0, 0), (1, 1)], "at least 3 distinct vertices"),
        ([(0, 0), (0.1, 0), (0.2, 0)], "non-zero area"),
        ([(0, 0), (0.1, 0.1), (0.1, 0), (0, 0.1)], "intersects itself"),
        ([(0, 0), (0.1, 0), (np.nan, 0.1)], "finite"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], r"shape \(k, 2\)"),
    ],
)
def test_bad_polygons_are_rejected(vertices, message):
    with pytest.raises(ValueError, match=message):
        check_polygon(vertices)


def test_check_polygon_type_error_names_argument():
    with pytest.raises(TypeError, match="vertices_m"):
        ObjectShape("not a polygon")


def test_object_shape_measures():
    s = ObjectShape.from_vertices(L_SHAPE, name="L")
    poly = shapely.Polygon(L_SHAPE)
    assert s.area_m2 == pytest.approx(poly.area)
    assert s.centroid_m == pytest.approx((poly.centroid.x, poly.centroid.y))
    assert not s.is_convex and ObjectShape(SQUARE).is_convex
    assert s.bounds_m == pytest.approx((0, 0, 0.06, 0.05))


def _svg(path, d, extra=""):
    path.write_text(
        '<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" '
        f'viewBox="0 0 100 100"><path d="{d}"/>{extra}</svg>'
    )
    return path


def test_svg_is_flipped_so_it_looks_like_the_drawing(tmp_path):
    # A right triangle with its right angle at the top-left corner of the drawing.
    f = _svg(tmp_path / "tri.svg", "M 10 10 L 50 10 L 10 30 Z")
    s = load_shape(f)
    assert s.name == "tri"
    assert s.area_m2 == pytest.approx(0.5 * 0.04 * 0.02)
    # The drawing's top edge (y = 10 mm, y down) is the highest in the world (y up).
    top = s.vertices_m[:, 1].max()
    assert np.sum(np.isclose(s.vertices_m[:, 1], top)) == 2
    assert top == pytest.approx(-0.010)


def test_svg_with_several_pieces_or_holes_is_rejected(tmp_path):
    two = _svg(tmp_path / "two.svg", "M 0 0 L 10 0 L 10 10 Z M 50 50 L 60 50 L 60 60 Z")
    with pytest.raises(ValueError, match="2 disjoint pieces"):
        load_shape(two)
    ring = _svg(
        tmp_path / "ring.svg", "M 0 0 L 40 0 L 40 40 L 0 40 Z M 10 10 L 10 30 L 30 30 L 30 10 Z"
    )
    with pytest.raises(ValueError, match="holes"):
        load_shape(ring)


def test_dxf_round_trip(tmp_path):
    path = trimesh.load_path(np.array([*L_SHAPE, L_SHAPE[0]]) * 1000.0)
    f = tmp_path / "ell.dxf"
    f.write_text(trimesh.path.exchange.dxf.export_dxf(path))
    s = load_shape(f)
    assert s.area_m2 == pytest.approx(ObjectShape(L_SHAPE).area_m2, rel=1e-6)


def _prism(outline_mm, triangles, z0, z1):
    """A closed prism over a counter-clockwise outline, caps from the given triangles."""
    k = len(outline_mm)
    verts = np.vstack([np.column_stack([outline_mm, np.full(k, z)]) for z in (z0, z1)])
    faces = [tuple(t[::-1]) for t in triangles] + [tuple(np.add(t, k)) for t in triangles]
    for i in range(k):
        j = (i + 1) % k
        faces += [(i, j, j + k), (i, j + k, i + k)]
    return trimesh.Trimesh(verts, np.array(faces), process=True)


def test_mesh_footprint_and_uniform_com(tmp_path):
    # An L-shaped plate 10 mm thick and a block resting on one of its arms: the
    # real object's CoM is not the footprint's centroid.
    ell = np.array(L_SHAPE) * 1000.0
    plate = _prism(ell, [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)], 0.0, 10.0)
    square = np.array([(35, 2), (55, 2), (55, 18), (35, 18)], float)
    block = _prism(square, [(0, 1, 2), (0, 2, 3)], 10.0, 50.0)
    mesh = trimesh.util.concatenate([plate, block])
    assert mesh.is_watertight
    f = tmp_path / "part.stl"
    mesh.export(f)
    s = load_shape(f)
    assert s.area_m2 == pytest.approx(ObjectShape(L_SHAPE).area_m2, rel=1e-6)
    expected = mesh.center_mass[:2] / 1000.0
    assert s.uniform_com_m == pytest.approx(tuple(expected), abs=1e-9)
    assert np.hypot(*(expected - s.centroid_m)) > 0.005
    sim = simulators.PushSimulator.from_shape(s)
    assert sim.com_m == pytest.approx(s.uniform_com_m, abs=1e-9)


def test_open_mesh_is_rejected(tmp_path):
    box = trimesh.creation.box((10, 10, 10))
    box.update_faces(np.arange(len(box.faces)) != 0)  # punch a hole
    f = tmp_path / "open.stl"
    box.export(f)
    with pytest.raises(ValueError, match="not a watertight mesh"):
        load_shape(f)


def test_unknown_suffix_and_missing_file(tmp_path):
    f = tmp_path / "x.txt"
    f.write_text("hello")
    with pytest.raises(ValueError, match="must end in one of"):
        load_shape(f)
    with pytest.raises(ValueError, match="existing file"):
        load_shape(tmp_path / "missing.svg")


@pytest.mark.parametrize(
    ("name", "content", "match"),
    [
        # no drawing at all: trimesh raised IndexError
        ("empty.svg", '<svg xmlns="http://www.w3.org/2000/svg"></svg>', "as an SVG drawing"),
        ("junk.svg", "hello, not xml", "as an SVG drawing"),  # lxml's XMLSyntaxError
        ("junk.dxf", "\x00\x01binary", "as a DXF drawing"),  # numpy's reshape error
        ("junk.ply", "not a mesh", "as a PLY mesh"),
    ],
)
def test_unreadable_files_are_named(tmp_path, name, content, match):
    path = tmp_path / name
    path.write_text(content)
    with pytest.raises(ValueError, match=rf"{name} could not be read {match}"):
        load_shape(path)


def test_import_is_light_and_a_missing_extra_says_what_to_install():
    import subprocess
    import sys

    code = (
        "import sys\n"
        "import simulators, predictors\n"
        "heavy = {'pymunk', 'trimesh', 'shapely', 'cv2', 'matplotlib', 'torch'}\n"
        "assert not heavy & set(sys.modules), heavy & set(sys.modules)\n"
        "sys.modules['shapely'] = None\n"
        "try:\n"
        "    simulators.ObjectShape([(0, 0), (1, 0), (0, 1)])\n"
        "except ImportError as e:\n"
        "    assert 'pip install comcore[sim]' in str(e) and e.__cause__ is not None\n"
        "    print('ok')\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "ok"


def _wedge_on_plate():
    """A 40 x 30 mm plate 5 mm thick with a 16 x 20 x 20 mm block on its right part (mm)."""
    plate = trimesh.creation.box((40.0, 30.0, 5.0))
    plate.apply_translation((20.0, 15.0, 2.5))
    block = trimesh.creation.box((16.0, 20.0, 20.0))
    block.apply_translation((28.0, 15.0, 15.0))
    return trimesh.util.concatenate([plate, block])


@pytest.mark.parametrize("suffix", [".obj", ".ply"])
def test_obj_and_ply_meshes_give_the_footprint_and_the_com(tmp_path, suffix):
    mesh = _wedge_on_plate()
    assert mesh.is_watertight
    f = tmp_path / f"part{suffix}"
    mesh.export(f)
    s = load_shape(f)
    assert s.name == "part"
    assert s.area_m2 == pytest.approx(0.040 * 0.030, rel=1e-6)
    assert s.bounds_m == pytest.approx((0.0, 0.0, 0.040, 0.030), abs=1e-9)
    # 40 x 30 x 5 plate (CoM x = 20 mm) + 16 x 20 x 20 block (CoM x = 28 mm)
    expected_x = (6000.0 * 20.0 + 6400.0 * 28.0) / 12400.0 / 1000.0
    assert s.uniform_com_m == pytest.approx((expected_x, 0.015), abs=1e-9)
    assert s.centroid_m == pytest.approx((0.020, 0.015), abs=1e-9)


@pytest.mark.parametrize("suffix", [".stl", ".obj", ".ply"])
def test_mesh_whose_footprint_is_several_pieces_is_rejected(tmp_path, suffix):
    # Two separate blocks on the table (a pair of feet): the footprint is two pieces.
    left = trimesh.creation.box((10.0, 10.0, 10.0))
    right = trimesh.creation.box((10.0, 10.0, 10.0))
    right.apply_translation((30.0, 0.0, 0.0))
    mesh = trimesh.util.concatenate([left, right])
    assert mesh.is_watertight
    f = tmp_path / f"feet{suffix}"
    mesh.export(f)
    with pytest.raises(ValueError, match="feet.* holds 2 disjoint pieces; an object must be one"):
        load_shape(f)


def test_mesh_standing_on_two_feet_joined_above_is_rejected(tmp_path):
    # One connected body (an arch), but it touches the table in two places.
    arch = _prism(
        np.array([(0, 0), (10, 0), (10, 10), (30, 10), (30, 0), (40, 0), (40, 20), (0, 20)], float),
        [(0, 1, 2), (0, 2, 7), (2, 3, 6), (2, 6, 7), (3, 4, 5), (3, 5, 6)],
        0.0,
        10.0,
    )
    # the prism's outline lies in the x-y plane: stand it up so the feet rest on z = 0
    arch.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (1, 0, 0)))
    assert arch.is_watertight and arch.body_count == 1
    f = tmp_path / "arch.stl"
    arch.export(f)
    with pytest.raises(ValueError, match="2 disjoint pieces"):
        load_shape(f)
