"""Contact geometry of a round pusher and a polygonal outline, batched in numpy."""

from __future__ import annotations

import numpy as np

from comcore.conventions import rotate_components

__all__ = [
    "closest_points",
    "exp_translation",
    "first_contacts",
    "inside",
    "perp",
    "rotation",
    "signed_area",
    "to_world",
]


def rotation(angle):
    """Cosines and sines of angles."""
    return np.cos(angle), np.sin(angle)


def perp(v):
    """``J v``: turn 2-vectors a quarter turn counter-clockwise (``y`` up)."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def closest_points(outline: np.ndarray, points: np.ndarray, with_vertex: bool = False):
    """Closest point of a closed outline (E, 2) to each of ``points`` (m, 2), and distances.

    With ``with_vertex``, also whether each closest point is a vertex of the outline.
    """
    a = outline[None, :, :]
    ab = np.roll(outline, -1, axis=0)[None, :, :] - a
    rel = points[:, None, :] - a
    t = np.clip(np.einsum("mek,mek->me", rel, ab) / np.einsum("mek,mek->me", ab, ab), 0.0, 1.0)
    q = a + t[..., None] * ab
    d = np.hypot(q[..., 0] - points[:, None, 0], q[..., 1] - points[:, None, 1])
    i = np.argmin(d, axis=1)
    rows = np.arange(len(points))
    if with_vertex:
        t_best = t[rows, i]
        return q[rows, i], d[rows, i], (t_best <= 0.0) | (t_best >= 1.0)
    return q[rows, i], d[rows, i]


def inside(outline: np.ndarray, points: np.ndarray) -> np.ndarray:
    a, b = outline[None, :, :], np.roll(outline, -1, axis=0)[None, :, :]
    py, px = points[:, None, 1], points[:, None, 0]
    crosses = (a[..., 1] > py) != (b[..., 1] > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_at = a[..., 0] + (py - a[..., 1]) * (b[..., 0] - a[..., 0]) / (b[..., 1] - a[..., 1])
    return (np.count_nonzero(crosses & (x_at > px), axis=1) % 2).astype(bool)


def first_contacts(outline, starts, directions, lengths, radius):
    """Distance along each straight path at which a disc first touches the outline.

    Exact: the disc's centre meets the outline dilated by ``radius`` (edges
    offset outwards and discs at the vertices). The outline is counter-clockwise.

    Returns
    -------
    numpy.ndarray, shape (n,)
        Distance from the start; ``inf`` if the disc does not touch the outline
        within ``lengths``; ``-1`` if it already overlaps it at the start.
    """
    s, d = np.asarray(starts, float), np.asarray(directions, float)
    a = outline[None]
    ab = np.roll(outline, -1, axis=0)[None] - a
    seg = np.hypot(ab[..., 0], ab[..., 1])
    a_off = a + radius * np.stack([ab[..., 1], -ab[..., 0]], axis=-1) / seg[..., None]
    denom = d[:, None, 0] * ab[..., 1] - d[:, None, 1] * ab[..., 0]
    rel = a_off - s[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        t_edge = (rel[..., 0] * ab[..., 1] - rel[..., 1] * ab[..., 0]) / denom
        u_edge = (rel[..., 0] * d[:, None, 1] - rel[..., 1] * d[:, None, 0]) / denom
    ok = (np.abs(denom) > 1e-15) & (u_edge >= 0) & (u_edge <= 1) & (t_edge >= 0)
    rel = s[:, None] - a
    bq = np.einsum("mek,mk->me", rel, d)
    disc = bq**2 - (np.einsum("mek,mek->me", rel, rel) - radius**2)
    t_vert = -bq - np.sqrt(np.maximum(disc, 0.0))
    t_vert = np.where((disc >= 0) & (t_vert >= 0), t_vert, np.inf)
    t = np.minimum(np.where(ok, t_edge, np.inf).min(axis=1), t_vert.min(axis=1))
    t = np.where(t <= lengths, t, np.inf)
    _, dist = closest_points(outline, s)
    return np.where((dist <= radius) | inside(outline, s), -1.0, t)


def to_world(v, c, s):
    """Body-frame vectors (m, 2) to world, for angles with cosines ``c`` and sines ``s`` (m, 1)."""
    return np.column_stack(rotate_components(v[:, 0], v[:, 1], c[:, 0], s[:, 0], inverse=True))


def exp_translation(xi):
    """Translation of the CoM for body-frame twists ``(vx, vy, omega)`` applied for unit time."""
    w = xi[:, 2]
    small = np.abs(w) < 1e-9
    ws = np.where(small, 1.0, w)
    a = np.where(small, 1.0 - w * w / 6.0, np.sin(ws) / ws)
    b = np.where(small, w / 2.0, (1.0 - np.cos(ws)) / ws)
    return np.column_stack([a * xi[:, 0] - b * xi[:, 1], b * xi[:, 0] + a * xi[:, 1]])


def signed_area(v) -> float:
    v = np.asarray(v, float)
    return 0.5 * float(
        np.dot(v[:, 0], np.roll(v[:, 1], -1)) - np.dot(np.roll(v[:, 0], -1), v[:, 1])
    )
