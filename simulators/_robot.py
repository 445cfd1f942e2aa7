"""The :class:`SimulatedRobot`: a push simulator playing a real robot with a fixed camera.

A real robot cannot put the object back after a push, and it sees the object
only through its camera. :class:`SimulatedRobot` wraps a
:class:`~simulators.PushSimulator` that way: the object is never reset (each
:meth:`~SimulatedRobot.execute` pushes from the pose the last push left), the
pusher can miss its commanded path by a random offset, and
:meth:`~SimulatedRobot.camera_mask` is the camera's (optionally noisy) mask at
the current pose, in a camera frame wide enough to keep the object in view.
"""

from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import numpy as np
from scipy import ndimage

import comcore
from comcore import Action, Mask, Motion
from comcore.checks import check_positive, check_probability

from ._deps import require_shapely
from ._settings import EngineSettings
from ._simulator import PushResult, PushSimulator

__all__ = [
    "DEFAULT_CAMERA_MARGIN",
    "RobotPush",
    "SimulatedRobot",
    "camera_frame_margin",
    "noisy_mask",
    "perturb_actions",
    "retreat_starts",
]

#: Table (metres) the robot's camera sees around the disc that holds the object in any
#: orientation (its circumradius about the area centroid): room for the pushes of a
#: session to carry it that far and turn it any way (why not less: docs/results/active.md, where a
#: pushed object leaves the camera's view).
DEFAULT_CAMERA_MARGIN = 0.15
#: A perturbed start that lands inside the object is moved back by this much (metres)
#: at a time, along the push, until it is outside.
RETREAT_STEP_M = 0.001
#: At most this many retreat steps (5 cm) before the push is refused.
MAX_RETREAT_STEPS = 50


class RobotPush(NamedTuple):
    """What :meth:`SimulatedRobot.execute` did."""

    commanded: Action
    """The action asked for (camera pixels)."""
    executed: Action
    """The pusher's real path: ``commanded`` moved by the pusher's position error."""
    motion: Motion
    """The exact motion of this push in the camera frame about the object's area centroid
    before it (the noise-free mask's): what a perfect tracker would report."""
    pose: Motion
    """The object's pose after the push relative to the first mask (:attr:`SimulatedRobot.pose`)."""
    hit: bool
    """Whether the pusher touched the object (``False``: a miss, the object did not move)."""
    result: PushResult
    """The simulator's result (world pose, contact)."""
    frames: tuple = ()
    """Camera masks during the push (``execute(..., frames=k)``), the last at its end."""


def perturb_actions(actions, offset_px, angle, retreat=None) -> np.ndarray:
    """Actions moved across their direction and turned about their start.

    Parameters
    ----------
    actions : array_like, shape (n, 4)
        Pusher paths ``(sx, sy, ex, ey)`` in pixels.
    offset_px : array_like, shape (n,)
        Shift of each whole path along its left-hand normal (the direction turned
        90 degrees counter-clockwise on screen), pixels.
    angle : array_like, shape (n,)
        Turn of each path about its (shifted) start, radians CCW on screen.
    retreat : callable, optional
        ``retreat(starts (n, 2), directions (n, 2)) -> starts (n, 2)``: moves starts
        that landed inside the object back along the push.

    Returns
    -------
    numpy.ndarray, shape (n, 4)

    Examples
    --------
    >>> perturb_actions([[0.0, 0.0, 10.0, 0.0]], [2.0], [0.0]).round(12) + 0.0
    array([[ 0., -2., 10., -2.]])
    """
    acts = comcore.checks.check_actions(actions)
    start, path = acts[:, :2], acts[:, 2:] - acts[:, :2]
    n = len(acts)
    offset = np.broadcast_to(np.asarray(offset_px, float), (n,))
    turn = np.broadcast_to(np.asarray(angle, float), (n,))
    unit = path / np.linalg.norm(path, axis=1, keepdims=True)
    normal = comcore.conventions.rotate_vectors(unit, math.pi / 2)
    new_start = start + offset[:, None] * normal
    new_path = comcore.conventions.rotate_vectors(path, turn)
    end = new_start + new_path
    if retreat is not None:
        new_start = retreat(new_start, new_path / np.linalg.norm(new_path, axis=1, keepdims=True))
    return np.column_stack([new_start, end])


