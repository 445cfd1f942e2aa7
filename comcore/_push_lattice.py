"""CoM lattices aligned with a push: where :class:`LimitSurfaceModel` integrates, and interpolates.

A push's motion is a smooth function of the CoM hypothesis except across the
push's line, where the rotation changes sense: a CoM just beside the line
balances on an unstable equilibrium and turns fast over a 3 cm push. So the
nodes lie on lines parallel to the push, close together near the push line
(``NEAR_LINE_SPACING_M``, growing by ``SPACING_GROWTH`` per unit of lever
arm) and ``spacing`` apart far from it and along it: spacings in metres, so
a finer camera does not multiply the nodes. The pressure at a node is
interpolated bilinearly from a table of the pressure spread on a square grid
over the image (``PRESSURE_GRID_M``), computed once per mask.
"""

from __future__ import annotations

import weakref
from collections import OrderedDict

import numpy as np

from ._mask import Mask
from ._neighbourhood import LocalArrays, Window, margin_px

__all__ = ["MAX_LATTICE_NODES", "PushLattice", "expect_frictions", "pressure_table", "remembered"]

#: Node spacing (metres) on the push line, and its growth per unit of lever arm.
NEAR_LINE_SPACING_M, SPACING_GROWTH = 0.0025, 0.5
#: Spacing (metres) of the per-mask table the nodes' pressures are interpolated from.
PRESSURE_GRID_M = 0.005
#: Pushes whose node motions are remembered per mask and model, and friction values.
CACHED_PUSHES, MAX_REMEMBERED_MUS = 4, 12
#: Most nodes of one push's lattice. A node holds a motion per pressure spread and friction
#: value remembered (up to 24 x 24 bytes) besides its position: a million nodes is about
#: 0.6 GB. A push on a wide camera frame at 1 mm per pixel needs about 25,000; the bound is
#: reached only when the spacing in pixels is wrong (a resolution typed in millimetres).
MAX_LATTICE_NODES = 1_000_000

_TABLES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
_MEMOS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def lever_nodes(spacing: float, near: float, reach: float) -> np.ndarray:
    """Node offsets across the push line, sorted, symmetric, covering ``+-reach``.

    ``near`` apart at the line, growing by ``SPACING_GROWTH`` per unit of
    offset up to ``spacing`` (all in the same unit).
    """
    out = [0.0]
    while out[-1] < reach:
        out.append(out[-1] + min(spacing, near + SPACING_GROWTH * out[-1]))
    half = np.array(out)
    return np.concatenate([-half[:0:-1], half])


def lever_count(spacing: float, near: float, reach: float) -> int:
    """About how many nodes :func:`lever_nodes` returns (within a few), without making them."""
    x, n = 0.0, 0
    while x < reach and near + SPACING_GROWTH * x < spacing:  # the growing steps: a few dozen
        x += near + SPACING_GROWTH * x
        n += 1
    n += max(0, int(np.ceil((reach - x) / spacing)))
    return 2 * n + 1


