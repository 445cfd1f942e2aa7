"""CoM lattices aligned with a push: where :class:`LimitSurfaceModel` integrates, and interpolates.

A push's motion is a smooth function of the CoM hypothesis except across the
push's line, where the rotation changes sense: a CoM just beside the line
balances on an unstable equilibrium and turns fast over a 3 cm push. So the
nodes lie on lines parallel to the push, close together near the push line
(``NEAR_LINE_SPACING_M``, growing by ``SPACING_GROWTH`` per unit of lever
arm) and ``spacing`` apart far from it and along it: spacings in metres, so
a finer camera does not multiply the nodes. The pressure at a node is
interpolated bilinearly from a table of the pressure spread on a square grid
over the image (``PRESSURE_GRID_M``), kept per mask and computed where it is
asked about: the object's neighbourhood (:mod:`comcore._neighbourhood`).
"""

from __future__ import annotations

import weakref
from collections import OrderedDict

import numpy as np

from .._mask import Mask
from .._neighbourhood import LocalArrays, Window, margin_px

__all__ = [
    "MAX_LATTICE_NODES",
    "PushLattice",
    "expect_frictions",
    "pressure_table",
    "remembered",
    "widened",
]

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
    """Nodes on lines parallel to one push, over the whole image or the part of it in a box.

    Node ``(i, j)`` lies at ``start + along[i] * u + lever[j] * w``, ``u`` the
    push direction and ``w`` its perpendicular; ``points`` (n_i * n_j, 2) in
    that order. With ``box`` (a :class:`comcore._neighbourhood.Window` of the
    image: the object's neighbourhood) only the whole image's nodes whose
    cells reach into the box are made, at the same positions; a point whose
    cell is not among them is not located (:meth:`cells` returns None) and
    :meth:`whole_ids` maps the nodes to those of the whole image's lattice.

    Raises
    ------
    ValueError
        If the whole image's lattice would hold more than
        :data:`MAX_LATTICE_NODES` nodes (a node spacing far below a pixel: a
        resolution or spacing in the wrong unit), naming the push and the numbers.
    """

    def __init__(self, mask: Mask, action: np.ndarray, spacing_m: float, box: Window | None = None):
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
        along = spacing * np.arange(first, last + 1)
        lever = lever_nodes(spacing, near, reach)
        self._whole = (along[0], len(along), lever)  # what locates a point in the whole lattice
        i0, i1, j0, j1 = 0, len(along), 0, len(lever)
        if box is not None:  # the nodes of the cells over the box (one more each side)
            (r0, c0), (r1, c1) = box.lo, box.hi
            inner = np.array([[c0 - 1, r0 - 1], [c1, r0 - 1], [c0 - 1, r1], [c1, r1]], float)
            a, b = (inner - self.start) @ self.u, (inner - self.start) @ self.w
            i0 = max(int(np.floor((a.min() - along[0]) / spacing)) - 1, 0)
            i1 = min(int(np.ceil((a.max() - along[0]) / spacing)) + 2, len(along))
            j0 = max(int(np.searchsorted(lever, b.min(), side="right")) - 2, 0)
            j1 = min(int(np.searchsorted(lever, b.max(), side="left")) + 2, len(lever))
        self._offset = (i0, j0)
        self.along, self.lever = along[i0:i1], lever[j0:j1]
        grid_a, grid_b = np.meshgrid(self.along, self.lever, indexing="ij")
        self.points = self.start + grid_a.reshape(-1, 1) * self.u + grid_b.reshape(-1, 1) * self.w

    def whole_ids(self) -> np.ndarray:
        """Each node's index in the whole image's lattice of the same push, (n_nodes,)."""
        n_j = len(self._whole[2])
        i = np.arange(len(self.along)) + self._offset[0]
        j = np.arange(len(self.lever)) + self._offset[1]
        return (i[:, None] * n_j + j[None, :]).ravel()

    def cells(self, points: np.ndarray):
        """:meth:`locate` and the sorted distinct nodes used, remembered for the last points.

        None when a point's cell is not in this lattice (one on a box: the
        point is off the box). An estimator asks about the same hypotheses for
        several friction values and models in turn.
        """
        last = getattr(self, "_last", None)
        if last is None or not np.array_equal(last[0], points):
            corners, weights, inside = self.locate(points)
            found = None
            if inside.all():
                used = np.zeros(len(self.points), dtype=bool)
                used[corners.ravel()] = True
                found = (corners, weights, np.flatnonzero(used))
            last = self._last = (points.copy(), found)
        return last[1]

    def locate(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Corner nodes (4, n), bilinear weights (4, n) of each point's cell, and if it is here.

        The cell and weights are the whole image's lattice's (a point beyond
        it is clamped to its edge cell), the nodes this lattice's numbers.
        """
        rel = points - self.start
        a, b = rel @ self.u, rel @ self.w
        along0, n_i, lever = self._whole
        fi = np.clip((a - along0) / self.spacing, 0.0, n_i - 1 - 1e-9)
        i = np.floor(fi).astype(np.intp)
        j = np.clip(np.searchsorted(lever, b, side="right") - 1, 0, len(lever) - 2)
        fa = fi - i
        fb = np.clip((b - lever[j]) / (lever[j + 1] - lever[j]), 0.0, 1.0)
        i, j = i - self._offset[0], j - self._offset[1]
        n_i, n_j = len(self.along), len(self.lever)
        inside = (i >= 0) & (i < n_i - 1) & (j >= 0) & (j < n_j - 1)
        i, j = np.where(inside, i, 0), np.where(inside, j, 0)
        nodes = np.stack([i * n_j + j, i * n_j + j + 1, (i + 1) * n_j + j, (i + 1) * n_j + j + 1])
        weights = np.stack([(1 - fa) * (1 - fb), (1 - fa) * fb, fa * (1 - fb), fa * fb])
        return nodes, weights, inside


def pressure_table(mask: Mask, key, compute, reach_px: float | None = None) -> LocalArrays:
    """``compute(mask, points)`` (n, N) on the square grid ``PRESSURE_GRID_M`` apart, cached.

    The grid's node ``(i, j)`` lies at pixel ``(x, y) = step * (i, j)``, over
    the whole image; its pressures are computed where they are asked about
    (:func:`table_pressures`): first on the object's box grown by ``reach_px``
    (how far from a CoM hypothesis on the object a lattice node it is
    interpolated from can lie; default the neighbourhood's margin), then
    grown when a point needs a node outside it
    (:class:`comcore._neighbourhood.LocalArrays`). A node's pressures do not
    depend on which other nodes are computed with it, so the table holds the
    whole image's numbers wherever it is read.

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
        reach = margin_px(mask.resolution) if reach_px is None else reach_px
        margin = int(np.ceil(reach / g)) + 1
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
        values[i, j] * (1 - fx) * (1 - fy)
        + values[i, j + 1] * (1 - fx) * fy
        + values[i + 1, j] * fx * (1 - fy)
        + values[i + 1, j + 1] * fx * fy
    )


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


def widened(mask: Mask, key, make_whole):
    """The push ``key``'s lattice made over the whole image, its node motions carried over.

    For a hypothesis off the object's neighbourhood (:meth:`PushLattice.cells`
    gives None): ``make_whole()`` is the whole image's lattice of the same
    push, and what the neighbourhood's lattice knew is kept under its nodes'
    indices there. Returns ``(lattice, per_mu)`` as :func:`remembered` does.
    """
    pushes = _memo(mask)["pushes"]
    lattice, per_mu = pushes[key]
    whole = make_whole()
    ids = lattice.whole_ids()
    carried = {}
    for job, motions in per_mu.items():
        carried[job] = np.full((len(whole.points), *motions.shape[1:]), np.nan)
        carried[job][ids] = motions
    pushes[key] = (whole, carried)
    return whole, carried


def remembered(mask: Mask, key, make_lattice, mu: float, spreads=("",), shape=(3,)):
    """The remembered lattice and node motions of one push (``key``), and the frictions to batch.

    Returns ``(lattice, per_mu, mus)``: the push's lattice (``make_lattice()``
    the first time), a dict from ``(spread, friction)`` to a NaN-initialised
    array of node motions, shape (n_nodes, *shape) (default ``(3,)``), for every
    pressure spread in ``spreads``, and the friction values to integrate together: ``mu`` and
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
            if (spread, m) not in per_mu:  # (not setdefault: it would fill an array every call)
                per_mu[spread, m] = np.full((len(lattice.points), *shape), np.nan)
    return lattice, per_mu, mus
