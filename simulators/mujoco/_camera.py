"""The MuJoCo robot's camera: where it is, its homography, and frames warped to a metric grid.

A perspective camera looks straight down at the table from above the middle of
the robot's grid (the top-down metric grid that comcore's masks are made on,
:attr:`MujocoRobot.simulator`'s pixels). A spot light beside it gives the table a
brightness gradient and the object a shadow. The homography from table metres to
image pixels comes from the camera's intrinsics (field of view, image size) and
its pose, for the plane of the object's top face (the outline a camera sees);
frames are warped onto the grid with it (bilinear), as a user warps a calibrated
camera's frames (docs/how-to/camera-frames.md, "Frames, units and your calibration"), and then
go through :func:`comcore.mask_from_image`.

Pixel convention (comcore's): pixel ``(row, col)``'s centre is at ``(x, y) = (col, row)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from comcore.checks import check_positive

__all__ = [
    "MAX_TILT",
    "TABLES",
    "CameraSettings",
    "CameraSetup",
    "homography_table_to_image",
    "warp_to_grid",
]


#: Tables the scene can show (``CameraSettings.table``).
TABLES = ("plain", "wood", "stripes")
#: The largest camera tilt off vertical (radians, about 57 degrees).
MAX_TILT = 1.0


@dataclass(frozen=True)
class CameraSettings:
    """The camera a user sets, and what it sees of the cell.

    Attributes
    ----------
    image_size : (int, int)
        ``(width, height)`` of a frame, pixels.
    fov : float
        Vertical field of view, radians.
    height : float or None
        Camera height above the object's top face, metres; ``None``: as low as keeps
        the whole grid in view.
    shadow_size : int
        Side, texels, of the light's shadow map (MuJoCo's ``visual/quality/shadowsize``,
        64 to 16384). The object's cast shadow, whose edge the segmentation must tell
        from the object's, is drawn at that resolution. Without a GPU (Mesa's software
        renderer) it is most of a frame's render: ``benchmarks/timing/bench_push_frames.py
        --shadow-size`` measures what a smaller one saves; the masks change by a few
        pixels at their edges, so the benchmark's figures are for the default.
    tilt : float
        Angle of the camera's optical axis off vertical, radians, in ``[0, MAX_TILT]``
        (0: straight down). A tilted camera stands on the table's ``-y`` side of the
        grid's middle and looks at it, the image's top edge farthest away; the scale
        of the table in the image then changes from the near edge to the far one.
        ``height`` is still the camera's height above the object's top face.
    table : str
        The table's look: ``"plain"`` (grey), ``"wood"`` (a procedural wood grain) or
        ``"stripes"`` (light and dark bands along ``y``); see :data:`TABLES`.
    arm : bool
        Draw the pusher's arm: a link rising from the pusher disc and reaching out
        past the grid's far edge, moving with the pusher (no mass, no collisions).
        It is in view whenever the pusher is (``execute(..., retract=False)``, the
        frames during a push).

    The defaults (straight down, plain table, no arm) give the scene every existing
    figure was made with; :meth:`MujocoRobot.cell_frame` returns a frame with the
    ground truth a calibration is tested on.

    Examples
    --------
    >>> CameraSettings(image_size=(320, 240)).fov
    0.8
    >>> CameraSettings(shadow_size=1024).shadow_size
    1024
    >>> CameraSettings(tilt=0.5, table="wood", arm=True).table
    'wood'
    >>> CameraSettings(fov=3.2)
    Traceback (most recent call last):
    ...
    ValueError: fov must be in (0, pi) radians, got 3.2 (degrees given as radians?)
    """

    image_size: tuple = (320, 240)
    fov: float = 0.8
    height: float | None = None
    shadow_size: int = 4096
    tilt: float = 0.0
    table: str = "plain"
    arm: bool = False

    def __post_init__(self):
        size = tuple(self.image_size) if np.ndim(self.image_size) == 1 else ()
        if len(size) != 2 or not all(
            isinstance(v, (int, np.integer)) and not isinstance(v, bool) and 16 <= v <= 4096
            for v in size
        ):
            raise ValueError(
                f"image_size must be (width, height), two integers in [16, 4096], "
                f"got {self.image_size!r}"
            )
        object.__setattr__(self, "image_size", (int(size[0]), int(size[1])))
        fov = check_positive(self.fov, "fov")
        if fov >= math.pi:
            raise ValueError(
                f"fov must be in (0, pi) radians, got {fov:g} (degrees given as radians?)"
            )
        if self.height is not None:
            check_positive(self.height, "height")
        size = self.shadow_size
        if not (isinstance(size, (int, np.integer)) and not isinstance(size, bool)):
            raise TypeError(f"shadow_size must be an integer (texels), got {type(size).__name__}")
        if not 64 <= size <= 16384:
            raise ValueError(f"shadow_size must be in [64, 16384] texels, got {size}")
        object.__setattr__(self, "shadow_size", int(size))
        self._check_cell()

    def _check_cell(self) -> None:
        """Check ``tilt``, ``table`` and ``arm``."""
        tilt = check_positive(self.tilt, "tilt", allow_zero=True)
        if tilt > MAX_TILT:
            raise ValueError(
                f"tilt must be in [0, {MAX_TILT:g}] radians off vertical, got {tilt:g}"
                + (" (degrees given as radians?)" if tilt > 2 * math.pi else "")
            )
        object.__setattr__(self, "tilt", tilt)
        if self.table not in TABLES:
            raise ValueError(f"table must be one of {TABLES}, got {self.table!r}")
        if not isinstance(self.arm, (bool, np.bool_)):
            raise TypeError(f"arm must be True or False, got {type(self.arm).__name__}")
        object.__setattr__(self, "arm", bool(self.arm))


@dataclass(frozen=True)
class CameraSetup:
    """Where the camera and light are (world metres), for a grid and a plane height."""

    image_size: tuple
    fov: float
    position: np.ndarray
    xyaxes: np.ndarray
    plane_z: float
    light_pos: np.ndarray
    light_dir: np.ndarray
    light_cutoff_deg: float
    shadow_size: int
    table: str = "plain"
    arm: bool = False
    bounds_m: tuple = ()

    @classmethod
    def above(cls, settings: CameraSettings, bounds_m, plane_z: float) -> CameraSetup:
        """A camera above the middle of ``bounds_m`` seeing all of it at ``plane_z``.

        Straight down, or tilted by ``settings.tilt`` towards ``+y`` (see
        :class:`CameraSettings`).
        """
        x0, y0, x1, y1 = bounds_m
        w, h = settings.image_size
        t = math.tan(0.5 * settings.fov)
        fit = max(0.5 * (y1 - y0) / t, 0.5 * (x1 - x0) / (t * w / h)) * 1.02
        d = fit if settings.height is None else settings.height
        centre = np.array([0.5 * (x0 + x1), 0.5 * (y0 + y1)])
        pos = np.array([centre[0], centre[1], plane_z + d])
        xyaxes = np.array([1.0, 0, 0, 0, 1.0, 0])
        if settings.tilt:
            pos, xyaxes = _tilted(settings, bounds_m, plane_z, d if settings.height else None)
            d = pos[2] - plane_z
        light = np.array([centre[0] + 0.5 * d, centre[1] + 0.35 * d, plane_z + 1.2 * d])
        target = np.array([centre[0], centre[1], 0.0])
        direction = (target - light) / np.linalg.norm(target - light)
        return cls(
            (w, h), settings.fov, pos, xyaxes, plane_z, light, direction, 70.0,
            settings.shadow_size, settings.table, settings.arm, tuple(map(float, bounds_m)),
        )

    @property
    def intrinsics(self) -> tuple[float, float, float, float]:
        """``(fx, fy, cx, cy)`` in pixels, OpenCV's pinhole model (no distortion).

        ``cx, cy`` is the image's middle in comcore's convention (pixel ``(row, col)``
        centred at ``(col, row)``).
        """
        w, h = self.image_size
        return (self.focal_px, self.focal_px, 0.5 * w - 0.5, 0.5 * h - 0.5)

    @property
    def focal_px(self) -> float:
        """Focal length in pixels (``fov`` is vertical, as MuJoCo's ``fovy``)."""
        return 0.5 * self.image_size[1] / math.tan(0.5 * self.fov)


def _tilted(settings: CameraSettings, bounds_m, plane_z: float, height) -> tuple:
    """Position and MuJoCo ``xyaxes`` of a camera tilted towards ``+y`` at the bounds' middle.

    With ``height`` ``None`` the camera backs off along its axis until the whole of
    ``bounds_m`` at ``plane_z`` is in the image (2 % to spare), else it stands
    ``height`` above ``plane_z``.
    """
    x0, y0, x1, y1 = bounds_m
    w, h = settings.image_size
    c, s = math.cos(settings.tilt), math.sin(settings.tilt)
    xyaxes = np.array([1.0, 0.0, 0.0, 0.0, c, s])
    back = np.array([0.0, -s, c])  # the camera's z axis: from what it sees towards it
    target = np.array([0.5 * (x0 + x1), 0.5 * (y0 + y1), plane_z])
    rotation = np.column_stack([xyaxes[:3], xyaxes[3:], back])
    focal = 0.5 * h / math.tan(0.5 * settings.fov)
    corners = np.array([[x0, y0, 1.0], [x1, y0, 1.0], [x1, y1, 1.0], [x0, y1, 1.0]])
    distance = (height / c) if height is not None else 0.5 * max(x1 - x0, y1 - y0)
    for _ in range(200 if height is None else 0):
        hom = homography_table_to_image(target + distance * back, rotation, focal, (w, h), plane_z)
        p = corners @ hom.T
        u, v = p[:, 0] / p[:, 2], p[:, 1] / p[:, 2]
        margin = 0.01 * np.array([w, h])
        inside = (p[:, 2] > 0) & (u >= margin[0]) & (u <= w - 1 - margin[0])
        if np.all(inside & (v >= margin[1]) & (v <= h - 1 - margin[1])):
            break
        distance *= 1.02
    return target + distance * back, xyaxes


def homography_table_to_image(position, rotation, focal_px, image_size, plane_z) -> np.ndarray:
    """The 3x3 homography from table metres ``(x, y)`` at height ``plane_z`` to image pixels.

    Parameters
    ----------
    position : array_like, shape (3,)
        Camera position, world metres.
    rotation : array_like, shape (3, 3)
        Camera orientation: columns are the camera's x (image right), y (image up) and z
        (pointing back, away from what it sees) axes in world coordinates (MuJoCo's
        ``cam_xmat``).
    focal_px : float
    image_size : (width, height)
    plane_z : float

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        ``H`` with ``[u w, v w, w] = H @ [x, y, 1]``; ``u`` the column, ``v`` the row.

    Examples
    --------
    >>> import numpy as np
    >>> H = homography_table_to_image([0, 0, 1.0], np.eye(3), 100.0, (201, 101), 0.0)
    >>> p = H @ [0.1, 0.2, 1.0]
    >>> (p[:2] / p[2]).round(9).tolist()  # 10 px right of the centre, 20 px up
    [110.0, 30.0]
    """
    c = np.asarray(position, float)
    r = np.asarray(rotation, float).reshape(3, 3)
    w, h = image_size
    m = np.array([[1.0, 0.0, -c[0]], [0.0, 1.0, -c[1]], [0.0, 0.0, plane_z - c[2]]])
    k = np.array(
        [[focal_px, 0.0, -(0.5 * w - 0.5)], [0.0, -focal_px, -(0.5 * h - 0.5)], [0.0, 0.0, -1.0]]
    )
    return k @ r.T @ m


def warp_to_grid(image, grid_to_image, grid_shape) -> np.ndarray:
    """The image resampled (bilinear) on a grid, given the grid-pixels-to-image homography.

    Parameters
    ----------
    image : numpy.ndarray, shape (H, W) or (H, W, C)
    grid_to_image : array_like, shape (3, 3)
    grid_shape : (rows, cols)

    Returns
    -------
    numpy.ndarray, shape grid_shape (+ (C,)), float
        Grid pixels that fall outside the image take the nearest edge pixel.
    """
    rows, cols = grid_shape
    yy, xx = np.mgrid[0:rows, 0:cols]
    q = np.stack([xx.ravel(), yy.ravel(), np.ones(rows * cols)]).astype(float)
    p = np.asarray(grid_to_image, float) @ q
    u, v = p[0] / p[2], p[1] / p[2]
    img = np.asarray(image, float)
    chans = [img] if img.ndim == 2 else [img[..., k] for k in range(img.shape[2])]
    out = [
        ndimage.map_coordinates(ch, [v, u], order=1, mode="nearest").reshape(rows, cols)
        for ch in chans
    ]
    return out[0] if img.ndim == 2 else np.stack(out, axis=-1)