class PushLattice:
    """Nodes on lines parallel to one push, over the whole image.

    Node ``(i, j)`` lies at ``start + along[i] * u + lever[j] * w``, ``u`` the
    push direction and ``w`` its perpendicular; ``points`` (n_i * n_j, 2) in
    that order.

    Raises
    ------
    ValueError
        If the lattice would hold more than :data:`MAX_LATTICE_NODES` nodes
        (a node spacing far below a pixel: a resolution or spacing in the wrong
        unit), naming the push and the numbers.
    """

    def __init__(self, mask: Mask, action: np.ndarray, spacing_m: float):
        self.start = np.asarray(action[:2], dtype=float)
        d = np.asarray(action[2:], dtype=float) - self.start
        self.u = d / np.hypot(d[0], d[1])
        self.w = np.array([-self.u[1], self.u[0]])
        h, w = mask.shape
        corners = np.array([[-1, -1], [w, -1], [-1, h], [w, h]], dtype=float) - self.start
        a, b = corners @ self.u, corners @ self.w
        spacing = self.spacing = max(float(spacing_m) / mask.resolution, 1e-3)
        near = min(NEAR_LINE_SPACING_M / mask.resolution, spacing)
        first, last = np.floor(a.min() / spacing), np.ceil(a.max() / spacing)
        reach = float(np.abs(b).max()) + spacing
        n_nodes = (last - first + 1) * lever_count(spacing, near, reach)
        if n_nodes > MAX_LATTICE_NODES:
            raise ValueError(
                f"the push {np.round(np.asarray(action, float), 3).tolist()} needs a lattice of "
                f"{n_nodes:.3g} nodes (node spacing {spacing:.3g} px = {spacing_m:g} m at "
                f"{mask.resolution:g} m per pixel over a {w} x {h} px image), over the bound "
                f"of {MAX_LATTICE_NODES:,}: is the mask's resolution in metres per pixel?"
            )
        self.along = spacing * np.arange(first, last + 1)
        self.lever = lever_nodes(spacing, near, reach)
        grid_a, grid_b = np.meshgrid(self.along, self.lever, indexing="ij")
        self.points = (
            self.start + grid_a.reshape(-1, 1) * self.u + grid_b.reshape(-1, 1) * self.w
        )  # fmt: skip

    def cells(self, points: np.ndarray):
        """:meth:`locate` and the sorted distinct nodes used, remembered for the last points.

        An estimator asks about the same hypotheses for several friction values
        and models in turn.
        """
        last = getattr(self, "_last", None)
        if last is None or not np.array_equal(last[0], points):
            corners, weights = self.locate(points)
            used = np.zeros(len(self.points), dtype=bool)
            used[corners.ravel()] = True
            last = self._last = (points.copy(), (corners, weights, np.flatnonzero(used)))
        return last[1]

    def locate(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Corner nodes (4, n) and bilinear weights (4, n) of each point's cell."""
        rel = points - self.start
        a, b = rel @ self.u, rel @ self.w
        n_i, n_j = len(self.along), len(self.lever)
        fi = np.clip((a - self.along[0]) / self.spacing, 0.0, n_i - 1 - 1e-9)
        i = np.floor(fi).astype(np.intp)
        j = np.clip(np.searchsorted(self.lever, b, side="right") - 1, 0, n_j - 2)
        fa = fi - i
        fb = np.clip((b - self.lever[j]) / (self.lever[j + 1] - self.lever[j]), 0.0, 1.0)
        nodes = np.stack([i * n_j + j, i * n_j + j + 1, (i + 1) * n_j + j, (i + 1) * n_j + j + 1])
        weights = np.stack([(1 - fa) * (1 - fb), (1 - fa) * fb, fa * (1 - fb), fa * fb])
        return nodes, weights


def pressure_table(mask: Mask, key, compute) -> LocalArrays:
    """``compute(mask, points)`` (n, N) on the square grid ``PRESSURE_GRID_M`` apart, cached.

    The grid's node ``(i, j)`` lies at pixel ``(x, y) = step * (i, j)``, over
    the whole image; its pressures are computed where they are asked about
    (:func:`table_pressures`): on the object's neighbourhood first (the CoM
    hypotheses lie on the object), grown when a point needs a node outside it
    (:class:`comcore._neighbourhood.LocalArrays`). A node's pressures do not
    depend on which other nodes are computed with it.

    Returns the table for :func:`table_pressures`.
    """
    tables = _TABLES.setdefault(mask, {})
    if key not in tables:
        h, w = mask.shape
        g = _table_step(mask)
        ni, nj = int(np.ceil((w - 1) / g)) + 2, int(np.ceil((h - 1) / g)) + 2
        box = mask._box  # rows, columns of the object
        lo = (int(np.floor(box.lo[1] / g)), int(np.floor(box.lo[0] / g)))
        hi = (int(np.ceil((box.hi[1] - 1) / g)) + 2, int(np.ceil((box.hi[0] - 1) / g)) + 2)
        margin = int(np.ceil(margin_px(mask.resolution) / g))
        ref = weakref.ref(mask)  # the cache must not keep its key alive

        def make(win):
            ii, jj = np.meshgrid(
                np.arange(win.lo[0], win.hi[0]), np.arange(win.lo[1], win.hi[1]), indexing="ij"
            )
            points = g * np.column_stack([ii.ravel(), jj.ravel()]).astype(float)
            return (compute(ref(), points).reshape((*ii.shape, -1)),)

        tables[key] = LocalArrays(Window.box((ni, nj), lo, hi, margin), make, margin=margin)
    return tables[key]


def _table_step(mask: Mask) -> float:
    """Spacing (pixels) of a mask's pressure table: ``PRESSURE_GRID_M``, at least 1 px."""
    return max(PRESSURE_GRID_M / mask.resolution, 1.0)


def table_pressures(table: LocalArrays, points: np.ndarray, step: float) -> np.ndarray:
    """Pressures at points, bilinear in the table of :func:`pressure_table`, (n, N)."""
    cell = np.clip(points / step, 0.0, np.array(table.window.shape) - 1 - 1e-9)
    lo = np.floor(cell).astype(np.intp)
    f = cell - lo
    i, j = lo[:, 0], lo[:, 1]
    (values,), origin = table.local(np.concatenate([i, i + 1]), np.concatenate([j, j + 1]))
    i, j = i - origin[0], j - origin[1]
    fx, fy = f[:, :1], f[:, 1:]
    return (
        values[i, j] * (1 - fx) * (1 - fy) + values[i, j + 1] * (1 - fx) * fy
        + values[i + 1, j] * fx * (1 - fy) + values[i + 1, j + 1] * fx * fy
    )  # fmt: skip


def _memo(mask: Mask) -> dict:
    return _MEMOS.setdefault(mask, {"push": None, "mus": [], "before": [], "pushes": OrderedDict()})


def expect_frictions(mask: Mask, mus) -> None:
    """Say which friction values the first push on ``mask`` will be asked about.

    Later pushes expect the values asked about for the push before them
    (:func:`remembered`); the first has none before it, so without this hint
    it is integrated once per friction value instead of in one batch. A hint
    after the first push changes nothing.
    """
    memo = _memo(mask)
    if memo["push"] is None and not memo["before"]:
        memo["before"] = [float(m) for m in mus][:MAX_REMEMBERED_MUS]


def remembered(mask: Mask, key, make_lattice, mu: float, spreads=("",)):
    """The remembered lattice and node motions of one push (``key``), and the frictions to batch.

    Returns ``(lattice, per_mu, mus)``: the push's lattice (``make_lattice()``
    the first time), a dict from ``(spread, friction)`` to a NaN-initialised
    array of node motions, shape (n_nodes, 3), for every pressure spread in
    ``spreads``, and the friction values to integrate together: ``mu`` and
    those asked about for the push before (an estimator asks about the same
    ones for every push; at most ``MAX_REMEMBERED_MUS``).
    """
    memo = _memo(mask)
    pushes = memo["pushes"]
    if key not in pushes:
        if len(pushes) >= CACHED_PUSHES:
            pushes.popitem(last=False)
        pushes[key] = (make_lattice(), {})
    if key != memo["push"]:  # a new push: expect the friction values of the one before
        memo["push"], memo["before"], memo["mus"] = key, memo["mus"] or memo["before"], []
    if mu not in memo["mus"]:
        memo["mus"].append(mu)
    expected = [m for m in memo["before"] if m not in memo["mus"]]
    mus = [mu, *(m for m in [*memo["mus"], *expected] if m != mu)][:MAX_REMEMBERED_MUS]
    lattice, per_mu = pushes[key]
    for spread in spreads:
        for m in mus:
            per_mu.setdefault((spread, m), np.full((len(lattice.points), 3), np.nan))
    return lattice, per_mu, mus