def noisy_mask(mask: Mask, flip: float, rng: np.random.Generator) -> Mask:
    """The mask with each outline pixel flipped with probability ``flip``.

    Outline pixels are the object's pixels with a 4-neighbour outside it and the
    outside pixels with a 4-neighbour inside. After the flips, holes are filled
    and the largest 8-connected component is kept
    (:func:`comcore.geometry.largest_component`, as :func:`comcore.mask_from_image`
    keeps the object's component).

    Parameters
    ----------
    mask : comcore.Mask
    flip : float
        Flip probability of each outline pixel, in [0, 1).
    rng : numpy.random.Generator

    Returns
    -------
    comcore.Mask
        A new mask at the same resolution (``mask`` itself when ``flip`` is 0).
    """
    data = mask.data
    if flip == 0:
        return mask
    inner = data & ~ndimage.binary_erosion(data, border_value=0)
    outer = ndimage.binary_dilation(data) & ~data
    edge = inner | outer
    flips = edge & (rng.random(data.shape) < flip)
    out = comcore.geometry.largest_component(ndimage.binary_fill_holes(data ^ flips))
    if not out.any():  # pragma: no cover - a mask of one pixel, flipped away
        out = data
    return Mask(out, resolution=mask.resolution)


def camera_frame_margin(shape, camera_margin: float, com_m=None) -> float:
    """The simulator ``margin`` (metres) of a camera seeing ``camera_margin`` around the object.

    The image then holds the disc about the footprint's area centroid that
    contains the footprint in every orientation, widened by ``camera_margin``;
    given the CoM ``com_m`` (the shape's frame, metres), also the disc about
    the CoM that does: an object turns about points near its CoM, and a CoM
    near one end of a long bar swings the far end through a disc almost twice
    the bar's half-length wider than the centroid's.
    """
    x_min, y_min, x_max, y_max = shape.bounds_m
    centres = [np.asarray(shape.centroid_m, dtype=float)]
    if com_m is not None:
        centres.append(np.asarray(com_m, dtype=float).reshape(2))
    reach = 0.0
    for centre in centres:
        radius = float(np.max(np.linalg.norm(shape.vertices_m - centre, axis=1)))
        reach = max(
            reach,
            radius - (centre[0] - x_min),
            radius - (x_max - centre[0]),
            radius - (centre[1] - y_min),
            radius - (y_max - centre[1]),
        )
    return float(camera_margin + reach)


def retreat_starts(simulator, pose, starts, directions) -> np.ndarray:
    """Starts (pixels) moved back along ``directions`` until outside the object at ``pose``.

    1 mm steps, at most 5 cm; a start still inside after that is returned as it is
    (the simulator then refuses the push).

    Parameters
    ----------
    simulator : PushSimulator
    pose : (x, y, angle)
        The object's pose (CoM in world metres, angle in radians).
    starts : array_like, shape (n, 2)
        Start points in pixels of ``simulator.mask``.
    directions : array_like, shape (n, 2)
        Unit push directions in pixels.

    Returns
    -------
    numpy.ndarray, shape (n, 2)
    """
    shapely = require_shapely()
    outline = shapely.Polygon(simulator.outline_at(pose))
    step = RETREAT_STEP_M / simulator.resolution
    out = np.array(starts, dtype=float)
    for i in range(len(out)):
        for _ in range(MAX_RETREAT_STEPS):
            w = simulator.to_world(out[i])[0]
            if not shapely.contains_xy(outline, w[0], w[1]):
                break
            out[i] = out[i] - step * np.asarray(directions[i])
    return out


