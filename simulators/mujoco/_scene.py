"""A MuJoCo scene (MJCF) of a :class:`~simulators.PushSimulator`'s object, table and pusher.

The object is an extruded body made of small convex prisms: the cells of the
trial's mass grid (:class:`~simulators.MassDistribution`) clipped to the
footprint, each carrying its support point's mass (a clipped cell that is not
convex is split into triangles, the cell's mass shared by area, so their centre
of mass is still the cell's centroid), and one small collision-free lump per
point mass. MuJoCo computes the body's centre of mass and inertia from these
pieces. A few hundred small spheres (the *feet*) under the footprint carry it on
the table plane and spread the support friction over it; the pressure under
them is whatever MuJoCo's soft contacts make of a rigid body on a plane, not
comcore's. The pusher is a vertical cylinder on two slide joints, driven by
position servos. Nothing of comcore's motion model or exact engine is used.

Collision bits: the table collides with the feet only, the pusher with the
pieces on the outline only.
"""

from __future__ import annotations

import importlib
import math
import os
import struct
import zlib
from dataclasses import dataclass

import numpy as np

from comcore.checks import check_positive

from .._deps import require_shapely
from .._mass import clipped_grid

__all__ = [
    "MujocoSettings",
    "build_scene_xml",
    "png_bytes",
    "require_mujoco",
    "scene_assets",
    "table_texture",
]

#: Where the pusher waits between pushes (world metres): far outside any camera's view.
PARK_XY = (5.0, 5.0)
#: Side (metres) of the table one copy of a table texture covers.
TABLE_TEXTURE_M = 0.25
#: The drawn arm: its radius and how far it rises above the pusher before reaching out (m).
ARM_RADIUS_M = 0.008
ARM_RISE_M = 0.06
SOLVERS = ("Newton", "CG", "PGS")
CONES = ("elliptic", "pyramidal")
INTEGRATORS = ("implicitfast", "implicit", "Euler", "RK4")


def require_mujoco():
    """Return the ``mujoco`` module (offscreen GL set to EGL unless already chosen).

    ``MUJOCO_GL=egl`` and ``EGL_PLATFORM=surfaceless`` are set only when the
    environment does not set them and mujoco is not imported yet; both must be
    set before the first ``import mujoco``.

    Raises
    ------
    ImportError
        If mujoco is not installed: ``pip install comcore[mujoco]``.
    """
    os.environ.setdefault("MUJOCO_GL", "egl")
    if os.environ["MUJOCO_GL"] == "egl":
        os.environ.setdefault("EGL_PLATFORM", "surfaceless")
    try:
        return importlib.import_module("mujoco")
    except ImportError as e:
        raise ImportError("the MuJoCo robot needs 'mujoco': pip install comcore[mujoco]") from e


