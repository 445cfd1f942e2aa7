"""Camera frames of one object on a table as a fixed camera gives them, with the true mask.

One generator for the tests (tests/camera/test_image.py) and the benchmarks
(benchmarks/accuracy/bench_mask_from_image.py, benchmarks/timing/bench_first_observe.py).
A frame is rendered in grey levels:

    image = illumination * (coverage * object + (1 - coverage) * table * cast_shadow) + noise

* ``table``: the table's grey level under unit light, optionally with a
  texture (a smooth random field, std ``texture`` grey levels, fixed per
  table: the reference image has the same one);
* ``object``: a random star-shaped polygon of ``share`` of the frame's area,
  dark on a light table or bright on a dark one, its coverage antialiased
  (4 x 4 samples a pixel) and blurred by the lens (Gaussian, ``blur`` px);
* ``illumination``: a linear ``gradient`` (grey levels of the table from one
  end of the frame to the other, in a random direction), ``vignetting`` (the
  corners that share darker, cos^4 law), a ``frame_shadow`` (one side of the
  frame, a quarter of it, that share darker behind a soft edge: the arm's
  shadow);
* ``cast_shadow``: the object's own shadow on the table, offset to one side
  and blurred, darkening the table by that share;
* ``noise``: sensor noise (Gaussian, grey levels), then clipped and rounded
  to uint8.

The truth is the polygon rasterised at pixel centres
(``comcore.geometry.rasterise_polygon``). The reference image of the empty
table has the same table and lighting but no object, no cast shadow and no
frame shadow (taken with the arm away), fresh noise and an exposure differing
by up to 2 %. Every draw takes a seed or Generator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

import comcore

#: Conditions of the benchmark: keyword arguments of :func:`make_frame`.
CONDITIONS: dict[str, dict] = {
    "even": {},
    "gradient 60": {"gradient": 60.0},
    "gradient 100": {"gradient": 100.0},
    "vignetting": {"vignetting": 0.4},
    "frame shadow": {"frame_shadow": 0.35},
    "cast shadow": {"cast_shadow": 0.3},
    "deep cast shadow": {"cast_shadow": 0.5},
    "textured table": {"texture": 12.0},
    "noisy": {"noise": 10.0},
    "strong texture": {"texture": 25.0},
    "low contrast": {"contrast": 30.0},
    "small object": {"share": 0.0005},
    "large object": {"share": 0.03},
    "cutting mat": {"grid": 40.0},
    "dark cutting mat": {"grid": 70.0},
    "clutter": {"clutter": True},
    "all": dict(gradient=60.0, vignetting=0.3, cast_shadow=0.25, texture=8.0, noise=6.0),
    "empty table": {"empty": True},
    "empty + gradient + texture": {"empty": True, "gradient": 60.0, "texture": 8.0},
}

#: A wide frame: 1280 x 720 pixels (rows, columns).
WIDE = (720, 1280)


@dataclass(frozen=True)
class Frame:
    """A rendered camera frame, the truth and what a user could give besides."""

    image: np.ndarray
    """The frame, uint8 (H, W)."""
    truth: np.ndarray | None
    """The object's pixels (pixel centres inside the polygon), bool (H, W); None: no object."""
    background: np.ndarray
    """The empty table under the same lighting (no frame or cast shadow), uint8 (H, W)."""
    roi: tuple[int, int, int, int]
    """A box around where the object lies, ``(x0, y0, x1, y1)`` (columns x0..x1-1)."""


def star_polygon(rng: np.random.Generator, area: float) -> np.ndarray:
    """A random star-shaped polygon about the origin with about ``area`` px^2, (k, 2)."""
    k = int(rng.integers(5, 10))
    while True:  # no gap over 0.7 pi between vertices: a gap wider than pi pinches the outline
        angles = np.sort(rng.uniform(0, 2 * np.pi, k))
        if np.diff(np.append(angles, angles[0] + 2 * np.pi)).max() < 0.7 * np.pi:
            break
    radii = rng.uniform(0.55, 1.0, k)
    xy = np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])
    x, y = xy[:, 0], xy[:, 1]
    a = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    return xy * np.sqrt(area / a)


def _coverage(vertices: np.ndarray, box: tuple[slice, slice], samples: int = 4) -> np.ndarray:
    """Share of each pixel of ``box`` inside the polygon (samples x samples a pixel)."""
    rows, cols = box
    h, w = rows.stop - rows.start, cols.stop - cols.start
    # sub-pixel j of pixel c is centred at c + (j % samples + 0.5) / samples - 0.5
    fine = (vertices - [cols.start, rows.start] + 0.5) * samples - 0.5
    inside = comcore.geometry.rasterise_polygon(fine, (h * samples, w * samples))
    return inside.reshape(h, samples, w, samples).mean(axis=(1, 3))


