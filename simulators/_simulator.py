"""The :class:`PushSimulator`: a footprint, its mass, a camera and a push engine.

The engine is the exact quasi-static limit-surface integrator
(:mod:`simulators.engines._quasistatic`) unless ``settings=EngineSettings(engine="pymunk")``
asks for the pymunk rigid-body engine (:mod:`simulators.engines._pymunk`).
"""

from __future__ import annotations

import dataclasses
import math
from functools import cached_property
from typing import NamedTuple

import numpy as np

import comcore
from comcore import Mask, Motion
from comcore.conventions import DEFAULT_PUSHER_RADIUS, rotate_components, rotation_matrix

from ._deps import require_shapely
from ._mass import DEFAULT_SUPPORT_POINTS, MassDistribution
from ._settings import EngineSettings
from ._shapes import ObjectShape, _finite_pair, load_shape
from .engines._quasistatic import QuasiStaticEngine

__all__ = ["DEFAULT_PUSHER_RADIUS", "PushResult", "PushSimulator"]

#: Floor friction coefficient (the quasi-static motion does not depend on it).
DEFAULT_MU_FLOOR = 0.5
#: Empty border around the footprint in the mask, metres.
DEFAULT_MARGIN = 0.02
#: Pushes integrated together by :meth:`PushSimulator.push_motions`.
BATCH_SIZE = 256
#: The integration step is at most this fraction of the pusher's radius: a longer step
#: carries a small disc through the outline (no motion, or motion the wrong way).
STEP_PER_RADIUS = 0.5
#: A push whose path takes more integration steps than this is refused (a 1e12 px path
#: would otherwise run for days): 100 m of path at the default 1 mm step.
MAX_STEPS_PER_PUSH = 100_000
#: Most pixels of the camera image (4096 x 4096): rasterising the footprint takes index
#: arrays of 16 bytes a pixel (256 MiB here); a larger image is a ``margin`` or a
#: ``resolution`` typed in the wrong unit (a margin of 7239 m asked numpy for 488 TiB).
#: A quarter of ``comcore.conventions.MAX_IMAGE_PIXELS`` (the most any comcore image may
#: have): the simulator rasterises its footprint at every pose it is asked about.
MAX_IMAGE_PIXELS = 4096 * 4096


class PushResult(NamedTuple):
    """The outcome of :meth:`PushSimulator.push`."""

    motion: Motion
    """Rotation (CCW on screen) and displacement (pixels) of the mask's area centroid."""
    pose: tuple[float, float, float]
    """Final pose: CoM ``(x, y)`` in world metres and body angle (radians, CCW)."""
    contact_px: tuple[float, float] | None = None
    """Where the pusher's disc first touched the outline (pixels); ``None``: a miss."""
    normal_px: tuple[float, float] | None = None
    """Unit inward normal at that contact (pixel frame); ``None``: a miss."""
    trajectory: np.ndarray | None = None
    """Poses along the push, shape (k, 3), when asked for with ``record=True``: CoM ``(x, y)``
    in world metres and angle, the start pose first, then one row per integration step
    after the first contact (the pymunk engine: and one after the object settled)."""
    travel_px: np.ndarray | None = None
    """How far the pusher's leading point had come along the action from its start at
    each row of ``trajectory``, shape (k,), pixels (as ``contact_px``), with
    ``record=True``. Row 0 is the travel at the first contact (the object has not moved
    before it), a miss's one row 0; it never decreases and ends at the action's length.
    Where the disc was lowered farther back on the line (a notch narrower than the
    pusher, :meth:`PushSimulator.push`) it starts negative: the disc touched the object
    before its leading point reached the action's start."""


