"""The :class:`MujocoRobot`: a MuJoCo scene playing the robot and its camera.

Same shape as :class:`~simulators.SimulatedRobot`: :meth:`~MujocoRobot.camera_mask`
(or the raw :meth:`~MujocoRobot.camera_frame`) out, :meth:`~MujocoRobot.execute`
in, the object never reset. Actions are in pixels of the robot's top-down metric
grid (:attr:`MujocoRobot.simulator`'s frame, ``resolution`` metres per pixel);
masks are made from rendered frames warped onto that grid with the camera's
homography and cut out by :func:`comcore.mask_from_image`, as a user's would be.
MuJoCo's contact solver moves the object; :attr:`MujocoRobot.simulator` is used
only for its grid (pixels <-> table metres) and its polygon masks.
"""

from __future__ import annotations

import contextlib
import math
import warnings
from typing import NamedTuple

import numpy as np

import comcore
from comcore import Action, Motion
from comcore.conventions import rotate_components, rotation_matrix

from .._deps import require_shapely
from .._robot import DEFAULT_CAMERA_MARGIN, MAX_FRAMES_PER_PUSH, _frame_times, camera_frame_margin
from .._simulator import PushSimulator
from ._camera import CameraSettings, CameraSetup, homography_table_to_image, warp_to_grid
from ._scene import PARK_XY, MujocoSettings, build_scene_xml, require_mujoco, scene_assets

__all__ = ["CellFrame", "MujocoPush", "MujocoRobot"]

#: A start whose disc would overlap the object is moved back along the push by this (m).
RETREAT_STEP_M = 0.001
#: After a push the pusher backs off along its path by this much (m), then is parked.
BACK_OFF_M = 0.005
#: Seconds the pusher holds the path's end before backing off (the servo's lag caught up).
HOLD_S = 0.05


class MujocoPush(NamedTuple):
    """What :meth:`MujocoRobot.execute` did."""

    commanded: Action
    """The action asked for (grid pixels)."""
    motion: Motion
    """The object's motion in grid pixels about its outline's area centroid before the push."""
    pose: Motion
    """The pose after the push relative to the first frame (:attr:`MujocoRobot.pose`)."""
    hit: bool
    """Whether the pusher touched the object."""
    world_pose: tuple
    """CoM ``(x, y)`` (table metres) and angle after the push."""
    lag_m: float
    """Largest distance between the pusher and its commanded point during the push (m)."""
    path: tuple[comcore.PushFrame, ...] = ()
    """Camera frames rendered during the push at ``execute(..., frame_rate=...)``: each a
    :class:`comcore.PushFrame`, the pusher's leading point then (grid pixels, from the
    pusher's simulated position: its centre plus ``pusher_radius`` along the push) and
    the mask of the frame (:meth:`MujocoRobot.camera_mask`'s steps, the object taken as
    the bright side: the pusher is in the picture, dark). The frame after the push
    (:meth:`MujocoRobot.camera_mask`) is not one of them."""
    path_times: tuple[float, ...] = ()
    """When each frame of ``path`` was rendered, simulated seconds since the pusher began
    to move (whole time steps)."""
    path_poses: tuple[Motion, ...] = ()
    """The object's pose at each frame of ``path`` relative to the first frame (the
    convention of :attr:`MujocoRobot.pose`)."""