def _smooth_field(rng: np.random.Generator, shape, sigma: float) -> np.ndarray:
    """A smooth random field of unit standard deviation."""
    field = ndimage.gaussian_filter(rng.normal(size=shape), sigma)
    return field / field.std()


def _illumination(rng, shape, gradient, table, vignetting) -> np.ndarray:
    """Unit-mean light over the frame: a linear ramp and cos^4 vignetting."""
    h, w = shape
    yy, xx = np.mgrid[0:h, 0:w].astype(float)
    light = np.ones(shape)
    if gradient:
        angle = rng.uniform(0, 2 * np.pi)
        u = np.cos(angle) * xx + np.sin(angle) * yy
        u = (u - u.min()) / (u.max() - u.min())
        light *= 1 + gradient / table * (u - 0.5)
    if vignetting:
        r2 = ((xx - (w - 1) / 2) ** 2 + (yy - (h - 1) / 2) ** 2) / (
            ((w - 1) / 2) ** 2 + ((h - 1) / 2) ** 2
        )
        focal2 = 1 / ((1 - vignetting) ** -0.5 - 1)  # corners (r2 = 1) get 1 - vignetting
        light *= (1 + r2 / focal2) ** -2
    return light


def _frame_shadow(rng, shape, depth) -> np.ndarray:
    """One side of the frame (a quarter of it) ``depth`` darker behind a soft edge."""
    h, w = shape
    side = rng.integers(4)
    length = (w, w, h, h)[side]
    coord = np.arange(length, dtype=float)
    if side in (1, 3):
        coord = coord[::-1]
    soft = 0.03 * length
    profile = 1 - depth / (1 + np.exp((coord - 0.25 * length) / soft))
    return profile[None, :] if side < 2 else profile[:, None]


def _add_clutter(rng, table, share, centre, radius, *, blur, object_level) -> None:
    """Draw another thing of the object's side and size on ``table`` (in place), away from it."""
    h, w = table.shape
    while True:
        other = star_polygon(rng, rng.uniform(1.0, 2.0) * share * h * w)
        reach = np.hypot(other[:, 0], other[:, 1]).max()
        spot = rng.uniform([reach + 3, reach + 3], [w - reach - 3, h - reach - 3])
        if np.hypot(*(spot - centre)) > reach + radius + 0.05 * min(h, w):
            break
    other = other + spot
    cbox = (
        slice(max(int(other[:, 1].min()) - 2, 0), min(int(other[:, 1].max()) + 3, h)),
        slice(max(int(other[:, 0].min()) - 2, 0), min(int(other[:, 0].max()) + 3, w)),
    )
    cover = ndimage.gaussian_filter(_coverage(other, cbox), blur)
    table[cbox] = cover * object_level + (1 - cover) * table[cbox]


def _grey_levels(rng, dark, contrast) -> tuple[float, float]:
    """The table's and the object's grey levels (``dark``: ``None`` draws it, even odds)."""
    if dark is None:
        dark = bool(rng.random() < 0.5)
    table_level = rng.uniform(140, 180) if dark else rng.uniform(60, 100)
    object_level = rng.uniform(20, 60) if dark else rng.uniform(190, 230)
    if contrast is not None:
        object_level = table_level - contrast if dark else table_level + contrast
    return table_level, object_level


def _place_object(rng, shape, share) -> tuple[np.ndarray, np.ndarray, float]:
    """A star polygon of ``share`` of the frame placed with a margin: vertices, centre, radius."""
    h, w = shape
    while True:  # a polygon that fits in the frame with a margin
        poly = star_polygon(rng, share * h * w)
        radius = np.hypot(poly[:, 0], poly[:, 1]).max()
        margin = radius + 0.05 * min(h, w) + 3
        if 2 * margin < min(h, w):
            break
    centre = rng.uniform([margin, margin], [w - margin, h - margin])
    return poly + centre, centre, radius


def _grid_lines(rng, shape, grid) -> np.ndarray:
    """``grid`` grey levels on 2 px lines 64 px apart at a drawn offset, else 0."""
    h, w = shape
    ys, xs = np.ogrid[0:h, 0:w]
    ox, oy = rng.uniform(0, 64, 2)
    lines = ((xs - ox) % 64 < 2) | ((ys - oy) % 64 < 2)
    return grid * lines


