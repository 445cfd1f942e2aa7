"""An object's outline from a file: a polygon CSV, or a mesh's section near its base.

The outline :func:`recording_from_poses` takes is a polygon in the object's own frame
(the frame its recorded poses are of), metres. :func:`read_outline` reads it from a
CSV of vertices or from a mesh (through trimesh, ``comcore[sim]``).
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np

from ..geometry._outline import check_outline

__all__ = ["MESH_SUFFIXES", "read_outline"]

#: File endings read as meshes (through trimesh); anything else is read as a CSV.
MESH_SUFFIXES = (".stl", ".obj", ".ply", ".off", ".glb", ".gltf", ".dae")
#: Where a mesh is cut: this fraction of its height above its lowest point.
SECTION_HEIGHT = 0.01


def read_outline(path) -> np.ndarray:
    r"""The object's outline (metres, its own frame) from a polygon CSV or a mesh file.

    * **CSV**: one vertex per row, ``x, y`` in metres in the object's frame
      (the frame its recorded poses are of), in order around the outline
      (either orientation); a header row (``x,y``) is optional, as is a
      closing vertex equal to the first.
    * **Mesh** (:data:`MESH_SUFFIXES`, read by trimesh: ``pip install
      comcore[sim]``), in metres and the object's frame with ``z`` up: the
      section of the mesh by the horizontal plane 1 % of its height above its
      lowest point (the footprint it stands on), its largest polygon's outer
      boundary.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    ndarray, shape (k, 2)
        The outline, read-only, as :func:`comcore.geometry.check_outline` returns it.

    Raises
    ------
    ValueError
        If the file cannot be read, a row is not two numbers, the polygon is
        degenerate, or a mesh has no section there.
    ImportError
        For a mesh without trimesh and shapely (``pip install comcore[sim]``).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from comcore.recordings import read_outline
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "plate.csv"
    >>> _ = path.write_text("x,y\n-0.03,-0.02\n0.03,-0.02\n0.03,0.02\n-0.03,0.02\n")
    >>> read_outline(path).tolist()
    [[-0.03, -0.02], [0.03, -0.02], [0.03, 0.02], [-0.03, 0.02]]
    """
    path = Path(os.fspath(path))
    if not path.is_file():
        raise ValueError(f"path: no such file: {path}")
    if path.suffix.lower() in MESH_SUFFIXES:
        return check_outline(_mesh_outline(path), f"the outline of {path}")
    return check_outline(_csv_outline(path), f"the outline in {path}")


def _csv_outline(path: Path) -> np.ndarray:
    """The vertices of a CSV of ``x, y`` rows (a header row optional)."""
    rows: list[list[float]] = []
    try:
        with path.open(newline="", encoding="utf-8-sig") as f:
            for number, row in enumerate(csv.reader(f), start=1):
                cells = [c.strip() for c in row if c.strip()]
                if not cells:
                    continue
                try:
                    values = [float(c) for c in cells]
                except ValueError:
                    if number == 1 and not rows:
                        continue  # the header
                    raise ValueError(
                        f"{path} line {number}: {', '.join(cells)!r} is not two numbers (x, y)"
                    ) from None
                if len(values) != 2:
                    raise ValueError(
                        f"{path} line {number}: expected two numbers (x, y), got {len(values)}"
                    )
                rows.append(values)
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise ValueError(f"cannot read {path}: {e}") from e
    return np.array(rows, dtype=float).reshape(-1, 2)


def _mesh_outline(path: Path) -> np.ndarray:
    """The outer boundary of the largest polygon of the mesh's section near its base."""
    try:
        import shapely  # noqa: F401  (trimesh's polygons need it)
        import trimesh
    except ImportError as e:
        raise ImportError(
            "reading an outline from a mesh needs trimesh and shapely: pip install comcore[sim]"
        ) from e
    try:
        mesh = trimesh.load(path, force="mesh")
    except (OSError, ValueError, TypeError, KeyError, IndexError, AttributeError) as e:
        raise ValueError(f"cannot read {path} as a mesh: {e}") from e
    if mesh.bounds is None or len(getattr(mesh, "faces", ())) == 0:
        raise ValueError(f"{path}: the mesh has no faces, so no section near its base")
    low, high = mesh.bounds[:, 2]
    height = low + SECTION_HEIGHT * (high - low)
    section = mesh.section(plane_origin=[0.0, 0.0, height], plane_normal=[0.0, 0.0, 1.0])  # type: ignore[attr-defined]
    if section is None:
        raise ValueError(f"{path}: the mesh has no section at z = {height:g}")
    to_plane = np.eye(4)
    to_plane[2, 3] = -height  # keeps x and y: the object's frame
    flatten = getattr(section, "to_2D", None) or section.to_planar  # to_planar: older trimesh
    planar, _ = flatten(to_2D=to_plane)
    polygons = list(planar.polygons_full)
    if not polygons:
        raise ValueError(f"{path}: the mesh's section at z = {height:g} holds no closed polygon")
    largest = max(polygons, key=lambda p: p.area)
    return np.asarray(largest.exterior.coords, dtype=float)[:-1]
