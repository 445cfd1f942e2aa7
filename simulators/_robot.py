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
    "DEFAULT_PUSHER_SPEED",
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
#: The pusher's speed along its path (m/s) that times the frames of ``execute(...,
#: frame_rate=...)``: 3 cm in 1.5 s, about an arm's slow, quasi-static push.
DEFAULT_PUSHER_SPEED = 0.02
#: ``execute(..., frame_rate=...)`` refuses a push that would take more frames than this
#: (each is a camera mask kept in memory): a frame rate in the wrong unit.
MAX_FRAMES_PER_PUSH = 1000


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
    path: tuple[comcore.PushFrame, ...] = ()
    """Camera frames taken during the push at ``execute(..., frame_rate=...)``: each a
    :class:`comcore.PushFrame`, the pusher's leading point then (camera pixels, on the
    ``executed`` path) and the camera's mask then (with ``mask_noise``). The mask after
    the push (:meth:`SimulatedRobot.camera_mask`) is not one of them."""
    path_times: tuple[float, ...] = ()
    """When each frame of ``path`` was taken, seconds since the push began: ``k /
    frame_rate`` for ``k = 1, 2, ...``, strictly before the push ended."""
    path_poses: tuple[Motion, ...] = ()
    """The object's true pose at each frame of ``path``, relative to the first mask (the
    convention of :attr:`SimulatedRobot.pose`)."""


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


def _poses_at_travel(trajectory, travel, at) -> np.ndarray:
    """Poses interpolated linearly in the pusher's travel along a recorded push.

    Parameters
    ----------
    trajectory : array_like, shape (k, 3)
        Poses along the push (``PushResult.trajectory``).
    travel : array_like, shape (k,)
        The pusher's travel at each of them, non-decreasing (``PushResult.travel_px``).
    at : array_like, shape (m,)
        Travels (the unit of ``travel``) to give the pose at.

    Returns
    -------
    numpy.ndarray, shape (m, 3)
        Each row linear between the two recorded poses around its travel (the angle
        too); the first pose before the first recorded travel (the pusher has not
        reached the object), the last after the last.

    Examples
    --------
    >>> _poses_at_travel([[0, 0, 0], [0, 0, 0], [1.0, 0, 0.2]], [4.0, 4.0, 6.0], [3.0, 5.0])
    array([[0. , 0. , 0. ],
           [0.5, 0. , 0.1]])
    """
    poses = np.asarray(trajectory, dtype=float).reshape(-1, 3)
    along = np.asarray(travel, dtype=float).reshape(-1)
    q = np.asarray(at, dtype=float).reshape(-1)
    if len(along) == 1:
        return np.repeat(poses, len(q), axis=0)
    i = np.clip(np.searchsorted(along, q, side="right") - 1, 0, len(along) - 2)
    span = along[i + 1] - along[i]
    w = np.divide(q - along[i], span, out=np.zeros_like(q), where=span > 0)
    w = np.clip(w, 0.0, 1.0)
    return poses[i] + w[:, None] * (poses[i + 1] - poses[i])


def _frame_times(duration: float, frame_rate: float) -> np.ndarray:
    """The times ``k / frame_rate`` (``k = 1, 2, ...``) strictly before ``duration`` (seconds).

    A time within a relative 1e-9 of ``duration`` counts as the end, not before it.

    Examples
    --------
    >>> _frame_times(0.3, 10.0).tolist(), _frame_times(0.05, 10.0).tolist()
    ([0.1, 0.2], [])
    """
    n = max(math.ceil(duration * frame_rate * (1.0 - 1e-9)) - 1, 0)
    return np.arange(1, n + 1) / frame_rate


