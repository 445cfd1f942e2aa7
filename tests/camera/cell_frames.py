"""Frames of a robot cell's table, for ``mask_from_image``'s tests and benchmark.

A tilted pinhole camera (20 to 35 degrees from straight down) looks at a
wood-grain table (sinusoids bent by a slow sinusoid, plus fine noise; any
direction, period 6 to 25 mm, amplitude 15 to 35 grey levels) under a lamp's
gradient; on it one object (a random star-shaped polygon, a rectangle, a long
bar or a near-disc, 2.5 to 6 cm across its half), a soft shadow (a blurred
polygon 15 to 30 % darker beside it, on any side), the arm (a bar entering
from the frame's edge at up to 35 degrees from the object's direction,
stopping short of it), optionally a second object, and Gaussian noise. Everything is drawn on the table in metres and projected
through the camera, so the object's scale changes across the frame. The
empty-table frame has the same table and light, fresh noise, and neither the
objects, the arm nor the shadow.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from comcore.geometry import rasterise_polygon

WIDE = (720, 1280)
CONDITIONS = ("cell", "low contrast", "two objects")


@dataclass(frozen=True)
class CellFrame:
    """A cell's camera frame and what a user could give besides."""

    image: np.ndarray
    """The frame, uint8 (H, W)."""
    truth: np.ndarray
    """The object's pixels (pixel centres inside it), bool (H, W)."""
    background: np.ndarray
    """The empty table, same camera and light, uint8 (H, W)."""
    box: tuple[int, int, int, int]
    """A box around the object ``(x0, y0, x1, y1)``, off the arm."""
    point: tuple[float, float]
    """A pixel ``(x, y)`` on the object."""
    contrast: float
    """The object's albedo less the table's mean, grey levels."""
    shadow: np.ndarray
    """The shadow's pixels off the object (at least 3 % darker), bool (H, W)."""


def _camera(rng, shape):
    """Table metres -> pixels (3 x 3) of a camera tilted 20 to 35 degrees, 0.8 to 1 m away."""
    h, w = shape
    f = 1.1 * w
    k = np.array([[f, 0, (w - 1) / 2], [0, f, (h - 1) / 2], [0, 0, 1]])
    a, yaw = np.radians(rng.uniform(20, 35)), rng.uniform(-0.3, 0.3)
    down = np.diag([1.0, -1.0, -1.0])
    tilt = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    turn = np.array([[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]])
    r = tilt @ down @ turn
    centre = -rng.uniform(0.8, 1.0) * r.T @ np.array([0, 0, 1.0])
    hom = k @ np.column_stack([r[:, 0], r[:, 1], -r @ centre])
    return hom / hom[2, 2]


def _project(hom, points):
    p = np.column_stack([points, np.ones(len(points))]) @ hom.T
    return p[:, :2] / p[:, 2:]


def _star(rng, radius):
    k = int(rng.integers(5, 9))
    angles = np.sort(rng.uniform(0, 2 * np.pi, k))
    while np.diff(np.append(angles, angles[0] + 2 * np.pi)).max() >= 0.7 * np.pi:
        angles = np.sort(rng.uniform(0, 2 * np.pi, k))
    radii = radius * rng.uniform(0.6, 1.0, k)
    return np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])


def _shape(rng, radius):
    """An outline about ``radius`` in size: a star, a rectangle, a bar or a near-disc."""
    kind = int(rng.integers(4))
    if kind == 0:
        return _star(rng, radius)
    if kind == 3:
        t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
        return radius * np.column_stack([np.cos(t), rng.uniform(0.8, 1.0) * np.sin(t)])
    long, short = radius, radius * (rng.uniform(0.5, 0.9) if kind == 1 else rng.uniform(0.2, 0.35))
    turn = rng.uniform(0, np.pi)
    rot = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    return np.array([[-long, -short], [long, -short], [long, short], [-long, short]]) @ rot.T


def _coverage(vertices, shape, samples=3):
    """Share of each pixel inside the polygon (pixel vertices), over its bounding box only."""
    lo = np.maximum(np.floor(vertices.min(axis=0)).astype(int) - 2, 0)
    hi = np.minimum(np.ceil(vertices.max(axis=0)).astype(int) + 3, [shape[1], shape[0]])
    out = np.zeros(shape)
    if np.any(hi <= lo):
        return out
    h, w = hi[1] - lo[1], hi[0] - lo[0]
    fine = (vertices - lo + 0.5) * samples - 0.5
    inside = rasterise_polygon(fine, (h * samples, w * samples))
    out[lo[1] : hi[1], lo[0] : hi[0]] = inside.reshape(h, samples, w, samples).mean(axis=(1, 3))
    return out


def _table(rng, hom, shape):
    """The wood grain's albedo at each pixel, and the lamp's light."""
    h, w = shape
    rows, cols = np.mgrid[0:h, 0:w].astype(float)
    inv = np.linalg.inv(hom)
    p = np.stack([cols, rows, np.ones_like(cols)], axis=-1) @ inv.T
    x, y = p[..., 0] / p[..., 2], p[..., 1] / p[..., 2]
    turn = rng.uniform(0, np.pi)
    u, v = np.cos(turn) * x + np.sin(turn) * y, -np.sin(turn) * x + np.cos(turn) * y
    period = rng.uniform(0.006, 0.025)
    bend = 0.3 * np.sin(2 * np.pi * u / rng.uniform(0.1, 0.3) + rng.uniform(0, 6.3))
    grain = np.sin(2 * np.pi * (v / period + bend)) + 0.4 * np.sin(2 * np.pi * (v / period * 2.7))
    albedo = rng.uniform(130, 170) + rng.uniform(15, 35) * grain / 1.4 + 4 * ndimage.gaussian_filter(
        rng.normal(size=shape), 1.5
    )
    angle = rng.uniform(0, 2 * np.pi)
    ramp = np.cos(angle) * cols + np.sin(angle) * rows
    light = 1 + rng.uniform(0.2, 0.35) * ((ramp - ramp.min()) / np.ptp(ramp) - 0.5)
    return albedo, light


