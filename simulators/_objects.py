"""The 20 benchmark objects: their recipes, their SVG files and loading by name.

The objects echo the paper's Fig. 4 in spirit (convex and concave, compact and
elongated, with and without symmetry) and match its Table I areas. They ship
as SVG files (millimetres, ``y`` down as in any drawing) in
``simulators/data`` and load through trimesh like a user's own file;
:func:`write_benchmark_svgs` regenerates those files from the recipes below.
"""

from __future__ import annotations

import math
from functools import cache
from importlib import resources
from pathlib import Path

import numpy as np

from ._shapes import ObjectShape, check_polygon, load_shape

__all__ = ["BENCHMARK_AREAS_CM2", "BENCHMARK_OBJECTS", "load_object", "write_benchmark_svgs"]

#: Names of the benchmark objects.
BENCHMARK_OBJECTS = tuple(f"Obj{i}" for i in range(1, 21))
#: Their areas in cm^2 (the paper's Table I).
BENCHMARK_AREAS_CM2 = dict(
    zip(
        BENCHMARK_OBJECTS,
        (32.9, 35.6, 27.0, 103.3, 42.5, 58.0, 53.4, 110.4, 119.4, 91.0,
         83.0, 58.3, 38.2, 43.0, 35.2, 67.8, 51.6, 120.4, 126.3, 150.5),
    )
)


def _arc(centre, radii, degrees, n):
    """``n`` points on the ellipse arc about ``centre``, semi-axes ``radii``, over ``degrees``."""
    (cx, cy), (rx, ry), (a0, a1) = centre, radii, degrees
    t = np.linspace(math.radians(a0), math.radians(a1), n)
    return np.column_stack([cx + rx * np.cos(t), cy + ry * np.sin(t)])


def _rounded_rect(w, h, r, n=6):
    pts = []
    for cx, cy, a in ((w - r, h - r, 0), (r, h - r, 90), (r, r, 180), (w - r, r, 270)):
        pts.append(_arc((cx, cy), (r, r), (a, a + 90), n))
    return np.vstack(pts)


def _star(k, r_out, r_in):
    t = np.pi / 2 + np.arange(2 * k) * np.pi / k
    r = np.where(np.arange(2 * k) % 2 == 0, r_out, r_in)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def _blob(radii):
    t = np.linspace(0, 2 * np.pi, len(radii), endpoint=False)
    return np.column_stack([radii * np.cos(t), radii * np.sin(t)])