class PushSimulator:
    """A flat object on a table, pushed by a round pusher and seen from above.

    World frame: metres, ``y`` up. The camera looks straight down; its mask
    (:attr:`mask`) shows the footprint at the initial pose with a margin, and
    :meth:`to_pixels` / :meth:`to_world` map between the two frames (pixel
    ``y`` points down). An action is the path of the pusher's leading point
    (the point of the disc farthest along the push); the disc's centre runs
    ``pusher_radius`` behind it. Every push starts from the initial pose unless
    ``pose=`` says otherwise, so all actions refer to the same mask.

    Build one with :meth:`from_polygon`, :meth:`from_shape`, :meth:`from_file`
    or :func:`simulators.random_simulator`.

    Examples
    --------
    >>> import numpy as np
    >>> sim = PushSimulator.from_polygon([(0, 0), (0.08, 0), (0.08, 0.06), (0, 0.06)])
    >>> sim.com_px, sim.mask.shape, sim.mask.area_px
    ((23.5, 19.5), (40, 48), 768)
    >>> res = sim.push((0, 19.5, 19.5, 19.5))  # along +x through the CoM, 3 cm after contact
    >>> m = res.motion
    >>> round(m.theta, 12), round(m.tx, 9), round(m.ty, 9)
    (0.0, 12.0, 0.0)
    """

    def __init__(
        self,
        shape: ObjectShape,
        mass: MassDistribution,
        *,
        mu_contact: float = 0.3,
        resolution: float = comcore.conventions.DEFAULT_RESOLUTION,
        margin: float = DEFAULT_MARGIN,
        pusher_radius: float = DEFAULT_PUSHER_RADIUS,
        mu_floor: float = DEFAULT_MU_FLOOR,
        settings: EngineSettings | None = None,
    ):
        if not isinstance(shape, ObjectShape):
            raise TypeError(f"shape must be a simulators.ObjectShape, got {type(shape).__name__}")
        if not isinstance(mass, MassDistribution):
            raise TypeError(f"mass must be a MassDistribution, got {type(mass).__name__}")
        lo, hi = comcore.checks.check_mu(mu_contact, "mu_contact")
        if lo != hi or math.isinf(lo):
            raise ValueError(f"mu_contact must be one finite number >= 0, got {mu_contact!r}")
        self.shape = shape
        self.mass = mass
        self.mu_contact = lo
        self.resolution = comcore.checks.check_positive(resolution, "resolution")
        self.margin = comcore.checks.check_positive(margin, "margin")
        self.pusher_radius = comcore.checks.check_positive(pusher_radius, "pusher_radius")
        self.mu_floor = comcore.checks.check_positive(mu_floor, "mu_floor")
        h, w = _image_shape(shape.bounds_m, self.margin, self.resolution)
        if h * w > MAX_IMAGE_PIXELS:
            x_min, y_min, x_max, y_max = shape.bounds_m
            raise ValueError(
                f"margin {self.margin:g} m and resolution {self.resolution:g} m per pixel make "
                f"a camera image of {h} x {w} pixels around the {x_max - x_min:.3g} x "
                f"{y_max - y_min:.3g} m object, more than MAX_IMAGE_PIXELS ({MAX_IMAGE_PIXELS}): "
                "margin and resolution are in metres (millimetres typed for metres?)"
            )
        self.settings = EngineSettings() if settings is None else settings
        if not isinstance(self.settings, EngineSettings):
            raise TypeError(f"settings must be an EngineSettings, got {type(settings).__name__}")
        x_min, _, _, y_max = shape.bounds_m
        # Pixel (0, 0) covers [x_min - margin, + resolution] x [y_max + margin, - resolution]:
        # outlines on round coordinates fall on pixel borders, not on pixel centres.
        half = 0.5 * self.resolution
        self._origin = np.array([x_min - self.margin + half, y_max + self.margin - half])
        self.com_m = mass.com_m
        self._com = np.asarray(self.com_m)
        self._outline_body = shape.vertices_m - self._com
        self._support_body = mass.points_m - self._com
        self._moment = mass.moment_of_inertia

    # -- construction ---------------------------------------------------------------
    @classmethod
    def from_shape(
        cls,
        shape: ObjectShape,
        com=None,
        mu_contact: float = 0.3,
        resolution: float = comcore.conventions.DEFAULT_RESOLUTION,
        point_masses=(),
        *,
        mass: float = 1.0,
        density_gradient=(0.0, 0.0),
        n_support: int = DEFAULT_SUPPORT_POINTS,
        **options,
    ) -> PushSimulator:
        """Simulator of a shape; ``com`` (metres) tilts the mass to put the CoM there.

        ``point_masses`` are ``(x, y, m)`` rows (metres, kg); ``mass`` is the
        mass of the rest of the body. ``options`` go to the constructor
        (``margin``, ``pusher_radius``, ``mu_floor``, ``settings``).
        """
        if not isinstance(shape, ObjectShape):
            raise TypeError(f"shape must be a simulators.ObjectShape, got {type(shape).__name__}")
        dist = MassDistribution.on_shape(
            shape,
            mass=mass,
            point_masses=point_masses,
            density_gradient=density_gradient,
            com=com,
            n_support=n_support,
        )
        return cls(shape, dist, mu_contact=mu_contact, resolution=resolution, **options)

    @classmethod
    def from_polygon(
        cls, vertices_m, com=None, mu_contact: float = 0.3, resolution=0.0025, point_masses=(), **kw
    ) -> PushSimulator:
        """Simulator of a polygon (vertices in metres, ``y`` up); see :meth:`from_shape`."""
        shape = ObjectShape.from_vertices(vertices_m)
        return cls.from_shape(shape, com, mu_contact, resolution, point_masses, **kw)

    @classmethod
    def from_file(cls, path, com=None, mu_contact: float = 0.3, *, scale=0.001, **kw):
        """Simulator of the object in a file (:func:`simulators.load_shape`)."""
        return cls.from_shape(load_shape(path, scale=scale), com, mu_contact, **kw)

    # -- camera ---------------------------------------------------------------------
    def to_pixels(self, points_m) -> np.ndarray:
        """World metres (``y`` up) to pixels (``x`` = column, ``y`` = row, down).

        Parameters
        ----------
        points_m : array_like, shape (n, 2) or (2,)
            Points in world metres.

        Returns
        -------
        numpy.ndarray, shape (n, 2)
            The points in pixels of :attr:`mask`.

        Raises
        ------
        ValueError
            If the points are not of shape (n, 2) or (2,), or not finite.
        """
        p = comcore.checks.check_points(points_m, "points_m")
        return np.column_stack([p[:, 0] - self._origin[0], self._origin[1] - p[:, 1]]) / (
            self.resolution
        )

    def _pixels_unchecked(self, points_m: np.ndarray) -> np.ndarray:
        """:meth:`to_pixels` of a (n, 2) array without its checks (NaN stays NaN)."""
        p = np.asarray(points_m, dtype=float)
        return np.column_stack([p[:, 0] - self._origin[0], self._origin[1] - p[:, 1]]) / (
            self.resolution
        )

    def to_world(self, points_px) -> np.ndarray:
        """Pixels to world metres; the inverse of :meth:`to_pixels`.

        Parameters
        ----------
        points_px : array_like, shape (n, 2) or (2,)
            Points ``(x, y)`` in pixels of :attr:`mask`.

        Returns
        -------
        numpy.ndarray, shape (n, 2)
            The points in world metres (``y`` up).

        Raises
        ------
        ValueError
            If the points are not of shape (n, 2) or (2,), or not finite.
        """
        p = comcore.checks.check_points(points_px, "points_px") * self.resolution
        return np.column_stack([p[:, 0] + self._origin[0], self._origin[1] - p[:, 1]])

    @property
    def com_px(self) -> tuple[float, float]:
        """True CoM ``(x, y)`` in pixels."""
        c = self.to_pixels(self._com)[0]
        return (float(c[0]), float(c[1]))

    @property
    def initial_pose(self) -> tuple[float, float, float]:
        """The CoM ``(x, y)`` in metres and angle 0."""
        return (self.com_m[0], self.com_m[1], 0.0)

    @cached_property
    def image_shape(self) -> tuple[int, int]:
        """``(H, W)`` of the camera image."""
        return _image_shape(self.shape.bounds_m, self.margin, self.resolution)

    def outline_at(self, pose=None) -> np.ndarray:
        """The outline in world metres at ``pose`` (default: the initial pose), (k, 2).

        Raises
        ------
        ValueError, TypeError
            If ``pose`` is not three finite numbers ``(x, y, angle)``.
        """
        x, y, a = self.initial_pose if pose is None else check_pose(pose)
        return self._outline_body @ rotation_matrix(a) + (x, y)  # body to world (y up)

    def contains(self, points_px, pose=None) -> np.ndarray:
        """Whether pixel points lie inside the object's outline at ``pose``.

        The exact outline, not the mask's pixels: a push that starts inside it
        is refused (:meth:`push`).

        Parameters
        ----------
        points_px : array_like, shape (n, 2) or (2,)
            Points ``(x, y)`` in pixels of :attr:`mask`.
        pose : (x, y, angle), optional
            The object's pose (default: the initial pose).

        Returns
        -------
        numpy.ndarray of bool, shape (n,)

        Examples
        --------
        >>> sim = PushSimulator.from_polygon([(0, 0), (0.04, 0), (0.04, 0.02), (0, 0.02)])
        >>> sim.contains([sim.com_px, (0.0, 0.0)]).tolist()
        [True, False]
        """
        shapely = require_shapely()
        w = self.to_world(points_px)
        return shapely.contains_xy(shapely.Polygon(self.outline_at(pose)), w[:, 0], w[:, 1])

    def mask_at(self, pose=None) -> Mask:
        """The camera's mask of the footprint at ``pose`` (pixel centres inside).

        Only the pixels in the outline's bounding box are tested (a pixel centre
        outside it is outside the outline), so the cost follows the object's size,
        not the image's.
        """
        shapely = require_shapely()
        h, w = self.image_shape
        outline = self.outline_at(pose)
        poly = shapely.Polygon(outline)
        inside = np.zeros((h, w), bool)
        (c0, r0), (c1, r1) = _pixel_window(self._pixels_unchecked(outline), h, w)
        if c0 < c1 and r0 < r1:
            rows, cols = np.mgrid[r0:r1, c0:c1]
            centres = self.to_world(np.column_stack([cols.ravel(), rows.ravel()]))
            window = shapely.contains_xy(poly, centres[:, 0], centres[:, 1])
            inside[r0:r1, c0:c1] = window.reshape(r1 - r0, c1 - c0)
        if not inside.any():
            corners = self.to_world([(-0.5, -0.5), (w - 0.5, h - 0.5)])
            image = shapely.box(*corners.min(axis=0), *corners.max(axis=0))
            if not poly.intersects(image):
                raise ValueError("the object is outside the camera image at this pose")
            x_min, y_min, x_max, y_max = self.shape.bounds_m
            raise ValueError(
                f"resolution {self.resolution:g} m per pixel is too coarse for this object "
                f"({(x_max - x_min) * 100:.3g} x {(y_max - y_min) * 100:.3g} cm): no pixel "
                "centre falls inside it; choose a finer resolution (e.g. the default "
                f"{comcore.conventions.DEFAULT_RESOLUTION:g} m)"
            )
        return Mask(inside, resolution=self.resolution)

    @cached_property
    def mask(self) -> Mask:
        """The mask at the initial pose."""
        return self.mask_at(None)

    @property
    def step_m(self) -> float:
        """The integration step in metres: ``settings.step_m``, at most half the pusher radius.

        With the default 4 mm pusher the default 1 mm step is used as it is; only radii
        below ``2 * settings.step_m`` shorten it.
        """
        return min(self.settings.step_m, STEP_PER_RADIUS * self.pusher_radius)

    @cached_property
    def _engine(self):
        settings = self.settings
        if self.step_m != settings.step_m:
            settings = dataclasses.replace(settings, step_m=self.step_m)
        if settings.engine == "pymunk":
            from .engines._pymunk import PymunkEngine

            return PymunkEngine(
                self._outline_body,
                self._support_body,
                self.mass.masses,
                self._moment,
                pusher_radius=self.pusher_radius,
                mu_contact=self.mu_contact,
                mu_floor=self.mu_floor,
                settings=settings,
            )
        return QuasiStaticEngine(
            self._outline_body,
            self._support_body,
            self.mass.masses,
            pusher_radius=self.pusher_radius,
            mu_contact=self.mu_contact,
            step_m=settings.step_m,
            projections=settings.projections,
        )

    def __getstate__(self):
        state = self.__dict__.copy()
        state.pop("_engine", None)  # pymunk spaces are rebuilt, not pickled
        return state

    @cached_property
    def _reference_body(self) -> np.ndarray:
        """The initial mask's area centroid as a body point (metres, relative to CoM)."""
        return self.to_world(self.mask.centroid)[0] - self._com

    # -- pushing --------------------------------------------------------------------
    def _material_points(self, poses) -> np.ndarray:
        """World position (n, 2) of the reference body point at each pose (n, 3)."""
        p = np.asarray(poses, dtype=float)
        c, s = np.cos(p[:, 2]), np.sin(p[:, 2])
        rx, ry = self._reference_body
        return np.column_stack(rotate_components(rx, ry, c, s, inverse=True, origin=p[:, :2].T))

    def push(self, action, pose=None, record: bool = False) -> PushResult:
        """Push once and return the motion, the final pose and the real contact.

        Parameters
        ----------
        action : Action or array_like, shape (4,)
            Path of the pusher's leading point in pixels of :attr:`mask`.
        pose : (x, y, angle), optional
            Start pose (CoM in metres, angle in radians); default the initial
            pose. Pass a previous result's ``pose`` to push in sequence.
        record : bool, optional
            Also return the poses along the push (``trajectory``) and the pusher's travel
            at each of them (``travel_px``).

        Returns
        -------
        PushResult
            ``motion.theta`` is the change of angle (CCW on screen);
            ``(motion.tx, motion.ty)`` is the displacement in pixels of the
            material point under the initial mask's area centroid (exactly the
            area centroid's displacement when starting from the initial pose).
            A pusher that misses the object leaves it where it was.

        Raises
        ------
        ValueError
            If the action's start (the pusher's leading point) lies inside the
            object's outline at the start pose, as :func:`comcore.geometry.contacts`
            refuses such actions; if ``pose`` is not three finite numbers; or
            if the path takes more than ``MAX_STEPS_PER_PUSH`` integration steps
            of :attr:`step_m` (100 m at the default step).
            An action starting outside the object whose disc (trailing the
            leading point) would overlap it, as in a notch narrower than the
            pusher, is not refused: the disc is lowered farther back on the
            same line.
        """
        acts = comcore.checks.check_actions(action, "action", allow_empty=False)
        if acts.shape[0] != 1:
            raise ValueError(f"action must be a single action, got {acts.shape[0]}")
        return self._push_checked(acts, pose, record, "action")[0]

    def push_many(self, actions, pose=None, record: bool = False) -> list[PushResult]:
        """Push each action from the same start pose (batched); one :class:`PushResult` each.

        Parameters and errors as for :meth:`push`; ``actions`` has shape (n, 4).
        """
        return self._push_checked(comcore.checks.check_actions(actions), pose, record, "actions")

    def _push_checked(self, acts, pose, record, name) -> list[PushResult]:
        start_pose = self.initial_pose if pose is None else check_pose(pose)
        if acts.shape[0] == 0:
            return []
        self._check_lengths(acts, name)
        ends = self.to_world(acts.reshape(-1, 2)).reshape(-1, 4)
        shapely = require_shapely()
        outline = shapely.Polygon(self.outline_at(start_pose))
        inside = shapely.contains_xy(outline, ends[:, 0], ends[:, 1])
        if inside.any():
            bad = np.flatnonzero(inside)[:5].tolist()
            raise ValueError(
                f"{name} must start outside the object; action(s) {bad} start inside its "
                "outline (the pusher would start within the object)"
            )
        poses = np.tile(start_pose, (len(acts), 1))
        out = self._engine.push_batch(poses, ends[:, :2], ends[:, 2:], record=record)
        moved = self._material_points(out.poses) - self._material_points(poses)
        results = []
        for i in range(len(acts)):
            motion = Motion(
                out.poses[i, 2] - start_pose[2],
                moved[i, 0] / self.resolution,
                -moved[i, 1] / self.resolution,
            )
            contact = normal = None
            if out.hit[i]:
                c = self.to_pixels(out.contact[i])[0]
                contact = (float(c[0]), float(c[1]))
                normal = (float(out.normal[i, 0]), float(-out.normal[i, 1]))
            traj = travel = None
            if out.trajectories is not None:
                traj, travel = out.trajectories[i], out.travel[i] / self.resolution
            pose_i = tuple(float(v) for v in out.poses[i])
            results.append(PushResult(motion, pose_i, contact, normal, traj, travel))
        return results

    def _check_lengths(self, acts: np.ndarray, name: str) -> None:
        """Refuse paths of more than ``MAX_STEPS_PER_PUSH`` integration steps."""
        length_m = np.hypot(acts[:, 2] - acts[:, 0], acts[:, 3] - acts[:, 1]) * self.resolution
        too_long = length_m / self.step_m > MAX_STEPS_PER_PUSH
        if too_long.any():
            bad = np.flatnonzero(too_long)[:5].tolist()
            raise ValueError(
                f"{name} must be at most {MAX_STEPS_PER_PUSH * self.step_m:.3g} m long "
                f"({MAX_STEPS_PER_PUSH} integration steps of {self.step_m:.3g} m, at most half "
                f"the pusher radius); action(s) {bad} run {length_m[bad[0]]:.3g} m: shorten "
                "the path or use a larger pusher_radius"
            )

    def push_motions(self, actions) -> np.ndarray:
        """Motions of a batch of pushes, each from the initial pose, shape (n, 3).

        Examples
        --------
        >>> import comcore
        >>> sim = PushSimulator.from_polygon([(0, 0), (0.06, 0), (0.06, 0.06), (0, 0.06)])
        >>> actions = comcore.sample_pushes(sim.mask, 4, rng=0)
        >>> motions = sim.push_motions(actions)
        >>> motions.shape, bool(np.allclose(motions[1], sim.push(actions[1]).motion))
        ((4, 3), True)
        """
        acts = comcore.checks.check_actions(actions)
        self._check_lengths(acts, "actions")  # indices into the whole batch
        out = np.zeros((acts.shape[0], 3))
        for lo in range(0, acts.shape[0], BATCH_SIZE):
            for i, res in enumerate(self.push_many(acts[lo : lo + BATCH_SIZE])):
                out[lo + i] = res.motion
        return out

    def with_com(self, com_m=None, mu_contact=None) -> PushSimulator:
        """The same object with its mass tilted to ``com_m`` and/or another ``mu_contact``.

        Raises
        ------
        ValueError, TypeError
            If ``com_m`` is not two finite numbers ``(x, y)`` (metres) strictly inside
            the support points.
        """
        mass = (
            self.mass
            if com_m is None
            else self.mass.tilted(_finite_pair(com_m, "com_m", "x, y metres"))
        )
        return PushSimulator(
            self.shape,
            mass,
            mu_contact=self.mu_contact if mu_contact is None else mu_contact,
            resolution=self.resolution,
            margin=self.margin,
            pusher_radius=self.pusher_radius,
            mu_floor=self.mu_floor,
            settings=self.settings,
        )

    def __repr__(self) -> str:
        return (
            f"PushSimulator(shape={self.shape!r}, com_px=({self.com_px[0]:.1f}, "
            f"{self.com_px[1]:.1f}), mu_contact={self.mu_contact:.3f})"
        )