class CellFrame(NamedTuple):
    """A rendered frame of the cell and the ground truth a camera calibration is tested on.

    Table frame: metres, ``x`` and ``y`` on the table (``y`` up in the grid's sense:
    away from a tilted camera), ``z`` up, the table's surface at ``z = 0``.
    """

    image: np.ndarray
    """The rendered RGB frame, uint8 ``(height, width, 3)``."""
    table_to_image: np.ndarray
    """3x3 homography from table-plane metres ``(x, y)`` at ``z = 0`` (where a printed
    board or a touched point lies) to image pixels ``(column, row)``, from the camera
    model: ``[u w, v w, w] = H @ [x, y, 1]``."""
    top_to_image: np.ndarray
    """3x3 homography for the plane of the object's top face (the outline the camera
    sees), ``settings.thickness`` and the feet above the table."""
    outline_m: np.ndarray
    """The object's outline now, table metres, ``(k, 2)``."""
    com_m: tuple
    """The object's CoM now, table metres ``(x, y)``."""
    intrinsics: tuple
    """``(fx, fy, cx, cy)``, pixels: OpenCV's pinhole model, no distortion."""
    camera_position: np.ndarray
    """The camera's centre in the table frame, metres, ``(3,)``."""
    camera_rotation: np.ndarray
    """``(3, 3)``: its columns are the camera's x (image right), y (image down) and z
    (optical axis, forward) axes in the table frame (OpenCV's convention), so a table
    point ``P`` is at ``camera_rotation.T @ (P - camera_position)`` in the camera."""


class _UnstableStep(Exception):
    """MuJoCo flagged the simulation unstable (caught in :meth:`MujocoRobot._stable`)."""


def _yaw(quat) -> float:
    w, x, y, z = quat
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


