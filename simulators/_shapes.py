"""Object footprints: :class:`ObjectShape`, polygon validation and file loading."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._deps import require_shapely, require_trimesh

__all__ = ["ObjectShape", "check_polygon", "load_shape"]

#: Areas below this (m^2) are treated as zero (a 0.1 mm x 0.1 mm square).
MIN_AREA_M2 = 1e-8
#: File units are millimetres unless told otherwise: metres per file unit.
DEFAULT_FILE_SCALE = 0.001
_PATH_SUFFIXES = {".svg", ".dxf"}
_MESH_SUFFIXES = {".stl", ".obj", ".ply", ".off", ".glb", ".gltf"}


def _signed_area(v: np.ndarray) -> float:
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _finite_pair(value, name: str, unit: str) -> np.ndarray:
    """``value`` as a float array of shape (2,), or an error naming ``name``."""
    want = f"{name} must be two finite numbers ({unit})"
    if isinstance(value, (str, bytes)) or value is None:
        raise TypeError(f"{want}, got {type(value).__name__}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{want}, got {value!r}") from e
    if arr.shape != (2,) or not np.isfinite(arr).all():
        raise ValueError(f"{want}, got {arr.tolist()}")
    return arr


def check_polygon(vertices, name: str = "vertices") -> np.ndarray:
    """Validate a simple polygon into a read-only (k, 2) array, counter-clockwise.

    A repeated closing vertex and consecutive duplicates are dropped.

    Parameters
    ----------
    vertices : array_like, shape (k, 2)
        Outline in metres, world frame (``y`` up), either orientation.
    name : str, optional
        Argument name used in error messages.

    Returns
    -------
    numpy.ndarray, shape (k, 2)
        The outline, counter-clockwise (positive signed area), read-only.

    Raises
    ------
    ValueError
        Fewer than 3 distinct vertices, zero area, or a self-intersecting outline.

    Examples
    --------
    >>> check_polygon([(0, 0), (0, 0.1), (0.1, 0), (0, 0)]).tolist()
    [[0.0, 0.0], [0.1, 0.0], [0.0, 0.1]]
    >>> check_polygon([(0, 0), (0.1, 0.1), (0.1, 0), (0, 0.1)])
    Traceback (most recent call last):
    ...
    ValueError: vertices must be a simple polygon, but its outline intersects itself
    """
    if isinstance(vertices, (str, bytes)) or vertices is None:
        raise TypeError(f"{name} must be array_like of shape (k, 2), got {type(vertices).__name__}")
    try:
        v = np.array(vertices, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be array_like of real numbers, shape (k, 2); {e}") from e
    if v.ndim != 2 or v.shape[1] != 2:
        raise ValueError(f"{name} must have shape (k, 2), got {v.shape}")
    if not np.isfinite(v).all():
        raise ValueError(f"{name} must be finite")
    keep = np.ones(len(v), bool)
    if len(v):
        keep[1:] = np.any(np.abs(np.diff(v, axis=0)) > 1e-12, axis=1)
    v = v[keep]
    if len(v) > 1 and np.all(np.abs(v[0] - v[-1]) <= 1e-12):
        v = v[:-1]
    if len(v) < 3:
        raise ValueError(f"{name} must have at least 3 distinct vertices, got {len(v)}")
    area = _signed_area(v)
    shapely = require_shapely()
    flat = np.linalg.matrix_rank(v - v.mean(axis=0), tol=1e-12) < 2
    if not flat and not shapely.LinearRing(v).is_simple:
        raise ValueError(f"{name} must be a simple polygon, but its outline intersects itself")
    if abs(area) < MIN_AREA_M2:
        raise ValueError(f"{name} must enclose a non-zero area, got {abs(area):.3g} m^2")
    if area < 0:
        v = v[::-1].copy()
    v.setflags(write=False)
    return v


@dataclass(frozen=True, eq=False)
class ObjectShape:
    """The footprint of a flat object on the table, in world metres (``y`` up).

    Attributes
    ----------
    vertices_m : numpy.ndarray, shape (k, 2)
        Counter-clockwise outline in metres (read-only).
    name : str
        A label (the file stem for loaded shapes).
    uniform_com_m : tuple of float or None
        Centre of mass of the real object at uniform density, projected on the
        table, when it differs from the footprint's area centroid (a mesh that
        is not a prism); ``None`` means the area centroid.

    Examples
    --------
    >>> s = ObjectShape.from_vertices([(0, 0), (0.04, 0), (0.04, 0.02), (0, 0.02)], name="box")
    >>> round(s.area_m2 * 1e4, 6), s.centroid_m
    (8.0, (0.02, 0.01))
    """

    vertices_m: np.ndarray
    name: str = ""
    uniform_com_m: tuple[float, float] | None = None

    def __post_init__(self):
        object.__setattr__(self, "vertices_m", check_polygon(self.vertices_m, "vertices_m"))
        if self.uniform_com_m is not None:
            com = _finite_pair(self.uniform_com_m, "uniform_com_m", "x, y metres")
            object.__setattr__(self, "uniform_com_m", (float(com[0]), float(com[1])))

    @classmethod
    def from_vertices(cls, vertices, name: str = "") -> ObjectShape:
        """Build a shape from a vertex array (metres, world frame, ``y`` up)."""
        return cls(vertices, name=name)

    @property
    def area_m2(self) -> float:
        """Area in square metres."""
        return abs(_signed_area(self.vertices_m))

    @property
    def centroid_m(self) -> tuple[float, float]:
        """Area centroid ``(x, y)`` in metres."""
        v = self.vertices_m
        x, y = v[:, 0], v[:, 1]
        x1, y1 = np.roll(x, -1), np.roll(y, -1)
        cross = x * y1 - x1 * y
        a6 = 3.0 * cross.sum()
        return (float(((x + x1) * cross).sum() / a6), float(((y + y1) * cross).sum() / a6))

    @property
    def bounds_m(self) -> tuple[float, float, float, float]:
        """``(min_x, min_y, max_x, max_y)`` in metres."""
        lo, hi = self.vertices_m.min(axis=0), self.vertices_m.max(axis=0)
        return (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))

    @property
    def is_convex(self) -> bool:
        """Whether the outline is convex."""
        d = np.diff(np.vstack([self.vertices_m, self.vertices_m[:2]]), axis=0)
        cross = d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0]
        return bool((cross >= -1e-15).all())

    def polygon(self):
        """The outline as a ``shapely.Polygon``."""
        return require_shapely().Polygon(self.vertices_m)

    def __repr__(self) -> str:
        return (
            f"ObjectShape(name={self.name!r}, n_vertices={len(self.vertices_m)}, "
            f"area_cm2={self.area_m2 * 1e4:.1f})"
        )


def _single_polygon(polygons, path: Path):
    """The one outline among closed curves (shapely polygons), or a clear error."""
    polys = [p for p in polygons if p is not None and p.area > 0]
    if not polys:
        raise ValueError(f"{path.name} holds no closed outline with a non-zero area")
    polys.sort(key=lambda p: -p.area)
    if len(polys) > 1:
        if any(polys[0].contains(p) for p in polys[1:]):
            raise ValueError(f"{path.name}: outlines with holes are not supported")
        raise ValueError(
            f"{path.name} holds {len(polys)} disjoint pieces; an object must be one piece"
        )
    return np.asarray(polys[0].exterior.coords, dtype=float)


def load_shape(path, scale: float = DEFAULT_FILE_SCALE, name: str | None = None) -> ObjectShape:
    """Load an object's footprint from a 2-D outline or a 3-D mesh file (trimesh).

    * SVG / DXF: the single closed outline in the file. SVG's ``y`` axis points
      down, so it is flipped: the footprint looks on screen (and in the mask)
      as the drawing does.
    * STL / OBJ / PLY / OFF / glTF: a watertight mesh resting on ``z = min``
      with ``z`` up; the footprint is its section just above the table, and
      its uniform-density centre of mass (trimesh mass properties) is kept,
      projected on the table, in :attr:`ObjectShape.uniform_com_m`.

    Parameters
    ----------
    path : str or pathlib.Path
    scale : float, optional
        Metres per file unit (default 0.001: files in millimetres).
    name : str, optional
        Label of the shape (default: the file stem).

    Returns
    -------
    ObjectShape

    Raises
    ------
    ValueError
        Unknown suffix, a file its format's reader cannot parse (not XML, no
        drawing), several pieces, holes, no closed outline, a mesh that is not
        watertight, or an invalid outline (see :func:`check_polygon`); the
        message names the file.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"path must be an existing file, got {str(path)!r}")
    if isinstance(scale, bool) or not isinstance(scale, (int, float)) or not scale > 0:
        raise ValueError(f"scale must be a positive number (metres per file unit), got {scale!r}")
    suffix = path.suffix.lower()
    trimesh = require_trimesh()
    uniform_com = None
    if suffix in _PATH_SUFFIXES:
        kind = "an SVG drawing" if suffix == ".svg" else "a DXF drawing"
        try:
            loaded = trimesh.load_path(str(path))
            polygons = loaded.polygons_closed
        except Exception as e:  # lxml's XMLSyntaxError, IndexError, ValueError from numpy ...
            raise ValueError(
                f"{path.name} could not be read as {kind} holding one closed outline "
                f"(trimesh: {type(e).__name__}: {e})"
            ) from e
        vertices = _single_polygon(polygons, path)
        if suffix == ".svg":
            vertices = vertices * (1.0, -1.0)
    elif suffix in _MESH_SUFFIXES:
        try:
            mesh = trimesh.load(str(path), force="mesh")
            watertight = bool(mesh.is_watertight)
        except Exception as e:  # parsers raise whatever they raise on a bad file
            raise ValueError(
                f"{path.name} could not be read as a {suffix[1:].upper()} mesh "
                f"(trimesh: {type(e).__name__}: {e})"
            ) from e
        if not watertight:
            raise ValueError(
                f"{path.name} is not a watertight mesh: its footprint and centre of mass "
                "are undefined (repair it, e.g. with trimesh.repair.fill_holes)"
            )
        z_min, z_max = mesh.bounds[:, 2]
        section = mesh.section(
            plane_origin=(0.0, 0.0, z_min + 1e-3 * (z_max - z_min)), plane_normal=(0.0, 0.0, 1.0)
        )
        if section is None:
            raise ValueError(f"{path.name}: the mesh has no section near its base")
        planar, to_3d = section.to_2D(normal=(0.0, 0.0, 1.0))
        vertices = _single_polygon(planar.polygons_closed, path)
        vertices = trimesh.transform_points(np.column_stack([vertices, 0 * vertices[:, 0]]), to_3d)
        vertices = vertices[:, :2]
        uniform_com = tuple(float(c) * scale for c in mesh.center_mass[:2])
    else:
        known = sorted(_PATH_SUFFIXES | _MESH_SUFFIXES)
        raise ValueError(f"path must end in one of {known}, got {path.name!r}")
    return ObjectShape(
        vertices * float(scale), name=path.stem if name is None else name, uniform_com_m=uniform_com
    )
