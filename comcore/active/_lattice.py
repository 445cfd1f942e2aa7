"""The lattice the motion model's terms are computed on when the camera is finer than it.

The model's log-likelihood of a push is a smooth function of the hypothetical CoM
over a few millimetres (the model's error scales are millimetres and a few
degrees), so a camera of 1 mm per pixel need not ask the model about each of its
pixels: :class:`comcore.Likelihood`'s ``model_spacing`` (metres) sets a square
lattice of CoM hypotheses, every ``stride``-th pixel in x and y, and every other
pixel's terms are interpolated bilinearly from the lattice nodes around it that
lie on the object (their weights renormalised: a convex combination, never an
extrapolation). A pixel none of whose four nodes lies on the object is a node
itself. The posterior stays on every pixel: the Voting Theorem's sense term, the
region and the estimate read each pixel as before.

``stride`` is ``floor(model_spacing / resolution)``: 1 (every pixel a node, the
terms computed exactly) for cameras of ``model_spacing`` per pixel or coarser,
which is the resolution every accuracy table was measured at (2.5 mm).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

__all__ = ["Lattice", "lattice_stride", "model_lattice"]


def lattice_stride(spacing_m: float, resolution: float) -> int:
    """Pixels between lattice nodes for a spacing (metres) on a camera of ``resolution``."""
    if spacing_m <= 0:
        return 1
    return max(1, int(np.floor(spacing_m / resolution + 1e-9)))


@dataclass(frozen=True)
class Lattice:
    """Nodes (indices into the posterior's pixels) and the interpolation weights.

    ``weights`` is a sparse (p, n) matrix whose rows sum to 1: pixel ``i``'s term is
    ``weights[i] @ node_terms``.
    """

    nodes: np.ndarray
    weights: sparse.csr_matrix

    def gather_any(self, flags: np.ndarray) -> np.ndarray:
        """Per node: whether any pixel that reads it is flagged; ``flags`` (p, ...) bool."""
        flat = flags.reshape(len(flags), -1).astype(float)
        return (self.weights.T @ flat > 0).reshape(len(self.nodes), *flags.shape[1:])

    def gather_sum(self, values: np.ndarray) -> np.ndarray:
        """Per node: the sum of ``values`` (p, ...) over the pixels it stands for.

        Each pixel's value is shared among the nodes it reads by its weights, so the
        nodes' total is the pixels'.
        """
        flat = values.reshape(len(values), -1)
        return np.asarray(self.weights.T @ flat).reshape(len(self.nodes), *values.shape[1:])

    def spread(self, node_values: np.ndarray, usable: np.ndarray) -> np.ndarray:
        """Per pixel: ``node_values`` (n, ...) interpolated; nodes not ``usable`` count 0.

        A pixel is only as good as its nodes: callers ask the model about every node a
        live pixel reads (:meth:`gather_any`), so a live pixel never reads an unusable one.
        """
        vals = np.where(usable, node_values, 0.0)
        flat = vals.reshape(len(self.nodes), -1)
        n_pix = self.weights.shape[0]
        return np.asarray(self.weights @ flat).reshape(n_pix, *node_values.shape[1:])


def model_lattice(pixels: np.ndarray, stride: int) -> Lattice | None:
    """The lattice of every ``stride``-th pixel of ``pixels`` (p, 2), or None for stride 1.

    ``pixels`` are pixel centres ``(x, y)`` on the integer grid (as
    :func:`comcore.conventions.pixel_centres` gives them), the nodes those whose
    column and row are multiples of ``stride`` counted from the first pixel's.
    Hypotheses off the integer grid (none a session makes) get None: every one asked.
    """
    if stride <= 1 or len(pixels) == 0:
        return None
    offsets = pixels - pixels.min(axis=0)
    if np.abs(offsets - np.rint(offsets)).max() > 1e-9:  # not a pixel grid: every one asked
        return None
    grid = np.rint(offsets).astype(np.intp)  # (p, 2) column, row
    cell = grid // stride
    on_node = (grid % stride == 0).all(axis=1)
    # the index of the pixel on each lattice node, -1 where the node is off the object
    lookup = np.full((int(cell[:, 1].max()) + 2, int(cell[:, 0].max()) + 2), -1, dtype=np.intp)
    lookup[cell[on_node, 1], cell[on_node, 0]] = np.flatnonzero(on_node)
    frac = (grid - cell * stride) / stride  # (p, 2) in [0, 1)
    rows, cols, vals = [], [], []
    for dx, dy in ((0, 0), (1, 0), (0, 1), (1, 1)):
        w = (frac[:, 0] if dx else 1 - frac[:, 0]) * (frac[:, 1] if dy else 1 - frac[:, 1])
        found = lookup[cell[:, 1] + dy, cell[:, 0] + dx]
        use = (found >= 0) & (w > 0)
        rows.append(np.flatnonzero(use))
        cols.append(found[use])
        vals.append(w[use])
    rows, cols, vals = np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)
    total = np.bincount(rows, weights=vals, minlength=len(pixels))
    lonely = np.flatnonzero(total == 0)  # no node of its cell on the object: its own node
    rows = np.concatenate([rows, lonely])
    cols = np.concatenate([cols, lonely])
    vals = np.concatenate([vals / total[rows[: len(vals)]], np.ones(len(lonely))])
    nodes, column = np.unique(cols, return_inverse=True)
    weights = sparse.csr_matrix((vals, (rows, column)), shape=(len(pixels), len(nodes)))
    return Lattice(nodes=nodes, weights=weights)