def _recipes() -> dict[str, np.ndarray]:
    """Outlines before scaling (arbitrary units, ``y`` up, any orientation)."""
    t = np.linspace(0, 2 * np.pi, 36, endpoint=False)
    bean = 1.0 + 0.25 * np.cos(2 * t) - 0.35 * np.cos(t) ** 3 * (np.cos(t) > 0)
    return {
        "Obj1": np.array([[0, 0], [2, 0], [2, 1], [0, 1]]),  # 2:1 rectangle
        "Obj2": np.array([[0, 0], [3, 0], [3, 1], [1, 1], [1, 2.5], [0, 2.5]]),  # L
        "Obj3": _arc((0, 0), (1, 1), (0, 360), 7)[:-1],  # regular hexagon
        "Obj4": np.array([[-2, 2], [2, 2], [2, 1.2], [0.5, 1.2], [0.5, -1.5], [-0.5, -1.5],
                          [-0.5, 1.2], [-2, 1.2]]),  # T
        "Obj5": np.array([[0, 0], [4, 0], [1.2, 2.6]]),  # scalene triangle
        "Obj6": _arc((0, 0), (3.0, 1), (0, 360), 41)[:-1],  # ellipse
        "Obj7": np.array([[-0.5, -1.5], [0.5, -1.5], [0.5, -0.5], [1.5, -0.5], [1.5, 0.5],
                          [0.5, 0.5], [0.5, 1.5], [-0.5, 1.5], [-0.5, 0.5], [-1.5, 0.5],
                          [-1.5, -0.5], [-0.5, -0.5]]),  # plus
        "Obj8": np.array([[0, 0], [5, 0], [5, 1], [0, 1]]),  # 5:1 bar
        "Obj9": np.array([[0, 0], [3, 0], [3, 3], [2.1, 3], [2.1, 0.9], [0.9, 0.9], [0.9, 3],
                          [0, 3]]),  # U
        "Obj10": _star(5, 1.0, 0.5),  # five-pointed star
        "Obj11": np.array([[0, 0], [4.5, 0], [3.7, 1.6], [0.6, 1.6]]),  # trapezoid
        "Obj12": np.vstack([_arc((0, 0), (2, 2), (20, 160), 15),
                            _arc((0, -0.5), (1.55, 1.55), (150, 30), 13)]),  # crescent
        "Obj13": np.array([[0, 0], [2.2, -0.3], [2.8, 1.5], [1.2, 2.6], [-0.4, 1.6]]),  # pentagon
        "Obj14": np.array([[0, -0.35], [3.6, -0.35], [3.6, -0.9], [5.0, 0], [3.6, 0.9], [3.6, 0.35],
                           [0, 0.35]]),  # arrow
        "Obj15": _arc((0, 0), (1, 1), (0, 180), 19),  # half disc
        "Obj16": _blob(1.6 * bean) * (1.3, 1.0),  # bean / kidney
        "Obj17": _rounded_rect(3, 2, 0.5),  # rounded rectangle
        "Obj18": np.array([[0, 3], [3, 3], [3, 2.3], [1.2, 0.7], [3, 0.7], [3, 0], [0, 0],
                           [0, 0.7], [1.8, 2.3], [0, 2.3]]),  # Z
        "Obj19": np.array([[0, 0], [6.3, 0], [6.3, -0.9], [7.5, -0.9], [7.5, 1.6], [6.3, 1.6],
                           [6.3, 0.7], [0, 0.7]]),  # hammer
        "Obj20": _blob(np.array([1.0, 1.15, 1.3, 1.2, 1.0, 0.85, 0.9, 1.1, 1.25, 1.0, 0.8,
                                 0.75, 0.9, 1.05, 1.2, 1.1])),  # irregular convex-ish blob
    }


def benchmark_outline(name: str) -> np.ndarray:
    """The outline of a benchmark object in millimetres, centred, scaled to its area."""
    v = check_polygon(_recipes()[name])
    shape = ObjectShape(v)
    s = math.sqrt(BENCHMARK_AREAS_CM2[name] * 100.0 / shape.area_m2)  # mm^2 per unit^2
    return (v - np.asarray(shape.centroid_m)) * s


def write_benchmark_svgs(directory) -> list[Path]:
    """Write ``Obj1.svg`` ... ``Obj20.svg`` (millimetres, ``y`` down) into ``directory``."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for name in BENCHMARK_OBJECTS:
        v = benchmark_outline(name) * (1.0, -1.0)  # drawings have y down
        lo = v.min(axis=0) - 5.0
        v = v - lo
        w, h = np.ceil(v.max(axis=0) + 5.0)
        d = "M " + " L ".join(f"{x:.4f} {y:.4f}" for x, y in v) + " Z"
        path = directory / f"{name}.svg"
        path.write_text(
            '<?xml version="1.0" encoding="UTF-8"?>\n'
            f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0f}mm" height="{h:.0f}mm" '
            f'viewBox="0 0 {w:.0f} {h:.0f}">\n'
            f"  <title>comcore benchmark object {name}, "
            f"{BENCHMARK_AREAS_CM2[name]} cm^2 (units: mm)</title>\n"
            f'  <path d="{d}" fill="black" stroke="none"/>\n</svg>\n'
        )
        written.append(path)
    return written


@cache
def load_object(name: str) -> ObjectShape:
    """Load a benchmark object by name (``"Obj1"`` ... ``"Obj20"``), centred on the origin.

    Examples
    --------
    >>> shape = load_object("Obj7")
    >>> shape.name, round(shape.area_m2 * 1e4, 1)
    ('Obj7', 53.4)
    """
    if name not in BENCHMARK_AREAS_CM2:
        raise ValueError(f"name must be one of Obj1 ... Obj20, got {name!r}")
    with resources.as_file(resources.files("simulators") / "data" / f"{name}.svg") as path:
        shape = load_shape(path, scale=0.001, name=name)
    return ObjectShape(shape.vertices_m - np.asarray(shape.centroid_m), name=name)