def make_cell_frame(rng, condition="cell", shape=WIDE) -> CellFrame:
    """A frame of ``condition`` (one of :data:`CONDITIONS`), drawn from ``rng``."""
    hom = _camera(rng, shape)
    albedo, light = _table(rng, hom, shape)
    h, w = shape
    inv = np.linalg.inv(hom)
    corners = _project(inv, np.array([[0.3 * w, 0.3 * h], [0.7 * w, 0.7 * h]]))
    where = corners[0] + rng.uniform(0, 1, 2) * (corners[1] - corners[0])
    outline = _project(hom, where + _shape(rng, rng.uniform(0.025, 0.06)))
    table_mean = float(np.mean(albedo))
    if condition == "low contrast":
        contrast = float(rng.choice([-1, 1]) * rng.uniform(12, 18))
    else:
        contrast = float(rng.choice([-1, 1]) * rng.uniform(70, 100))
    cover = _coverage(outline, shape)
    seen = albedo * (1 - cover) + (table_mean + contrast) * cover
    centre = outline.mean(axis=0)
    size = np.ptp(outline, axis=0).max()
    # a soft shadow beside the object, on the side away from the lamp
    shade = _coverage(outline + rng.uniform(0.15, 0.3) * size * rng.normal(size=2), shape)
    shade = ndimage.gaussian_filter(np.maximum(shade - cover, 0), rng.uniform(4, 8))
    shade_factor = 1 - rng.uniform(0.15, 0.28) * shade
    # the arm: a bar from the frame's edge towards the object, stopping short of it
    side = int(rng.integers(4))
    edge = [(centre[0], -50), (w + 50, centre[1]), (centre[0], h + 50), (-50, centre[1])][side]
    along = (1, 0) if side in (0, 2) else (0, 1)  # slide along the edge, never off it
    edge = np.array(edge) + rng.uniform(-0.15, 0.15) * np.array(along) * (w, h)
    towards = centre - edge
    swing = rng.uniform(-0.6, 0.6)  # the arm comes in at an angle, its tip still near the object
    towards = np.array([[np.cos(swing), -np.sin(swing)], [np.sin(swing), np.cos(swing)]]) @ towards
    length = np.hypot(*towards)
    edge = centre - towards * (2 * max(w, h) / length)  # from well outside the frame
    reach = np.hypot(*(outline - centre).T).max()
    tip = centre - towards * ((reach + rng.uniform(40, 80)) / length)
    normal = np.array([-towards[1], towards[0]]) / length * rng.uniform(30, 50)
    arm = np.array([edge + normal, tip + normal * 0.7, tip - normal * 0.7, edge - normal])
    arm_cover = _coverage(arm, shape)
    arm_grey = rng.uniform(50, 110) + 20 * np.linspace(-1, 1, w)[None, :] * arm_cover
    seen = seen * (1 - arm_cover) + arm_grey * arm_cover
    if condition == "two objects":
        for _ in range(50):  # a place off the arm, the object and its shadow, in the frame
            turn = rng.uniform(0, 2 * np.pi)
            shift = rng.uniform(2.0, 3.0) * size * np.array([np.cos(turn), np.sin(turn)])
            second = outline - centre + np.clip(centre + shift, size, (w - size, h - size))
            cover2 = _coverage(second, shape)
            grown = ndimage.binary_dilation(cover2 > 0, iterations=20)
            if not (grown & ((arm_cover > 0) | (cover > 0) | (shade > 0.05))).any():
                break
        seen = seen * (1 - cover2) + (table_mean + contrast) * cover2
    noise = rng.uniform(2.0, 4.0)
    image = np.clip(np.rint(seen * light * shade_factor + rng.normal(0, noise, shape)), 0, 255)
    background = np.clip(np.rint(albedo * light + rng.normal(0, noise, shape)), 0, 255)
    truth = rasterise_polygon(outline, shape)
    rows, cols = np.nonzero(truth)
    pad = int(rng.integers(30, 50))
    box = (int(max(cols.min() - pad, 0)), int(max(rows.min() - pad, 0)),
           int(min(cols.max() + pad + 1, w)), int(min(rows.max() + pad + 1, h)))  # fmt: skip
    inner = ndimage.distance_transform_edt(truth)
    r, c = np.unravel_index(int(np.argmax(inner)), shape)
    shadow = (shade_factor < 0.97) & ~truth
    return CellFrame(image.astype(np.uint8), truth, background.astype(np.uint8), box,
                     (float(c), float(r)), contrast, shadow)  # fmt: skip


def iou(found: np.ndarray, truth: np.ndarray) -> float:
    """Intersection over union of two bool images."""
    union = np.logical_or(found, truth).sum()
    return float(np.logical_and(found, truth).sum() / union) if union else 1.0
