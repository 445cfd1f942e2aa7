"""Camera frames of a flat object carrying a fiducial tag (AprilTag or ArUco), with the truth.

One generator for the tests (tests/camera/test_tags.py), the benchmark
(benchmarks/accuracy/bench_tags.py) and the how-to (docs/how-to/tags.md). The
scene lies in comcore's pixel frame (x = column, y = row down, the mask's
frame): a bright object (a polygon) on a dark table, and on the object a tag,
the marker image of ``cv2.aruco.generateImageMarker`` (black border included:
its outer corners are the corners the detector returns) turned by ``theta``
(counter-clockwise on screen, :mod:`comcore.conventions`) about its centre. The
camera sees that plane through ``image_from_pixels``, a homography from the
scene's pixels to the image's (identity: a camera looking straight down, its
image already the mask frame).

Each image pixel is sampled at 4 x 4 points, each mapped back into the scene
by the inverse homography and read there (the polygon by the even-odd rule,
the tag by its cell): the marker warped by the homography with nearest-cell
lookup on a four-times finer grid, then averaged, which is what
``cv2.warpPerspective`` of an upsampled marker does, without its resampling
blur. The lens blurs the image (Gaussian, ``blur`` px), the sensor adds
Gaussian noise (``noise`` grey levels), and the result is rounded to uint8.
Only the object's neighbourhood is sampled; the rest of the frame is table.
cv2 is imported when a frame is rendered (``pip install comcore[sim]``).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

import comcore

__all__ = ["marker_cells", "render_tag_frame"]

#: Sub-samples per image pixel along each axis.
SAMPLES = 4


def marker_cells(tag_id: int, dictionary: str = "apriltag_36h11") -> np.ndarray:
    """The marker's cells, bool (n, n), True white, black border included.

    ``dictionary`` is a name of :data:`comcore.camera.TAG_DICTIONARIES`.

    Examples
    --------
    >>> cells = marker_cells(0)
    >>> cells.shape, bool(cells[0].any() or cells[:, 0].any())  # 6 x 6 bits in a black border
    ((8, 8), False)
    """
    if dictionary not in comcore.camera.TAG_DICTIONARIES:
        raise ValueError(
            f"dictionary must be one of {list(comcore.camera.TAG_DICTIONARIES)}, got {dictionary!r}"
        )
    try:
        import cv2
    except ImportError as e:
        raise ImportError("rendering a tag needs opencv: pip install comcore[sim]") from e
    d = cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, "DICT_" + dictionary.upper()))
    n = int(d.markerSize) + 2
    return cv2.aruco.generateImageMarker(d, int(tag_id), n, borderBits=1) > 127


def _inside(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Even-odd rule for (m, 2) points against a (k, 2) polygon."""
    x, y = points[:, 0], points[:, 1]
    inside = np.zeros(len(points), bool)
    x0, y0 = polygon[:, 0], polygon[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    for ax, ay, bx, by in zip(x0, y0, x1, y1):
        crosses = (ay > y) != (by > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            at = ax + (y - ay) * (bx - ax) / (by - ay)
        inside ^= crosses & (x < at)
    return inside


def _apply(h: np.ndarray, points: np.ndarray) -> np.ndarray:
    q = points @ h[:, :2].T + h[:, 2]
    return q[:, :2] / q[:, 2:]


def render_tag_frame(
    outline,
    tag_centre,
    tag_theta: float,
    tag_side: float,
    *,
    tag_id: int = 0,
    dictionary: str = "apriltag_36h11",
    shape: tuple[int, int] = (240, 320),
    image_from_pixels=None,
    blur: float = 0.8,
    noise: float = 3.0,
    table: float = 70.0,
    surface: float = 210.0,
    ink: float = 25.0,
    rng=None,
) -> np.ndarray:
    """Render the camera image of an object carrying a tag (see the module's docstring).

    Parameters
    ----------
    outline : array_like, shape (k, 2)
        The object's outline where it is now, comcore pixels.
    tag_centre : array_like, shape (2,)
        The tag's centre, comcore pixels.
    tag_theta : float
        The tag's rotation, radians, counter-clockwise on screen (0: upright).
    tag_side : float
        The marker's side (its black border's outer edge), comcore pixels.
    tag_id, dictionary
        Which marker (:data:`comcore.camera.TAG_DICTIONARIES`).
    shape : (int, int)
        The image's (rows, cols).
    image_from_pixels : array_like, shape (3, 3), optional
        Homography from comcore pixels to image pixels; default identity.
    blur, noise : float
        Lens blur (Gaussian std, px) and sensor noise (std, grey levels).
    table, surface, ink : float
        Grey levels of the table, the object and the tag's black cells.
    rng : None, int or numpy.random.Generator
        Seed of the noise.

    Returns
    -------
    numpy.ndarray of uint8, shape ``shape``

    Examples
    --------
    >>> square = [(100, 80), (220, 80), (220, 180), (100, 180)]
    >>> image = render_tag_frame(square, (160, 130), 0.3, 48, rng=0)
    >>> image.shape, image.dtype, int(image[5, 5]) < 100 < int(image[85, 105])
    ((240, 320), dtype('uint8'), True)
    """
    rng = np.random.default_rng(rng)
    poly = np.asarray(outline, dtype=float)
    centre = np.asarray(tag_centre, dtype=float)
    h = np.eye(3) if image_from_pixels is None else np.asarray(image_from_pixels, dtype=float)
    back = np.linalg.inv(h)
    cells = marker_cells(tag_id, dictionary)
    n = cells.shape[0]
    rows, cols = shape
    pad = int(np.ceil(4 * blur)) + 3
    seen = _apply(h, poly)
    x0, y0 = np.maximum(np.floor(seen.min(axis=0)).astype(int) - pad, 0)
    x1, y1 = np.minimum(np.ceil(seen.max(axis=0)).astype(int) + pad + 1, (cols, rows))
    grey = np.full(shape, float(table))
    if x1 > x0 and y1 > y0:
        offsets = (np.arange(SAMPLES) + 0.5) / SAMPLES - 0.5
        xs = (np.arange(x0, x1)[:, None] + offsets).ravel()
        ys = (np.arange(y0, y1)[:, None] + offsets).ravel()
        gx, gy = np.meshgrid(xs, ys)
        scene = _apply(back, np.column_stack([gx.ravel(), gy.ravel()]))
        level = np.where(_inside(scene, poly), float(surface), float(table))
        c, s = np.cos(tag_theta), np.sin(tag_theta)
        d = scene - centre  # tag frame: R(-theta) d, with R(theta) = [[c, s], [-s, c]]
        u = (c * d[:, 0] - s * d[:, 1]) / tag_side + 0.5
        v = (s * d[:, 0] + c * d[:, 1]) / tag_side + 0.5
        on_tag = (u >= 0) & (u < 1) & (v >= 0) & (v < 1)
        i = np.clip((v[on_tag] * n).astype(int), 0, n - 1)
        j = np.clip((u[on_tag] * n).astype(int), 0, n - 1)
        level[on_tag] = np.where(cells[i, j], float(surface), float(ink))
        fine = level.reshape(y1 - y0, SAMPLES, x1 - x0, SAMPLES).mean(axis=(1, 3))
        grey[y0:y1, x0:x1] = fine
        if blur:
            b0, b1 = max(y0 - pad, 0), min(y1 + pad, rows)
            a0, a1 = max(x0 - pad, 0), min(x1 + pad, cols)
            grey[b0:b1, a0:a1] = ndimage.gaussian_filter(grey[b0:b1, a0:a1], blur)
    grey += rng.normal(0.0, noise, shape)
    return np.clip(np.rint(grey), 0, 255).astype(np.uint8)