def _check_frame_rate(frame_rate, frames) -> float:
    """``frame_rate`` (Hz) as a float, refusing a bad one and ``frames`` given beside it."""
    rate = check_positive(frame_rate, "frame_rate")
    if frames:
        raise TypeError(
            f"execute takes frames (a count, got {frames!r}) or frame_rate (Hz), not both"
        )
    return rate


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

    The object starts at the simulator's initial pose and stays wherever each push leaves it.
    Actions are in the **camera frame**: pixels of :meth:`camera_mask` (x = column, y = row
    down), the camera fixed and looking straight down. The camera covers the disc about the
    footprint's area centroid that holds the object in every orientation, plus
    ``camera_margin`` on every side (:func:`camera_frame_margin`), so pushes that turn the
    object any way and carry it a few centimetres keep it in view; :meth:`camera_mask` raises
    when the object touches the image border (it left the view). ``execute(action,
    frame_rate=...)`` also returns the frames a video camera saw during the push.

    Parameters
    ----------
    simulator : PushSimulator
        The object (shape, mass, friction, pusher). It is not modified; the robot builds its
        own copy with the camera's margin, resolution and engine.
    pusher_error : float, optional
        Std (metres) of the pusher's position: the whole path is shifted along its normal by
        one draw per push (default 0). A start shifted into the object is moved back along
        the push (1 mm steps, at most 5 cm) until it is outside.
    angle_error : float, optional
        Std (radians) of a turn of the path about its start, drawn per push (default 0).
    mask_noise : float, optional
        Probability, in [0, 1), that each outline pixel of a camera mask is flipped (holes
        then filled, the largest component kept); each :meth:`camera_mask` draws afresh
        (default 0; 0.5 moves the outline by about half a pixel).
    camera_margin : float or None, optional
        Metres of table around the object's bounding disc in the camera image (default
        :data:`DEFAULT_CAMERA_MARGIN`); ``None`` keeps the simulator's frame.
    resolution : float, optional
        Metres per camera pixel; default the simulator's.
    engine : str or EngineSettings, optional
        The physics: ``"quasistatic"``, ``"pymunk"`` or :class:`EngineSettings`; default the
        simulator's.
    speed : float, optional
        The pusher's speed along its path, m/s (default :data:`DEFAULT_PUSHER_SPEED`): what
        times the video frames. The pushes are quasi-static whatever it is.
    rng : None, int or numpy.random.Generator, optional
        Seed of the pusher and camera noise, the only random draws.

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
        speed: float = DEFAULT_PUSHER_SPEED,
        rng=None,
    ):
        if not isinstance(simulator, PushSimulator):
            raise TypeError(
                f"simulator must be a simulators.PushSimulator, got {type(simulator).__name__}"
            )
        self.pusher_error = check_positive(pusher_error, "pusher_error", allow_zero=True)
        self.angle_error = check_positive(angle_error, "angle_error", allow_zero=True)
        self.mask_noise = check_probability(mask_noise, "mask_noise", open_high=True)
        self.speed = check_positive(speed, "speed")
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

    def _exact_mask(self, pose=None, when: str | None = None) -> Mask:
        """The noise-free mask at ``pose`` (default: now); ``when`` names it in the error."""
        mask = self.simulator.mask_at(self._world if pose is None else pose)
        d = mask.data
        if d[0].any() or d[-1].any() or d[:, 0].any() or d[:, -1].any():
            when = f"after {self.pushes} push(es)" if when is None else when
            raise ValueError(
                "the object left the camera's view (its mask touches the image border) "
                f"{when}; build the robot with a larger camera_margin "
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

    @property
    def true_com_px(self) -> tuple[float, float]:
        """The true CoM in the FIRST mask's frame (pixels): what an estimate is scored on."""
        return self.simulator.com_px

    @property
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

    def execute(self, action, frames: int = 0, *, frame_rate: float | None = None) -> RobotPush:
        """Push the object from where it is now; the object stays where the push leaves it.

        Parameters
        ----------
        action : Action or array_like, shape (4,)
            The commanded pusher path in camera pixels (the leading point's path).
        frames : int, optional
            Also return this many camera masks (with ``mask_noise``) taken during the
            push, evenly spaced along its steps, the last one at its end: what a
            video camera gives a tracker that follows the object (default none).
        frame_rate : float, optional
            Also return the frames of a camera taking one every ``1 / frame_rate``
            seconds (Hz) during the push, in ``RobotPush.path`` (with
            ``path_times`` and ``path_poses``). The push starts at time 0 with the
            pusher's leading point at the start of the executed path and moves along
            it at :attr:`speed`; frames are taken at ``1 / frame_rate``,
            ``2 / frame_rate``, ... strictly before it reaches the end (the mask
            after the push is :meth:`camera_mask`'s). Each frame holds where the
            leading point is then and the camera's mask (with ``mask_noise``, drawn
            afresh) of the object at the pose interpolated, linearly in the
            pusher's travel, between the engine's recorded poses (the start pose
            until the pusher reaches the object). A frame costs one rasterisation
            of the footprint over its bounding box (:meth:`PushSimulator.mask_at`)
            and, with ``mask_noise``, a noise draw over the whole image;
            benchmarks/timing/bench_push_frames.py measures it
            (docs/how-to/your-robot.md gives the figures). Not with ``frames``.

        Returns
        -------
        RobotPush
            The commanded and executed paths, the exact motion, the new pose and
            whether the pusher touched the object.

        Raises
        ------
        ValueError
            If ``action`` is not one finite, non-zero-length action, or the
            commanded start lies inside the object as it is now; if ``frame_rate``
            is not a finite number > 0, or would take more than
            :data:`MAX_FRAMES_PER_PUSH` frames; if a frame's mask touches the image
            border, as :meth:`camera_mask` (the robot's pose and history are
            unchanged then).
        TypeError
            If ``frame_rate`` is not a number, or ``frames`` and ``frame_rate`` are
            both given.
        """
        acts = comcore.checks.check_actions(action, "action", allow_empty=False)
        if acts.shape[0] != 1:
            raise ValueError(f"action must be a single action (4 numbers), got {acts.shape[0]}")
        if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < 0:
            raise ValueError(f"frames must be an integer >= 0, got {frames!r}")
        sim = self.simulator
        rate = None if frame_rate is None else self._path_rate(acts[0], frame_rate, frames)
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
        result = sim.push(executed[0], pose=before, record=bool(frames) or rate is not None)
        path = ()
        if rate is not None:  # before the pose changes: a frame out of view changes nothing
            path = self._path_frames(executed[0], result, rate)
        self._world = tuple(float(v) for v in result.pose)
        shots = self._frames_along(result, frames) if frames else ()
        record = RobotPush(
            Action(*acts[0]),
            Action(*executed[0]),
            self._motion_between(body, before, self._world),
            self.pose,
            result.contact_px is not None,
            result,
            shots,
            *path,
        )
        self.history.append(record)
        return record

    def _path_rate(self, action: np.ndarray, frame_rate, frames) -> float:
        """``frame_rate`` (Hz) checked for a push along ``action``: at most MAX_FRAMES_PER_PUSH."""
        rate = _check_frame_rate(frame_rate, frames)
        length_m = math.hypot(*(action[2:] - action[:2])) * self.simulator.resolution
        n_frames = len(_frame_times(length_m / self.speed, rate))
        if n_frames > MAX_FRAMES_PER_PUSH:
            raise ValueError(
                f"frame_rate {rate:g} Hz takes {n_frames} frames during this push "
                f"({length_m:.3g} m at speed {self.speed:g} m/s), more than "
                f"MAX_FRAMES_PER_PUSH ({MAX_FRAMES_PER_PUSH}): frame_rate is in Hz"
            )
        return rate

    def _frames_along(self, result: PushResult, frames: int) -> tuple:
        """``frames`` camera masks evenly spaced along the recorded push, the last at its end."""
        traj = np.asarray(result.trajectory, float)
        picks = np.round(np.linspace(0, len(traj) - 1, int(frames) + 1)[1:]).astype(int)
        picks[-1] = len(traj) - 1
        poses = [*traj[picks[:-1]], result.pose]
        sim = self.simulator
        return tuple(noisy_mask(sim.mask_at(tuple(p)), self.mask_noise, self._rng) for p in poses)

    def _path_frames(self, executed: np.ndarray, result: PushResult, rate: float) -> tuple:
        """``(path, path_times, path_poses)`` of :class:`RobotPush` for ``execute``'s frames."""
        sim = self.simulator
        start, end = executed[:2], executed[2:]
        length_px = float(np.hypot(*(end - start)))
        times = _frame_times(length_px * sim.resolution / self.speed, rate)
        along = times * self.speed / sim.resolution  # the leading point's travel, pixels
        pushers = start + along[:, None] * ((end - start) / length_px)
        poses = _poses_at_travel(result.trajectory, result.travel_px, along)
        frames = []
        for t, pusher, pose in zip(times, pushers, poses):
            when = f"at t = {t:.3g} s during push {self.pushes + 1}"
            mask = noisy_mask(self._exact_mask(tuple(pose), when), self.mask_noise, self._rng)
            frames.append(comcore.PushFrame((float(pusher[0]), float(pusher[1])), mask))
        first = sim.initial_pose
        motions = tuple(self._motion_between(self._first_centroid_body, first, p) for p in poses)
        return tuple(frames), tuple(float(t) for t in times), motions

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