@dataclass(frozen=True)
class MujocoSettings:
    """Physics of the MuJoCo scene (defaults chosen in docs/how-to/mujoco.md).

    Attributes
    ----------
    speed : float
        Pusher speed along the path, m/s. Slow enough for the turns to stay near their
        slow-push limit; faster pushes make the object hop on its feet and turn less
        (calibrated by benchmarks/mujoco/mujoco_hop.py; docs/results/simulators.md).
    timestep : float
        MuJoCo time step, seconds.
    contact_timeconst : float
        Time constant (``solref``) of the pusher's contact with the object, seconds; at
        least twice ``timestep``. Stiff, so that the pusher does not sink into the object.
    support_timeconst : float
        Time constant of the feet's contacts with the table. MuJoCo's default softness:
        stiffer support contacts make the pushed object hop on its feet, which weakens
        the support friction (calibrated by benchmarks/mujoco/mujoco_hop.py;
        docs/results/simulators.md).
    solver, cone, integrator : str
        MuJoCo's ``<option>`` settings.
    iterations : int
        Solver iterations per step.
    impratio : float
        MuJoCo's ratio of frictional to normal constraint impedance (> 1: stiffer friction).
    noslip_iterations : int
        Iterations of MuJoCo's no-slip post-solver (0: off).
    n_feet : int
        About how many support spheres carry the object.
    foot_radius : float
        Their radius, metres.
    thickness : float
        Height of the extruded object, metres.
    settle : float
        Seconds simulated after each push, the pusher parked away, before a frame.
    pusher_gain : float
        Stiffness of the pusher's position servos, N/m (critically damped).
    pusher_mass : float
        kg.

    Examples
    --------
    >>> MujocoSettings(timestep=0.0005).contact_timeconst
    0.002
    >>> MujocoSettings(solver="Gauss")
    Traceback (most recent call last):
    ...
    ValueError: solver must be one of ('Newton', 'CG', 'PGS'), got 'Gauss'
    """

    speed: float = 0.01
    timestep: float = 0.001
    contact_timeconst: float = 0.002
    support_timeconst: float = 0.02
    solver: str = "Newton"
    cone: str = "elliptic"
    integrator: str = "implicitfast"
    iterations: int = 50
    impratio: float = 1.0
    noslip_iterations: int = 0
    n_feet: int = 300
    foot_radius: float = 0.001
    thickness: float = 0.01
    settle: float = 0.3
    pusher_gain: float = 20000.0
    pusher_mass: float = 0.5

    def __post_init__(self):
        for name in ("speed", "timestep", "contact_timeconst", "support_timeconst"):
            check_positive(getattr(self, name), name)
        for name in ("foot_radius", "thickness"):
            check_positive(getattr(self, name), name)
        check_positive(self.pusher_gain, "pusher_gain")
        check_positive(self.pusher_mass, "pusher_mass")
        check_positive(self.settle, "settle", allow_zero=True)
        check_positive(self.impratio, "impratio")
        n = self.noslip_iterations
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise ValueError(f"noslip_iterations must be an integer >= 0, got {n!r}")
        for name in ("contact_timeconst", "support_timeconst"):
            if getattr(self, name) < 2 * self.timestep:
                raise ValueError(
                    f"{name} must be at least 2 * timestep ({2 * self.timestep:g} s), "
                    f"got {getattr(self, name):g} (MuJoCo would soften it silently)"
                )
        for name, allowed in (
            ("solver", SOLVERS),
            ("cone", CONES),
            ("integrator", INTEGRATORS),
        ):
            if getattr(self, name) not in allowed:
                raise ValueError(f"{name} must be one of {allowed}, got {getattr(self, name)!r}")
        for name in ("iterations", "n_feet"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 4:
                raise ValueError(f"{name} must be an integer >= 4, got {value!r}")


def _convex_parts(piece, shapely) -> list[np.ndarray]:
    """Convex polygons (ccw vertex arrays) whose union is ``piece``."""
    parts = []
    for geom in getattr(piece, "geoms", [piece]):
        if geom.geom_type != "Polygon" or geom.area <= 0:
            continue
        if abs(geom.convex_hull.area - geom.area) <= 1e-9 * geom.area:
            parts.append(shapely.orient_polygons(geom))
        else:
            tris = shapely.constrained_delaunay_triangles(geom)
            parts.extend(shapely.orient_polygons(t) for t in tris.geoms)
    return [np.asarray(p.exterior.coords)[:-1] for p in parts if p.area > 1e-10]


def object_pieces(simulator):
    """Convex pieces (vertex arrays, metres), their masses, and lumps ``(x, y, kg)``.

    Each support point of the mass distribution that is the centroid of a clipped
    grid cell gives its mass to that cell's pieces (by area); any other support
    point (a point mass) becomes a lump.
    """
    shapely = require_shapely()
    mass = simulator.mass
    poly = simulator.shape.polygon()
    cells = clipped_grid(poly, mass.cell_size_m, shapely)
    centroids = shapely.get_coordinates(shapely.centroid(cells))
    pieces, masses, lumps = [], [], []
    for p, m in zip(mass.points_m, mass.masses):
        d = np.hypot(*(centroids - p).T)
        k = int(np.argmin(d))
        if d[k] > 1e-9:
            lumps.append((float(p[0]), float(p[1]), float(m)))
            continue
        parts = _convex_parts(cells[k], shapely)
        areas = np.array([shapely.Polygon(v).area for v in parts])
        pieces.extend(parts)
        masses.extend(m * areas / areas.sum())
    return pieces, np.array(masses), lumps


def _feet(poly, n: int, shapely) -> np.ndarray:
    cells = clipped_grid(poly, math.sqrt(poly.area / n), shapely)
    pts = shapely.get_coordinates(shapely.point_on_surface(cells))
    return pts


def _f(values) -> str:
    return " ".join(f"{float(v):.9g}" for v in np.ravel(values))


def _object_xml(simulator, settings: MujocoSettings) -> tuple[list[str], list[str]]:
    """The object's mesh assets and its geoms: convex pieces, lumps and feet."""
    shapely = require_shapely()
    s = settings
    poly = simulator.shape.polygon()
    pieces, masses, lumps = object_pieces(simulator)
    outline = poly.exterior
    z0, z1 = 2 * s.foot_radius, 2 * s.foot_radius + s.thickness
    assets, geoms = [], []
    for i, (v, m) in enumerate(zip(pieces, masses)):
        verts = np.vstack([np.column_stack([v, np.full(len(v), z)]) for z in (z0, z1)])
        assets.append(f'<mesh name="piece{i}" vertex="{_f(verts)}"/>')
        on_outline = shapely.distance(shapely.Polygon(v).exterior, outline) < 1e-9
        bits = 'contype="0" conaffinity="2"' if on_outline else 'contype="0" conaffinity="0"'
        geoms.append(
            f'<geom name="piece{i}" type="mesh" mesh="piece{i}" mass="{m:.9g}" {bits} '
            f'friction="{simulator.mu_contact:.9g} 0 0" material="object"/>'
        )
    for i, (x, y, m) in enumerate(lumps):
        geoms.append(
            f'<geom name="lump{i}" type="sphere" size="{0.25 * s.thickness:.9g}" '
            f'pos="{x:.9g} {y:.9g} {0.5 * (z0 + z1):.9g}" mass="{m:.9g}" contype="0" '
            'conaffinity="0" group="3" rgba="0 0 0 0"/>'
        )
    for i, (x, y) in enumerate(_feet(poly, s.n_feet, shapely)):
        geoms.append(
            f'<geom name="foot{i}" type="sphere" size="{s.foot_radius:.9g}" '
            f'pos="{x:.9g} {y:.9g} {s.foot_radius:.9g}" density="0" contype="0" '
            f'conaffinity="1" friction="{simulator.mu_floor:.9g} 0 0" group="3" rgba="0 0 0 0" '
            f'solref="{s.support_timeconst:.9g} 1"/>'
        )
    return assets, geoms


def _table_material(camera) -> str:
    """The table's ``<material>`` (and its texture) for ``camera.table``."""
    table = getattr(camera, "table", "plain")
    if table == "plain":
        return '<material name="table" rgba="0.45 0.47 0.5 1"/>'
    repeat = 1.0 / TABLE_TEXTURE_M
    return (
        f'<texture name="table" type="2d" file="{table}.png"/>\n    '
        f'<material name="table" texture="table" texrepeat="{repeat:.9g} {repeat:.9g}" '
        'texuniform="true" rgba="1 1 1 1" specular="0.1"/>'
    )


def _arm_xml(camera, pusher_top: float) -> str:
    """The arm's geoms on the pusher body (massless, no collisions), or nothing."""
    if not getattr(camera, "arm", False):
        return ""
    rise = pusher_top + ARM_RISE_M
    reach = (camera.bounds_m[3] - camera.bounds_m[1]) + 0.2 if camera.bounds_m else 0.4
    look = 'density="0" contype="0" conaffinity="0" rgba="0.3 0.32 0.36 1"'
    return (
        f'\n      <geom name="arm_wrist" type="capsule" size="{ARM_RADIUS_M:.9g}" '
        f'fromto="0 0 {pusher_top:.9g} 0 0 {rise:.9g}" {look}/>\n      '
        f'<geom name="arm_link" type="capsule" size="{ARM_RADIUS_M:.9g}" '
        f'fromto="0 0 {rise:.9g} 0 {reach:.9g} {rise + 0.5 * ARM_RISE_M:.9g}" {look}/>'
    )


def scene_assets(camera) -> dict[str, bytes]:
    """The files the scene's XML names (the table's texture PNG), for ``MjModel``'s ``assets``."""
    table = getattr(camera, "table", "plain")
    if table == "plain":
        return {}
    return {f"{table}.png": png_bytes(table_texture(table))}


def build_scene_xml(simulator, settings: MujocoSettings, camera) -> str:
    """The MJCF of the scene.

    Parameters
    ----------
    simulator : PushSimulator
        The object (shape, mass, ``mu_contact``, ``mu_floor``, ``pusher_radius``).
    settings : MujocoSettings
    camera : simulators.mujoco._camera.CameraSetup
        Where the camera and the light are, the table's look and whether the arm is
        drawn (a textured table needs :func:`scene_assets` beside the XML).

    Returns
    -------
    str
    """
    s = settings
    assets, geoms = _object_xml(simulator, s)
    z0, z1 = 2 * s.foot_radius, 2 * s.foot_radius + s.thickness
    r = simulator.pusher_radius
    kv = 2.0 * math.sqrt(s.pusher_gain * s.pusher_mass)
    w, h = camera.image_size
    return f"""<mujoco model="comcore push">
  <compiler angle="radian"/>
  <option timestep="{s.timestep:.9g}" solver="{s.solver}" cone="{s.cone}"
          integrator="{s.integrator}" iterations="{int(s.iterations)}" impratio="{s.impratio:.9g}"
          noslip_iterations="{int(s.noslip_iterations)}" gravity="0 0 -9.81"/>
  <visual>
    <global offwidth="{w}" offheight="{h}"/>
    <quality shadowsize="{int(camera.shadow_size)}"/>
    <headlight ambient="0.25 0.25 0.25" diffuse="0.2 0.2 0.2" specular="0 0 0"/>
  </visual>
  <default><geom solref="{s.contact_timeconst:.9g} 1" condim="3"/></default>
  <asset>
    {_table_material(camera)}
    <material name="object" rgba="0.95 0.75 0.3 1"/>
    {chr(10).join(assets)}
  </asset>
  <worldbody>
    <light name="key" pos="{_f(camera.light_pos)}" dir="{_f(camera.light_dir)}"
           directional="false" castshadow="true" cutoff="{camera.light_cutoff_deg:.6g}"
           exponent="2" diffuse="0.8 0.8 0.8" specular="0.1 0.1 0.1"/>
    <geom name="table" type="plane" size="0 0 0.01" contype="1" conaffinity="0"
          friction="{simulator.mu_floor:.9g} 0 0" material="table"
          solref="{s.support_timeconst:.9g} 1"/>
    <camera name="top" pos="{_f(camera.position)}" xyaxes="{_f(camera.xyaxes)}"
            fovy="{math.degrees(camera.fov):.9g}"/>
    <body name="object">
      <freejoint name="object"/>
      {chr(10).join(geoms)}
    </body>
    <body name="pusher" pos="{PARK_XY[0]} {PARK_XY[1]} {0.5 * (z0 + z1):.9g}">
      <joint name="pusher_x" type="slide" axis="1 0 0"/>
      <joint name="pusher_y" type="slide" axis="0 1 0"/>
      <geom name="pusher" type="cylinder" size="{r:.9g} {s.thickness:.9g}" mass="{s.pusher_mass}"
            contype="2" conaffinity="0" friction="{simulator.mu_contact:.9g} 0 0"
            rgba="0.2 0.2 0.2 1"/>{_arm_xml(camera, s.thickness)}
    </body>
  </worldbody>
  <actuator>
    <position name="pusher_x" joint="pusher_x" kp="{s.pusher_gain:.9g}" kv="{kv:.9g}"/>
    <position name="pusher_y" joint="pusher_y" kp="{s.pusher_gain:.9g}" kv="{kv:.9g}"/>
  </actuator>
</mujoco>
"""


def table_texture(kind: str, size: int = 512, seed: int = 0) -> np.ndarray:
    """A procedural table texture, uint8 RGB ``(size, size, 3)``, spanning TABLE_TEXTURE_M.

    ``"wood"``: light wood with wavy growth rings and a fine grain along the image's
    rows, from a seeded generator (the same texture every time); ``"stripes"``:
    light and dark bands, eight across.

    Examples
    --------
    >>> tex = table_texture("stripes", size=64)
    >>> tex.shape, tex.dtype.name, int(tex.min()) < int(tex.max())
    ((64, 64, 3), 'uint8', True)
    """
    from scipy import ndimage

    yy, xx = np.mgrid[0:size, 0:size] / size
    if kind == "stripes":
        level = 0.5 + 0.5 * np.tanh(4.0 * np.sin(2 * np.pi * 8 * xx))
        rgb = np.array([0.55, 0.56, 0.58]) + np.array([0.3, 0.3, 0.3]) * level[..., None]
    elif kind == "wood":
        rng = np.random.default_rng(seed)
        warp = ndimage.gaussian_filter(rng.normal(size=(size, size)), size / 16, mode="wrap")
        warp /= warp.std()
        rings = 0.5 + 0.5 * np.sin(2 * np.pi * (6 * yy + 0.35 * warp))
        grain = ndimage.gaussian_filter(
            rng.normal(size=(size, size)), (0.6, size / 24), mode="wrap"
        )
        grain /= grain.std()
        level = 0.75 * rings + 0.1 * grain
        rgb = np.array([0.80, 0.66, 0.50]) - np.array([0.22, 0.2, 0.17]) * level[..., None]
    else:
        raise ValueError(f"kind must be 'wood' or 'stripes', got {kind!r}")
    return np.clip(np.rint(255 * rgb), 0, 255).astype(np.uint8)


def png_bytes(rgb: np.ndarray) -> bytes:
    """An 8-bit RGB image ``(H, W, 3)`` as the bytes of a PNG file."""
    rgb = np.ascontiguousarray(rgb, dtype=np.uint8)
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[row].tobytes() for row in range(h))

    def chunk(tag: bytes, data: bytes) -> bytes:
        crc = zlib.crc32(tag + data) & 0xFFFFFFFF
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", crc)

    header = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw))
        + chunk(b"IEND", b"")
    )