class MujocoRobot:
    """A MuJoCo scene of a :class:`~simulators.PushSimulator`'s object as a robot with a camera.

    The trial's shape, mass distribution (hence CoM), ``mu_contact``, ``mu_floor``
    and pusher radius are built into a MuJoCo model (:mod:`simulators.mujoco._scene`);
    the pusher follows each commanded path at ``settings.speed`` on slide joints,
    backs off 5 mm, is parked out of view, and the scene settles ``settings.settle``
    seconds before the next frame. Frames: a top-down perspective camera
    (``camera``), rendered offscreen (``MUJOCO_GL=egl``, set if unset);
    ``execute(action, frame_rate=...)`` also renders the frames a camera at that rate
    sees during the push, the pusher in the picture.

    Parameters
    ----------
    simulator : PushSimulator
        The trial. Not modified.
    settings : MujocoSettings, optional
    camera : CameraSettings, optional
    camera_margin : float, optional
        Metres of table around the object's bounding disc on the grid, as
        :class:`~simulators.SimulatedRobot` (default :data:`DEFAULT_CAMERA_MARGIN`).
    resolution : float, optional
        Metres per grid pixel (the masks' resolution); default the simulator's.

    Examples
    --------
    >>> import comcore, simulators
    >>> sim = simulators.random_simulator("Obj3", friction="high", rng=1)
    >>> robot = simulators.MujocoRobot(sim, camera=simulators.CameraSettings((160, 120)))
    >>> first = robot.camera_mask()
    >>> push = robot.execute(comcore.sample_pushes(first, 1, rng=0)[0])
    >>> push.hit, robot.pushes
    (True, 1)
    """

    def __init__(
        self,
        simulator: PushSimulator,
        *,
        settings: MujocoSettings | None = None,
        camera: CameraSettings | None = None,
        camera_margin: float = DEFAULT_CAMERA_MARGIN,
        resolution: float | None = None,
    ):
        if not isinstance(simulator, PushSimulator):
            raise TypeError(
                f"simulator must be a simulators.PushSimulator, got {type(simulator).__name__}"
            )
        self.settings = MujocoSettings() if settings is None else settings
        self.camera = CameraSettings() if camera is None else camera
        for value, cls, name in ((self.settings, MujocoSettings, "settings"),
                                 (self.camera, CameraSettings, "camera")):
            if not isinstance(value, cls):
                raise TypeError(f"{name} must be a simulators.{cls.__name__}, got {value!r}")
        margin = camera_frame_margin(
            simulator.shape, comcore.checks.check_positive(camera_margin, "camera_margin"),
            simulator.com_m,
        )
        res = simulator.resolution if resolution is None else resolution
        self.simulator = PushSimulator(
            simulator.shape, simulator.mass, mu_contact=simulator.mu_contact,
            resolution=comcore.checks.check_positive(res, "resolution"), margin=margin,
            pusher_radius=simulator.pusher_radius, mu_floor=simulator.mu_floor,
        )
        mujoco = require_mujoco()
        self._mj = mujoco
        grid = self.simulator
        h, w = grid.image_shape
        corners = grid.to_world([[-0.5, -0.5], [w - 0.5, h - 0.5]])
        bounds = (*corners.min(axis=0), *corners.max(axis=0))
        top = 2 * self.settings.foot_radius + self.settings.thickness
        self.camera_setup = CameraSetup.above(self.camera, bounds, top)
        xml = build_scene_xml(grid, self.settings, self.camera_setup)
        assets = scene_assets(self.camera_setup)
        self.model = (
            mujoco.MjModel.from_xml_string(xml, assets)
            if assets
            else mujoco.MjModel.from_xml_string(xml)
        )
        self.data = mujoco.MjData(self.model)
        self._body = self.model.body("object").id
        self._pusher_geom = self.model.geom("pusher").id
        self._renderer = None
        bad = ("BADQPOS", "BADQVEL", "BADQACC", "BADCTRL")
        self._unstable_ids = [int(getattr(mujoco.mjtWarning, f"mjWARN_{b}")) for b in bad]
        self._unstable_seen = 0
        mujoco.mj_forward(self.model, self.data)
        self._settle()
        self._start_qpos = self.data.qpos[:7].copy()
        x, y, a = self._body_pose()
        self._centroid_body = self._to_body(grid.to_world(grid.mask.centroid)[0], (x, y, a))
        self._initial = self.world_pose
        self.history: list[MujocoPush] = []

    # -- state --------------------------------------------------------------------
    @property
    def resolution(self) -> float:
        """Metres per grid pixel."""
        return self.simulator.resolution

    @property
    def pushes(self) -> int:
        """Pushes executed."""
        return len(self.history)

    @property
    def com_body(self) -> np.ndarray:
        """MuJoCo's centre of mass of the object in its body frame (= the trial's frame)."""
        return self.model.body_ipos[self._body][:2].copy()

    def _body_pose(self) -> tuple[float, float, float]:
        q = self.data.qpos
        return (float(q[0]), float(q[1]), _yaw(q[3:7]))

    @property
    def world_pose(self) -> tuple[float, float, float]:
        """The object's CoM ``(x, y)`` in table metres and its angle (CCW) now."""
        x, y, a = self._body_pose()
        c = self._to_world(self.com_body, (x, y, a))
        return (float(c[0]), float(c[1]), a)

    @staticmethod
    def _to_world(p, pose) -> np.ndarray:
        x, y, a = pose
        c, s = math.cos(a), math.sin(a)
        return np.array(rotate_components(p[0], p[1], c, s, inverse=True, origin=(x, y)))

    @staticmethod
    def _to_body(p, pose) -> np.ndarray:
        x, y, a = pose
        d = np.asarray(p, float) - (x, y)
        return np.array(rotate_components(d[0], d[1], math.cos(a), math.sin(a)))

    @property
    def outline_m(self) -> np.ndarray:
        """The object's outline now, table metres, (k, 2)."""
        pose = self._body_pose()
        v = self.simulator.shape.vertices_m
        return v @ rotation_matrix(pose[2]) + pose[:2]  # body to world (y up)

    @property
    def true_com_px(self) -> tuple[float, float]:
        """MuJoCo's CoM in the FIRST frame's grid pixels: what an estimate is scored on."""
        c = self.simulator.to_pixels(self._initial[:2])[0]
        return (float(c[0]), float(c[1]))

    @property
    def com_in_camera(self) -> tuple[float, float]:
        """Where the CoM is on the grid now (pixels)."""
        c = self.simulator.to_pixels(self.world_pose[:2])[0]
        return (float(c[0]), float(c[1]))

    def _motion_between(self, body_point, before, after) -> Motion:
        p0 = self.simulator.to_pixels(self._to_world(body_point, before))[0]
        p1 = self.simulator.to_pixels(self._to_world(body_point, after))[0]
        return Motion(after[2] - before[2], float(p1[0] - p0[0]), float(p1[1] - p0[1]))

    @property
    def pose(self) -> Motion:
        """The pose now relative to the first frame (as :attr:`comcore.ActiveSession.pose`)."""
        first = self._start_pose
        return self._motion_between(self._centroid_body, first, self._body_pose())

    @property
    def _start_pose(self):
        q = self._start_qpos
        return (float(q[0]), float(q[1]), _yaw(q[3:7]))

    # -- camera -------------------------------------------------------------------
    def homography_table_to_image(self) -> np.ndarray:
        """3x3 homography from table metres (the top face's plane) to frame pixels."""
        cam = self.model.camera("top").id
        setup = self.camera_setup
        return homography_table_to_image(
            self.data.cam_xpos[cam], self.data.cam_xmat[cam].reshape(3, 3), setup.focal_px,
            setup.image_size, setup.plane_z,
        )

    def homography_grid_to_image(self) -> np.ndarray:
        """3x3 homography from grid pixels to frame pixels."""
        g = self.simulator
        o, ex, ey = g.to_world([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
        grid_to_table = np.column_stack([ex - o, ey - o, o])
        grid_to_table = np.vstack([grid_to_table, [0.0, 0.0, 1.0]])
        return self.homography_table_to_image() @ grid_to_table

    def camera_frame(self) -> np.ndarray:
        """A rendered RGB frame now, uint8 (height, width, 3)."""
        mujoco = self._mj
        if self._renderer is None:
            w, h = self.camera.image_size
            try:
                self._renderer = mujoco.Renderer(self.model, height=h, width=w)
            except Exception as e:  # GLFW without a display, EGL missing, ...
                raise RuntimeError(
                    f"MuJoCo cannot render offscreen here ({e}); set MUJOCO_GL=egl and "
                    "EGL_PLATFORM=surfaceless before mujoco is first "
                    "imported (docs/how-to/mujoco.md)"
                ) from e
        self._renderer.update_scene(self.data, camera="top")
        return self._renderer.render().copy()

    def cell_frame(self) -> CellFrame:
        """A rendered frame now with the camera model and the object's pose on the table.

        What a calibration is tested on: the homography from the table plane to the
        image (a calibration from four or more table points should find it), the
        object's outline in table metres (rasterised on the table plane, the mask a
        rectified frame should give), and the camera's intrinsics and pose. Set the
        camera's tilt, the table's texture and the arm with :class:`CameraSettings`.

        Examples
        --------
        >>> import simulators
        >>> sim = simulators.PushSimulator.from_polygon([(0, 0), (0.08, 0), (0, 0.05)])
        >>> camera = simulators.CameraSettings((160, 120), tilt=0.5, table="wood", arm=True)
        >>> robot = simulators.MujocoRobot(sim, camera=camera)
        >>> cell = robot.cell_frame()
        >>> cell.image.shape, cell.table_to_image.shape, cell.outline_m.shape[1]
        ((120, 160, 3), (3, 3), 2)
        """
        image = self.camera_frame()
        cam = self.model.camera("top").id
        position = self.data.cam_xpos[cam].copy()
        rotation = self.data.cam_xmat[cam].reshape(3, 3).copy()
        setup = self.camera_setup
        hom = [
            homography_table_to_image(position, rotation, setup.focal_px, setup.image_size, z)
            for z in (0.0, setup.plane_z)
        ]
        opencv = rotation * np.array([1.0, -1.0, -1.0])  # MuJoCo's camera: y up, z back
        x, y, _ = self.world_pose
        return CellFrame(
            image, hom[0], hom[1], self.outline_m, (x, y), setup.intrinsics, position, opencv
        )

    def grid_image(self, frame=None) -> np.ndarray:
        """``frame`` (default a new one) warped onto the grid, float RGB (rows, cols, 3)."""
        frame = self.camera_frame() if frame is None else frame
        return warp_to_grid(frame, self.homography_grid_to_image(), self.simulator.image_shape)

    def camera_mask(self, **options) -> comcore.Mask:
        """The object's mask from a new frame, warped to the grid: :func:`comcore.mask_from_image`.

        ``options`` go to :func:`comcore.mask_from_image` (its ValueError when it
        refuses the frame propagates; the robot is unchanged).
        """
        return comcore.mask_from_image(self.grid_image(), resolution=self.resolution, **options)

    # -- the arm ------------------------------------------------------------------
    def _settle(self, seconds: float | None = None) -> None:
        t = self.settings.settle if seconds is None else seconds
        steps = round(t / self.model.opt.timestep)
        if steps:
            self._mj.mj_step(self.model, self.data, nstep=steps)

    def _set_pusher(self, centre) -> None:
        q = np.asarray(centre, float) - PARK_XY
        self.data.qpos[7:9] = q
        self.data.qvel[6:8] = 0.0
        self.data.ctrl[:] = q
        self._mj.mj_forward(self.model, self.data)

    def execute(
        self, action, frames: int = 0, *, retract: bool = True, frame_rate: float | None = None
    ) -> MujocoPush:
        """Push the object from where it is now along ``action`` (grid pixels).

        The pusher's centre is lowered ``pusher_radius`` behind the path's start
        (farther back, 1 mm at a time, if its disc would overlap the object), follows
        the line at ``settings.speed`` to the end, backs off 5 mm and is parked out of
        view; the scene settles ``settings.settle`` s. ``retract=False`` leaves the
        pusher where the path ended, touching the object, in the next frames (what a
        camera sees of an arm that does not move away).

        Parameters
        ----------
        action : Action or array_like, shape (4,)
            The pusher's leading point's path, grid pixels.
        frames : int, optional
            Only 0: there for ``SimulatedRobot.execute``'s callers; the MuJoCo robot
            takes frames at a rate (``frame_rate``), not a count of them.
        retract : bool, optional
            Back the pusher off and park it after the push (default).
        frame_rate : float, optional
            Also render the camera's frames during the push, one every
            ``1 / frame_rate`` simulated seconds (Hz, at most one per time step),
            from when the pusher begins to move until before its set point reaches
            the path's end; each becomes a mask as :meth:`camera_mask` makes one
            (rendered, warped to the grid, :func:`comcore.mask_from_image`, here
            with ``object="bright"``: the pusher is in the picture, dark on the grey
            table, and is never taken for the object). ``MujocoPush.path`` holds
            them, with ``path_times`` and ``path_poses``. A frame costs a render,
            a warp and a ``mask_from_image``: benchmarks/timing/bench_push_frames.py
            measures it (docs/how-to/your-robot.md gives the figures).

        Raises
        ------
        ValueError
            If ``action`` is not one finite, non-zero-length action, is longer than
            the bound :meth:`PushSimulator.push` sets (``MAX_STEPS_PER_PUSH`` steps of
            its ``step_m``), or starts inside the object as it is now, ``frames`` is
            not 0, or ``frame_rate`` is not a finite number > 0, above ``1 /
            settings.timestep`` or would take more than ``MAX_FRAMES_PER_PUSH``
            frames (the robot is unchanged then).
        comcore.ImageError
            If a frame rendered during the push does not show the whole object
            (:func:`comcore.mask_from_image`'s refusal); the scene is put back as it
            was before the push.
        RuntimeError
            If MuJoCo's simulation goes unstable during the push (NaN, infinite or
            huge positions, velocities, accelerations or controls: settings such as
            ``pusher_gain`` or ``timestep`` out of MuJoCo's range); the scene is put
            back as it was before the push.
        TypeError
            If ``frame_rate`` is not a number.
        """
        if frames:
            raise ValueError(
                f"frames={frames!r}: the MuJoCo robot takes no count of frames; for camera "
                "frames during the push give frame_rate= (Hz, simulated time), or take "
                "camera_mask() after it"
            )
        rate = None if frame_rate is None else self._check_frame_rate(frame_rate)
        acts = comcore.checks.check_actions(action, "action", allow_empty=False)
        if acts.shape[0] != 1:
            raise ValueError(f"action must be a single action (4 numbers), got {acts.shape[0]}")
        self.simulator._check_lengths(acts, "action")
        c0, d, length, outline = self._pusher_line(acts[0])
        before = self._body_pose()
        centroid = self._to_body(np.asarray(outline.centroid.coords[0]), before)
        shots = {} if rate is None else self._frame_ticks(length, rate)
        state = self._state()
        with self._stable(state, f"push {self.pushes + 1}"):
            self._set_pusher(c0)
            hit, lag, seen = self._drive(d, length, shots, retract)
            if retract:
                self._set_pusher(PARK_XY)
            self._settle()
        path = self._path_frames(seen, state)
        after = self._body_pose()
        record = MujocoPush(
            Action(*acts[0]), self._motion_between(centroid, before, after), self.pose, hit,
            self.world_pose, lag, *path,
        )
        self.history.append(record)
        return record

    def _check_frame_rate(self, frame_rate) -> float:
        """``frame_rate`` (Hz) as a float: finite, > 0, at most one frame per time step."""
        dt = self.model.opt.timestep
        rate = comcore.checks.check_positive(frame_rate, "frame_rate")
        if rate * dt > 1.0 + 1e-9:
            raise ValueError(
                f"frame_rate must be at most one frame per time step ({1 / dt:g} Hz, "
                f"settings.timestep {dt:g} s), got {rate:g} Hz"
            )
        return rate

    def _pusher_line(self, action: np.ndarray) -> tuple:
        """``(c0, d, length, outline)``: the pusher centre's start, unit direction and travel.

        Table metres; the start is ``pusher_radius`` behind the action's start, moved
        back 1 mm at a time while the disc would overlap ``outline`` (the object's now).
        """
        shapely = require_shapely()
        outline = shapely.Polygon(self.outline_m)
        start, end = self.simulator.to_world(action.reshape(2, 2))
        if shapely.contains_xy(outline, *start):
            raise ValueError(
                f"action must start outside the object as it is now; {action.tolist()} starts "
                "inside its outline"
            )
        r = self.simulator.pusher_radius
        d = (end - start) / np.linalg.norm(end - start)
        c0, c1 = start - r * d, end - r * d
        for _ in range(int(0.5 / RETREAT_STEP_M)):
            if shapely.distance(outline, shapely.Point(*c0)) > r:
                break
            c0 = c0 - RETREAT_STEP_M * d
        return c0, d, float(np.dot(c1 - c0, d)), outline

    def _frame_ticks(self, length: float, rate: float) -> dict[int, int]:
        """Time step -> frame index of the frames at ``rate`` during a travel of ``length`` (m)."""
        dt = self.model.opt.timestep
        n_forward = max(1, math.ceil(length / (self.settings.speed * dt)))
        ticks = np.round(_frame_times(n_forward * dt, rate) / dt).astype(int)
        ticks = ticks[(ticks >= 1) & (ticks < n_forward)]
        if len(ticks) > MAX_FRAMES_PER_PUSH:
            raise ValueError(
                f"frame_rate {rate:g} Hz takes {len(ticks)} frames during this push "
                f"({length:.3g} m at speed {self.settings.speed:g} m/s), more than "
                f"MAX_FRAMES_PER_PUSH ({MAX_FRAMES_PER_PUSH}): frame_rate is in Hz"
            )
        return {int(k): i for i, k in enumerate(ticks)}

    def _drive(self, d: np.ndarray, length: float, shots: dict, retract: bool) -> tuple:
        """Servo the pusher ``length`` along ``d`` (and back ``BACK_OFF_M`` with ``retract``).

        Returns ``(hit, lag, seen)``: whether it touched the object, its largest lag
        (m), and per frame of ``shots`` its time, the RGB frame, the leading point
        (table metres) and the pose.
        """
        mj, model, data = self._mj, self.model, self.data
        step = self.settings.speed * model.opt.timestep
        lag, hit = 0.0, False
        seen = []
        for travel in (length, -BACK_OFF_M) if retract else (length,):
            origin = data.qpos[7:9].copy()
            n = max(1, math.ceil(abs(travel) / step))
            for k in range(1, n + 1):
                data.ctrl[:] = origin + (travel * k / n) * d
                mj.mj_step(model, data)
                self._raise_if_unstable()
                if not hit and data.ncon:
                    hit = bool(np.any(data.contact.geom[: data.ncon] == self._pusher_geom))
                lag = max(lag, float(np.hypot(*(data.qpos[7:9] - data.ctrl))))
                if travel > 0 and k in shots:
                    # mj_step leaves the bodies' frames one step behind qpos: bring them up
                    mj.mj_kinematics(model, data)
                    lead = data.qpos[7:9] + PARK_XY + self.simulator.pusher_radius * d
                    seen.append((k * model.opt.timestep, self.camera_frame(), lead, self.pose))
            if travel > 0:  # hold the end point until the servo has caught up
                mj.mj_step(model, data, nstep=max(1, round(HOLD_S / model.opt.timestep)))
        return hit, lag, seen

    def _unstable_count(self) -> int:
        """How many times MuJoCo has flagged a bad position, velocity, acceleration or control."""
        return sum(int(self.data.warning[i].number) for i in self._unstable_ids)

    def _raise_if_unstable(self) -> None:
        if self._unstable_count() > self._unstable_seen:
            raise _UnstableStep

    @contextlib.contextmanager
    def _stable(self, state: np.ndarray, what: str):
        """Step MuJoCo inside: its warnings caught (no MUJOCO_LOG.TXT), instability raised.

        MuJoCo resets a simulation that goes unstable and carries on; here the scene
        is put back to ``state`` and a RuntimeError names ``what`` went wrong. Other
        MuJoCo warnings come out as Python ``RuntimeWarning``.
        """
        mj, messages = self._mj, []
        previous = mj.get_mju_user_warning()
        self._unstable_seen = self._unstable_count()
        mj.set_mju_user_warning(messages.append)
        try:
            yield
            self._raise_if_unstable()
            if not np.all(np.isfinite(self.data.qpos)):  # pragma: no cover - MuJoCo resets first
                raise _UnstableStep
        except _UnstableStep:
            self._restore(state)
            raise RuntimeError(
                f"MuJoCo's simulation went unstable during {what} "
                f"({'; '.join(messages) or 'non-finite state'}); the scene is put back as it "
                "was before it. MujocoSettings out of MuJoCo's range (pusher_gain, timestep, "
                "speed)?"
            ) from None
        finally:
            mj.set_mju_user_warning(previous)
            for message in messages:
                if "unstable" not in message.lower():
                    warnings.warn(f"MuJoCo: {message}", RuntimeWarning, stacklevel=3)

    def _state(self) -> np.ndarray:
        """The scene's full integration state (MuJoCo's ``mjSTATE_INTEGRATION``)."""
        mj = self._mj
        spec = mj.mjtState.mjSTATE_INTEGRATION
        state = np.empty(mj.mj_stateSize(self.model, spec))
        mj.mj_getState(self.model, self.data, state, spec)
        return state

    def _restore(self, state: np.ndarray) -> None:
        mj = self._mj
        mj.mj_setState(self.model, self.data, state, mj.mjtState.mjSTATE_INTEGRATION)
        mj.mj_forward(self.model, self.data)

    def _path_frames(self, seen, state) -> tuple:
        """``(path, path_times, path_poses)`` of :class:`MujocoPush` from the rendered frames.

        A frame that ``mask_from_image`` refuses puts the scene back to ``state`` (before
        the push) and raises its error.
        """
        grid, frames = self.simulator, []
        to_image = self.homography_grid_to_image()
        for t, image, lead, _ in seen:
            warped = warp_to_grid(image, to_image, grid.image_shape)
            try:
                mask = comcore.mask_from_image(warped, resolution=self.resolution, object="bright")
            except comcore.ImageError as e:
                self._restore(state)
                raise comcore.ImageError(
                    f"the frame at t = {t:.3g} s of push {self.pushes + 1}: {e}"
                ) from e
            p = grid.to_pixels(lead)[0]
            frames.append(comcore.PushFrame((float(p[0]), float(p[1])), mask))
        return tuple(frames), tuple(s[0] for s in seen), tuple(s[3] for s in seen)

    def execute_table(self, push_m, *, rest=None) -> MujocoPush:
        """Push along ``push_m``, ``(sx, sy, ex, ey)`` in table metres: what a cell's arm takes.

        Parameters
        ----------
        push_m : array_like, shape (4,)
            The pusher's leading point's path, table metres (the frame of
            :meth:`cell_frame`).
        rest : (float, float), optional
            A table point (metres) where the pusher and its arm then wait, in the
            camera's view (:meth:`rest_pusher`); default parked out of view.

        Returns
        -------
        MujocoPush
            As :meth:`execute`, which makes the push on the grid's pixels.

        Raises
        ------
        ValueError
            If ``push_m`` is not four finite numbers, or as :meth:`execute` (a start
            inside the object, a push too long) or :meth:`rest_pusher`.
        """
        push = np.asarray(push_m, dtype=float)
        if push.shape != (4,) or not np.isfinite(push).all():
            raise ValueError(
                f"push_m must be four finite numbers (sx, sy, ex, ey) in table metres, "
                f"got {push_m!r}"
            )
        record = self.execute(Action(*self.simulator.to_pixels(push.reshape(2, 2)).ravel()))
        if rest is not None:
            self.rest_pusher(rest)
        return record

    def rest_pusher(self, at=None) -> None:
        """Put the pusher (and the arm drawn on it) at table point ``at`` (metres), still.

        Default: parked out of view. A point whose pusher disc would touch the object
        is refused with a ValueError (the robot is unchanged).
        """
        if at is None:
            self._set_pusher(PARK_XY)
            return
        xy = np.asarray(at, dtype=float)
        if xy.shape != (2,) or not np.isfinite(xy).all():
            raise ValueError(f"at must be a table point (x, y) in metres, got {at!r}")
        shapely = require_shapely()
        gap = shapely.distance(shapely.Polygon(self.outline_m), shapely.Point(*xy))
        if gap <= self.simulator.pusher_radius:
            raise ValueError(
                f"at={tuple(xy.tolist())} puts the pusher on the object ({gap * 1000:.1f} mm "
                f"from its outline, radius {self.simulator.pusher_radius * 1000:.1f} mm)"
            )
        self._set_pusher(xy)

    def empty_table_frame(self) -> np.ndarray:
        """A rendered frame with the object taken out of view, the scene left as it was.

        What a cell's camera sees of the empty table (the arm where it is now): the
        ``background=`` of :func:`comcore.mask_from_image`.
        """
        state = self._state()
        self.data.qpos[:2] += 2.0 * np.asarray(PARK_XY)
        self._mj.mj_forward(self.model, self.data)
        try:
            return self.camera_frame()
        finally:
            self._restore(state)

    def place(self, pose=None) -> None:
        """Put the object at ``pose`` (CoM ``(x, y)`` table metres, angle); default the start.

        What a person does between trials; not a push (not counted). The scene then settles.
        """
        if pose is None:
            self.data.qpos[:7] = self._start_qpos
        else:
            try:
                x, y, a = (float(v) for v in pose)
            except (TypeError, ValueError) as e:
                raise TypeError(f"pose must be three numbers (x, y, angle), got {pose!r}") from e
            if not all(map(math.isfinite, (x, y, a))):
                raise ValueError(f"pose must be three finite numbers (x, y, angle), got {pose!r}")
            origin = np.array([x, y]) - self._to_world(self.com_body, (0.0, 0.0, a))
            self.data.qpos[:7] = [*origin, self._start_qpos[2], math.cos(a / 2), 0, 0,
                                  math.sin(a / 2)]
        self.data.qvel[:6] = 0.0
        self._set_pusher(PARK_XY)
        self._settle(min(self.settings.settle, 0.05))

    def close(self) -> None:
        """Free the renderer's GL context (also done when the robot is garbage-collected)."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    def __repr__(self) -> str:
        return f"MujocoRobot({self.simulator.shape!r}, pushes={self.pushes})"