def check_pose(pose, name: str = "pose") -> tuple[float, float, float]:
    """``pose`` as three floats ``(x, y, angle)``, finite, or an error naming ``name``.

    Examples
    --------
    >>> check_pose([0.1, 0.2, 0.0])
    (0.1, 0.2, 0.0)
    >>> check_pose((0.1, 0.2))
    Traceback (most recent call last):
    ...
    ValueError: pose must be three finite numbers (x, y, angle), metres and radians; got shape (2,)
    """
    want = f"{name} must be three finite numbers (x, y, angle), metres and radians"
    if isinstance(pose, (str, bytes, dict)):
        raise TypeError(f"{want}; got {type(pose).__name__}")
    try:
        arr = np.asarray(pose, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{want}; got {pose!r}") from e
    if arr.shape != (3,):
        raise ValueError(f"{want}; got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError(f"{want}; got {arr.tolist()}")
    return (float(arr[0]), float(arr[1]), float(arr[2]))


def _pixel_window(points_px: np.ndarray, h: int, w: int):
    """The pixels of an ``h`` x ``w`` image whose centres may lie in the points' bounding box.

    ``(c0, r0), (c1, r1)``: columns ``c0:c1`` and rows ``r0:r1``, the box of
    ``points_px`` padded by a pixel against rounding; the whole image for non-finite
    points.
    """
    if not np.isfinite(points_px).all():
        return (0, 0), (w, h)
    lo = np.floor(points_px.min(axis=0)) - 1
    hi = np.ceil(points_px.max(axis=0)) + 2
    c0, r0 = (int(min(max(v, 0), n)) for v, n in zip(lo, (w, h)))
    c1, r1 = (int(min(max(v, 0), n)) for v, n in zip(hi, (w, h)))
    return (c0, r0), (c1, r1)


def _image_shape(bounds_m, margin: float, resolution: float) -> tuple[int, int]:
    """``(H, W)`` of the camera image of a footprint with ``bounds_m`` and a ``margin``."""
    x_min, y_min, x_max, y_max = bounds_m
    w = math.ceil((x_max - x_min + 2 * margin) / resolution - 1e-9)
    h = math.ceil((y_max - y_min + 2 * margin) / resolution - 1e-9)
    return (h, w)