class SimulatedRobot:
    """A push simulator playing a real robot: never reset, seen through a camera.

    The object starts at the simulator's initial pose and stays wherever each
    push leaves it. Actions are in the **camera frame**: pixels of
    :meth:`camera_mask` (x = column, y = row down), the camera fixed and looking
    straight down. The camera covers the disc about the footprint's area
    centroid that holds the object in every orientation, plus ``camera_margin``
    on every side (:func:`camera_frame_margin`), so pushes that turn the object
    any way and carry it a few centimetres keep it in view; :meth:`camera_mask`
    raises when the object touches the image border (it left the view).

    Realism options, each drawn from ``rng``:

    * ``pusher_error``: std (metres) of the pusher's position across the push:
      the whole commanded path is shifted along its normal by one normal draw
      per push. ``angle_error``: std (radians) of a turn of the path about its
      start, drawn per push. A shifted start that lands inside the object is
      moved back along the push (1 mm steps, at most 5 cm) until it is outside,
      as an arm lowering its pusher a little farther back would.
    * ``mask_noise``: probability that each outline pixel of a camera mask is
      flipped (object pixels on the outline become table, table pixels next to
      it become object); holes are then filled and the largest component kept.
      0.5 shifts the outline by about half a pixel, pixel by pixel; every
      :meth:`camera_mask` call draws afresh, like a new camera frame.

    Parameters
    ----------
    simulator : PushSimulator
        The object (shape, mass, friction, pusher). It is not modified; the robot
        builds its own copy with the camera's margin, resolution and engine.
    pusher_error : float, optional
        Metres (std) across the push, default 0.
    angle_error : float, optional
        Radians (std) of the push direction, default 0.
    mask_noise : float, optional
        Flip probability of each outline pixel, in [0, 1), default 0.
    camera_margin : float or None, optional
        Metres of table around the object's bounding disc in the camera image
        (default :data:`DEFAULT_CAMERA_MARGIN`); ``None`` keeps the simulator's
        frame (its mask is then the camera's first image).
    resolution : float, optional
        Metres per camera pixel; default the simulator's.
    engine : str or EngineSettings, optional
        The physics playing the world: ``"quasistatic"``, ``"pymunk"`` or full
        :class:`EngineSettings`; default the simulator's.
    rng : None, int or numpy.random.Generator, optional
        Seed of the pusher and camera noise (:func:`comcore.checks.check_rng`).

    Examples
    --------
    >>> import comcore, simulators
    >>> sim = simulators.random_simulator("Obj3", friction="high", rng=1)
    >>> robot = simulators.SimulatedRobot(sim, pusher_error=0.002, rng=0)
    >>> first = robot.camera_mask()
    >>> action = comcore.sample_pushes(first, 1, rng=0)[0]
    >>> push = robot.execute(action)
    >>> push.hit, robot.pushes, robot.camera_mask().shape == first.shape
    (True, 1, True)
    """

    def __init__(
        self,
        simulator: PushSimulator,
        *,
        pusher_error: float = 0.0,
        angle_error: float = 0.0,
        mask_noise: float = 0.0,
        camera_margin: float | None = DEFAULT_CAMERA_MARGIN,
        resolution: float | None = None,
        engine=None,
        rng=None,
    ):
        if not isinstance(simulator, PushSimulator):
            raise TypeError(
                f"simulator must be a simulators.PushSimulator, got {type(simulator).__name__}"
            )
        self.pusher_error = check_positive(pusher_error, "pusher_error", allow_zero=True)
        self.angle_error = check_positive(angle_error, "angle_error", allow_zero=True)
        self.mask_noise = check_probability(mask_noise, "mask_noise", open_high=True)
        if camera_margin is None:
            margin = simulator.margin
        else:
            margin = check_positive(camera_margin, "camera_margin")
            margin = camera_frame_margin(simulator.shape, margin, simulator.com_m)
        res = (
            simulator.resolution if resolution is None else check_positive(resolution, "resolution")
        )
        if engine is None:
            settings = simulator.settings
        elif isinstance(engine, EngineSettings):
            settings = engine
        elif isinstance(engine, str):
            settings = dataclasses.replace(simulator.settings, engine=engine)
        else:
            raise TypeError(
                "engine must be None, an engine name or a simulators.EngineSettings, "
                f"got {type(engine).__name__}"
            )
        self.simulator = PushSimulator(
            simulator.shape,
            simulator.mass,
            mu_contact=simulator.mu_contact,
            resolution=res,
            margin=margin,
            pusher_radius=simulator.pusher_radius,
            mu_floor=simulator.mu_floor,
            settings=settings,
        )
        self._rng = comcore.checks.check_rng(rng)
        self._world = tuple(float(v) for v in self.simulator.initial_pose)
        self.history: list[RobotPush] = []
        sim = self.simulator
        self._first_centroid_body = sim.to_world(sim.mask.centroid)[0] - np.asarray(sim.com_m)

    # -- what the camera sees -----------------------------------------------------
    @property
    def resolution(self) -> float:
        """Metres per camera pixel."""
        return self.simulator.resolution

    @property
    def image_shape(self) -> tuple[int, int]:
        """``(H, W)`` of the camera image."""
        return self.simulator.image_shape

    @property
    def pushes(self) -> int:
        """Pushes executed so far."""
        return len(self.history)

    @property
    def world_pose(self) -> tuple[float, float, float]:
        """The CoM ``(x, y)`` in world metres and the body angle (radians) now."""
        return self._world

    def _exact_mask(self) -> Mask:
        mask = self.simulator.mask_at(self._world)
        d = mask.data
        if d[0].any() or d[-1].any() or d[:, 0].any() or d[:, -1].any():
            raise ValueError(
                "the object left the camera's view (its mask touches the image border) after "
                f"{self.pushes} push(es); build the robot with a larger camera_margin "
                f"(now {self.simulator.margin:g} m)"
            )
        return mask

    def camera_mask(self) -> Mask:
        """The camera's mask of the object at its current pose (with ``mask_noise``).

        Raises
        ------
        ValueError
            If the object touches the image border or left the image (the camera
            no longer sees all of it).
        """
        return noisy_mask(self._exact_mask(), self.mask_noise, self._rng)

    def true_com_px(self) -> tuple[float, float]:
        """The true CoM in the FIRST mask's frame (pixels): what an estimate is scored on."""
        return self.simulator.com_px

    def com_in_camera(self) -> tuple[float, float]:
        """Where the true CoM is in the camera image now (pixels)."""
        c = self.simulator.to_pixels(self._world[:2])[0]
        return (float(c[0]), float(c[1]))

    def _body_to_pixels(self, body, pose) -> np.ndarray:
        x, y, a = pose
        c, s = math.cos(a), math.sin(a)
        turn = comcore.conventions.rotate_components
        world = np.array(turn(body[0], body[1], c, s, inverse=True, origin=(x, y)))  # to world
        return self.simulator.to_pixels(world)[0]

    def _motion_between(self, body, before, after) -> Motion:
        p0, p1 = self._body_to_pixels(body, before), self._body_to_pixels(body, after)
        return Motion(after[2] - before[2], float(p1[0] - p0[0]), float(p1[1] - p0[1]))

    @property
    def pose(self) -> Motion:
        """The pose now relative to the first (noise-free) mask.

        ``theta`` the turn since the start (CCW on screen); ``(tx, ty)`` the
        displacement in pixels of the material point under the first mask's area
        centroid: the convention of :attr:`comcore.ActiveSession.pose`.
        """
        return self._motion_between(
            self._first_centroid_body, self.simulator.initial_pose, self._world
        )

    # -- the arm ------------------------------------------------------------------
    def _retreat(self, starts: np.ndarray, directions: np.ndarray) -> np.ndarray:
        return retreat_starts(self.simulator, self._world, starts, directions)

    def execute(self, action, frames: int = 0) -> RobotPush:
        """Push the object from where it is now; the object stays where the push leaves it.

        Parameters
        ----------
        action : Action or array_like, shape (4,)
            The commanded pusher path in camera pixels (the leading point's path).
        frames : int, optional
            Also return this many camera masks (with ``mask_noise``) taken during the
            push, evenly spaced along its steps, the last one at its end: what a
            video camera gives a tracker that follows the object (default none).

        Returns
        -------
        RobotPush
            The commanded and executed paths, the exact motion, the new pose and
            whether the pusher touched the object.

        Raises
        ------
        ValueError
            If ``action`` is not one finite, non-zero-length action, or the
            commanded start lies inside the object as it is now (the robot is
            unchanged then).
        """
        acts = comcore.checks.check_actions(action, "action", allow_empty=False)
        if acts.shape[0] != 1:
            raise ValueError(f"action must be a single action (4 numbers), got {acts.shape[0]}")
        if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < 0:
            raise ValueError(f"frames must be an integer >= 0, got {frames!r}")
        sim = self.simulator
        shapely = require_shapely()
        start_w = sim.to_world(acts[0, :2])[0]
        if shapely.contains_xy(shapely.Polygon(sim.outline_at(self._world)), *start_w):
            raise ValueError(
                f"action must start outside the object as it is now; {acts[0].tolist()} starts "
                "inside its outline"
            )
        offset = (
            self._rng.normal(0.0, self.pusher_error / sim.resolution) if self.pusher_error else 0.0
        )
        turn = self._rng.normal(0.0, self.angle_error) if self.angle_error else 0.0
        if offset or turn:
            executed = perturb_actions(acts, [offset], [turn], self._retreat)
        else:
            executed = acts
        before = self._world
        try:  # the pixel mask's area centroid: the frame a tracker reports motions in
            w = sim.to_world(sim.mask_at(before).centroid)[0]
        except ValueError:  # out of the image: the footprint's own centroid
            w = np.asarray(shapely.Polygon(sim.outline_at(before)).centroid.coords[0])
        x, y, a = before
        c, s = math.cos(a), math.sin(a)
        body = np.array(comcore.conventions.rotate_components(w[0] - x, w[1] - y, c, s))
        result = sim.push(executed[0], pose=before, record=bool(frames))
        self._world = tuple(float(v) for v in result.pose)
        shots: tuple = ()
        if frames:
            traj = np.asarray(result.trajectory, float)
            picks = np.round(np.linspace(0, len(traj) - 1, int(frames) + 1)[1:]).astype(int)
            picks[-1] = len(traj) - 1
            poses = [*traj[picks[:-1]], result.pose]
            shots = tuple(
                noisy_mask(sim.mask_at(tuple(p)), self.mask_noise, self._rng) for p in poses
            )
        record = RobotPush(
            Action(*acts[0]),
            Action(*executed[0]),
            self._motion_between(body, before, self._world),
            self.pose,
            result.contact_px is not None,
            result,
            shots,
        )
        self.history.append(record)
        return record

    def place(self, pose=None) -> None:
        """Put the object at ``pose`` (CoM ``(x, y)`` in world metres, angle), not a push.

        What a person or a pick-and-place does; default the initial pose.

        Raises
        ------
        ValueError
            If ``pose`` is not three finite numbers.
        """
        if pose is None:
            pose = self.simulator.initial_pose
        try:
            values = tuple(float(v) for v in pose)
        except (TypeError, ValueError) as e:
            raise TypeError(f"pose must be three numbers (x, y, angle), got {pose!r}") from e
        if len(values) != 3 or not all(map(math.isfinite, values)):
            raise ValueError(f"pose must be three finite numbers (x, y, angle), got {pose!r}")
        self._world = values

    def __repr__(self) -> str:
        return (
            f"SimulatedRobot({self.simulator!r}, pushes={self.pushes}, "
            f"pusher_error={self.pusher_error:g}, mask_noise={self.mask_noise:g})"
        )