def _cast_shade(rng, shape, poly, radius, corners, depth) -> np.ndarray:
    """The object's soft shadow, offset a quarter radius a drawn way: a factor per pixel.

    ``corners`` are ``(x0, y0, x1, y1)`` of the object's padded box (pixels).
    """
    h, w = shape
    x0, y0, x1, y1 = corners
    shade = np.ones(shape)
    offset = 0.25 * radius * np.array([np.cos(a := rng.uniform(0, 2 * np.pi)), np.sin(a)])
    grow = int(np.ceil(radius * 0.6))
    sbox = (
        slice(max(y0 - grow, 0), min(y1 + grow, h)),
        slice(max(x0 - grow, 0), min(x1 + grow, w)),
    )
    silhouette = _coverage(poly + offset, sbox, samples=1)
    shade[sbox] = 1 - depth * ndimage.gaussian_filter(silhouette, 0.12 * radius)
    return shade


def _work_area(rng, shape, centre, radius, truth) -> tuple[int, int, int, int]:
    """The box a user draws around the work area: about the object, jittered, holding it."""
    h, w = shape
    half = max(2.5 * radius, 80.0)
    jitter = rng.uniform(-0.3, 0.3, 2) * half
    cx, cy = centre + jitter
    roi = (
        int(max(cx - half, 0)), int(max(cy - half, 0)),
        int(min(cx + half, w)), int(min(cy + half, h)),
    )
    if truth is not None:  # the box holds the whole object (a user draws it around the work area)
        rows, cols = np.nonzero(truth)
        roi = (min(roi[0], cols.min() - 4), min(roi[1], rows.min() - 4),
               max(roi[2], cols.max() + 5), max(roi[3], rows.max() + 5))
    return roi


def make_frame(
    rng=None,
    *,
    shape: tuple[int, int] = WIDE,
    share: float = 0.002,
    dark: bool | None = None,
    gradient: float = 0.0,
    vignetting: float = 0.0,
    frame_shadow: float = 0.0,
    cast_shadow: float = 0.0,
    texture: float = 0.0,
    noise: float = 3.0,
    blur: float = 0.8,
    contrast: float | None = None,
    grid: float = 0.0,
    clutter: bool = False,
    empty: bool = False,
) -> Frame:
    """Render one frame (see the module's docstring for the model).

    ``share``: the object's share of the frame's area; ``dark``: a dark object
    on a light table (``None``: drawn, even odds); ``contrast``: the object's
    difference from the table in grey levels (default: drawn, 80 to 170);
    ``grid``: dark grid lines on the table (a cutting mat: 2 px wide, 64 px
    apart, that many grey levels); ``clutter``: another thing of the
    object's side and size fixed on the table elsewhere (in the reference
    image too).
    """
    rng = np.random.default_rng(rng)
    h, w = shape
    table_level, object_level = _grey_levels(rng, dark, contrast)
    table = np.full(shape, table_level)
    if texture:
        table += texture * (
            0.7 * _smooth_field(rng, shape, 1.5) + 0.3 * _smooth_field(rng, shape, 12)
        )
    light = _illumination(rng, shape, gradient, table_level, vignetting)
    poly, centre, radius = _place_object(rng, shape, share)
    if grid:
        table = table - _grid_lines(rng, shape, grid)
    if clutter:  # as big as the object, elsewhere, and part of the scene
        _add_clutter(rng, table, share, centre, radius, blur=blur, object_level=object_level)
    pad = int(np.ceil(3 * blur)) + 2
    x0, y0 = np.floor(poly.min(axis=0)).astype(int) - pad
    x1, y1 = np.ceil(poly.max(axis=0)).astype(int) + pad + 1
    box = (slice(max(y0, 0), min(y1, h)), slice(max(x0, 0), min(x1, w)))
    coverage = np.zeros(shape)
    truth = None
    if not empty:
        coverage[box] = ndimage.gaussian_filter(_coverage(poly, box), blur)
        truth = comcore.geometry.rasterise_polygon(poly, shape)
    shade = np.ones(shape)
    if cast_shadow and not empty:
        shade = _cast_shade(rng, shape, poly, radius, (x0, y0, x1, y1), cast_shadow)
    side_shade = _frame_shadow(rng, shape, frame_shadow) if frame_shadow else 1.0

    def shot(with_object: bool, gain: float) -> np.ndarray:
        cov = coverage if with_object else 0.0
        sh = shade if with_object else 1.0
        grey = gain * light * (cov * object_level + (1 - cov) * table * sh)
        if with_object:
            grey = grey * side_shade
        grey = grey + rng.normal(0.0, noise, shape)
        return np.clip(np.rint(grey), 0, 255).astype(np.uint8)

    image = shot(True, 1.0)
    background = shot(False, rng.uniform(0.98, 1.02))
    return Frame(image, truth, background, _work_area(rng, shape, centre, radius, truth))


def iou(found: np.ndarray, truth: np.ndarray) -> float:
    """Intersection over union of two bool images."""
    union = np.logical_or(found, truth).sum()
    return float(np.logical_and(found, truth).sum() / union) if union else 1.0
