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

__all__ = ["CameraSettings", "CameraSetup", "homography_table_to_image", "warp_to_grid"]


@dataclass(frozen=True)
class CameraSettings:
    """The camera a user sets.

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

    Examples
    --------
    >>> CameraSettings(image_size=(320, 240)).fov
    0.8
    >>> CameraSettings(shadow_size=1024).shadow_size
    1024
    >>> CameraSettings(fov=3.2)
    Traceback (most recent call last):
    ...
    ValueError: fov must be in (0, pi) radians, got 3.2 (degrees given as radians?)
    """

    image_size: tuple = (320, 240)
    fov: float = 0.8
    height: float | None = None
    shadow_size: int = 4096

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

    @classmethod
    def above(cls, settings: CameraSettings, bounds_m, plane_z: float) -> CameraSetup:
        """A camera straight above the middle of ``bounds_m`` seeing all of it at ``plane_z``."""
        x0, y0, x1, y1 = bounds_m
        w, h = settings.image_size
        t = math.tan(0.5 * settings.fov)
        fit = max(0.5 * (y1 - y0) / t, 0.5 * (x1 - x0) / (t * w / h)) * 1.02
        d = fit if settings.height is None else settings.height
        centre = np.array([0.5 * (x0 + x1), 0.5 * (y0 + y1)])
        pos = np.array([centre[0], centre[1], plane_z + d])
        light = np.array([centre[0] + 0.5 * d, centre[1] + 0.35 * d, plane_z + 1.2 * d])
        target = np.array([centre[0], centre[1], 0.0])
        direction = (target - light) / np.linalg.norm(target - light)
        return cls(
            (w, h), settings.fov, pos, np.array([1.0, 0, 0, 0, 1.0, 0]), plane_z, light,
            direction, 70.0, settings.shadow_size,
        )  # fmt: skip

    @property
    def focal_px(self) -> float:
        """Focal length in pixels (``fov`` is vertical, as MuJoCo's ``fovy``)."""
        return 0.5 * self.image_size[1] / math.tan(0.5 * self.fov)


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
