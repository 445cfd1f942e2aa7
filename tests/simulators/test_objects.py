"""The 20 benchmark objects: areas (paper Table I), variety, files in sync with recipes."""

import numpy as np
import pytest

pytest.importorskip("trimesh")
shapely = pytest.importorskip("shapely")

import simulators  # noqa: E402
from simulators._objects import benchmark_outline, write_benchmark_svgs  # noqa: E402

TABLE_I = (32.9, 35.6, 27.0, 103.3, 42.5, 58.0, 53.4, 110.4, 119.4, 91.0,
           83.0, 58.3, 38.2, 43.0, 35.2, 67.8, 51.6, 120.4, 126.3, 150.5)  # fmt: skip


@pytest.mark.parametrize(("name", "area_cm2"), list(zip(simulators.BENCHMARK_OBJECTS, TABLE_I)))
def test_area_matches_table_one(name, area_cm2):
    shape = simulators.load_object(name)
    assert shape.name == name
    assert shape.area_m2 * 1e4 == pytest.approx(area_cm2, rel=0.02)
    assert np.allclose(shape.centroid_m, 0.0, atol=1e-9)


def _mirror_symmetric(poly) -> bool:
    """Symmetric about some line through the centroid (checked at 1 degree steps)."""
    c = poly.centroid
    for angle in np.radians(np.arange(0, 180, 1.0)):
        ca, sa = np.cos(2 * angle), np.sin(2 * angle)
        mirrored = shapely.affinity.affine_transform(
            poly, [ca, sa, sa, -ca, c.x - ca * c.x - sa * c.y, c.y - sa * c.x + ca * c.y]
        )
        if poly.symmetric_difference(mirrored).area < 1e-3 * poly.area:
            return True
    return False


def test_the_set_is_varied():
    convex, elongated, symmetric = 0, 0, 0
    for name in simulators.BENCHMARK_OBJECTS:
        shape = simulators.load_object(name)
        poly = shape.polygon()
        convex += shape.is_convex
        rect = np.asarray(poly.minimum_rotated_rectangle.exterior.coords)[:3]
        sides = np.hypot(*np.diff(rect, axis=0).T)
        elongated += sides.max() / sides.min() >= 2.5
        symmetric += _mirror_symmetric(poly)
    assert 6 <= convex <= 14, convex
    assert elongated >= 4, elongated
    assert 5 <= symmetric <= 15, symmetric


def test_packaged_svgs_match_the_recipes(tmp_path):
    for path in write_benchmark_svgs(tmp_path):
        packaged = simulators.load_object(path.stem)
        fresh = simulators.load_shape(path)
        assert np.allclose(packaged.vertices_m, fresh.vertices_m - fresh.centroid_m, atol=1e-6)
    # The recipe is the outline the files were written from (mm, centred, y up).
    recipe = shapely.Polygon(benchmark_outline("Obj5") / 1000.0)
    loaded = simulators.load_object("Obj5").polygon()
    assert recipe.symmetric_difference(loaded).area < 1e-6 * loaded.area


def test_unknown_name():
    with pytest.raises(ValueError, match=r"Obj1 \.\.\. Obj20"):
        simulators.load_object("Obj21")
