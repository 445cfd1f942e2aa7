"""Mass distributions over a footprint: support points, their masses, the CoM.

The floor carries the object at ``n`` support points; point ``i`` presses on
it with the weight of the mass ``m_i`` above it (flat, uniform floor), so the
pressure distribution *is* the mass distribution. Support points are the
centroids of a square grid's cells clipped to the footprint (a cell's mass is
its clipped area times the local density), plus one point per point mass.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from comcore.checks import check_positive, readonly

from ._deps import require_shapely
from ._shapes import ObjectShape, _finite_pair

__all__ = ["DEFAULT_SUPPORT_POINTS", "MassDistribution", "tilt_to_com"]

#: Default number of grid support points over the footprint (see docs/explanation/simulators.md).
DEFAULT_SUPPORT_POINTS = 96


@dataclass(frozen=True, eq=False)
class MassDistribution:
    """Masses at support points of a footprint (world metres, initial pose).

    Attributes
    ----------
    points_m : numpy.ndarray, shape (n, 2)
        Support points in metres.
    masses : numpy.ndarray, shape (n,)
        Mass (kg) pressing on the floor at each point, all > 0.
    cell_size_m : float
        Side of the grid cells (their own inertia is added to the moment).
    """

    points_m: np.ndarray
    masses: np.ndarray
    cell_size_m: float

    def __post_init__(self):
        pts, m = readonly(self.points_m, float), readonly(self.masses, float)
        if pts.ndim != 2 or pts.shape[1] != 2 or m.shape != (pts.shape[0],):
            raise ValueError(f"points_m (n, 2) and masses (n,) disagree: {pts.shape}, {m.shape}")
        if not (np.isfinite(pts).all() and np.isfinite(m).all() and (m > 0).all()):
            raise ValueError("masses must be finite and > 0 at every support point")
        check_positive(self.cell_size_m, "cell_size_m")
        object.__setattr__(self, "points_m", pts)
        object.__setattr__(self, "masses", m)

    @property
    def total_mass(self) -> float:
        """Total mass (kg)."""
        return float(self.masses.sum())

    @property
    def com_m(self) -> tuple[float, float]:
        """Centre of mass ``(x, y)`` in metres."""
        c = self.masses @ self.points_m / self.masses.sum()
        return (float(c[0]), float(c[1]))

    @property
    def moment_of_inertia(self) -> float:
        """Moment of inertia about the CoM (kg m^2), cells counted as squares."""
        d = self.points_m - np.asarray(self.com_m)
        own = self.cell_size_m**2 / 6.0
        return float(self.masses @ (np.einsum("ij,ij->i", d, d) + own))

    def tilted(self, com_m) -> MassDistribution:
        """The same distribution exponentially tilted so that its CoM is ``com_m``."""
        return MassDistribution(
            self.points_m, tilt_to_com(self.points_m, self.masses, com_m), self.cell_size_m
        )

    @classmethod
    def on_shape(
        cls,
        shape: ObjectShape,
        *,
        mass: float = 1.0,
        point_masses=(),
        density_gradient=(0.0, 0.0),
        com=None,
        n_support: int = DEFAULT_SUPPORT_POINTS,
    ) -> MassDistribution:
        """Build a distribution on a footprint.

        Parameters
        ----------
        shape : ObjectShape
        mass : float, optional
            Mass (kg) of the body without the point masses.
        point_masses : sequence of (x, y, m), optional
            Extra masses (kg) at points (metres) inside the footprint.
        density_gradient : (gx, gy), optional
            Relative density change per metre: density ``1 + g . (p - centroid)``,
            which must stay positive over the footprint.
        com : (x, y) or None, optional
            Required CoM in metres. When given, the distribution above is
            exponentially tilted (:func:`tilt_to_com`) to put its CoM there.
            ``None`` keeps the CoM the distribution has (for a mesh shape with
            no point masses or gradient: the mesh's uniform-density CoM).
        n_support : int, optional
            About how many grid support points to spread over the footprint.
        """
        if isinstance(n_support, bool) or not isinstance(n_support, (int, np.integer)):
            raise TypeError(f"n_support must be an integer, got {type(n_support).__name__}")
        if n_support < 4:
            raise ValueError(f"n_support must be >= 4, got {n_support}")
        if not (isinstance(mass, (int, float)) and math.isfinite(mass) and mass > 0):
            raise ValueError(f"mass must be a positive number (kg), got {mass!r}")
        shapely = require_shapely()
        poly = shape.polygon()
        centers, areas, h = _grid_cells(poly, shapely, int(n_support))
        grad = _finite_pair(density_gradient, "density_gradient", "per metre")
        density = 1.0 + (centers - np.asarray(shape.centroid_m)) @ grad
        if (density <= 0).any():
            raise ValueError(
                "density_gradient is too steep: the density must stay positive over the footprint"
            )
        cell_mass = areas * density
        cell_mass *= mass / cell_mass.sum()
        pm = _point_masses(point_masses)
        if pm is not None:
            if not np.isfinite(pm).all() or (pm[:, 2] <= 0).any():
                raise ValueError("point_masses must be finite (x, y, m) rows with m > 0")
            if not shapely.contains_xy(poly, pm[:, 0], pm[:, 1]).all():
                raise ValueError("point_masses must lie inside the footprint")
            centers = np.vstack([centers, pm[:, :2]])
            cell_mass = np.concatenate([cell_mass, pm[:, 2]])
        dist = cls(centers, cell_mass, h)
        if com is None and pm is None and not grad.any() and shape.uniform_com_m is not None:
            com = shape.uniform_com_m
        if com is not None:
            com = _finite_pair(com, "com", "metres")
            if not shapely.contains_xy(poly, com[0], com[1]):
                raise ValueError(f"com {tuple(com.tolist())} must lie inside the footprint")
            dist = dist.tilted(com)
        return dist


def clipped_grid(poly, h: float, shapely):
    """The cells of side ``h`` of the grid over ``poly``'s box, clipped to it (empty ones dropped).

    The grid is centred on the box; the same cells carry the mass in
    :meth:`MassDistribution.on_shape` and in the MuJoCo scene's object.
    """
    x0, y0, x1, y1 = poly.bounds
    nx, ny = math.ceil((x1 - x0) / h), math.ceil((y1 - y0) / h)
    ox = x0 - 0.5 * (nx * h - (x1 - x0))
    oy = y0 - 0.5 * (ny * h - (y1 - y0))
    ix, iy = np.meshgrid(np.arange(nx), np.arange(ny))
    lo_x, lo_y = ox + ix.ravel() * h, oy + iy.ravel() * h
    clipped = shapely.intersection(shapely.box(lo_x, lo_y, lo_x + h, lo_y + h), poly)
    return clipped[shapely.area(clipped) > 1e-6 * h * h]


def _grid_cells(poly, shapely, n_support: int):
    """Centroids, areas and spacing of grid cells clipped to the polygon."""
    h = math.sqrt(poly.area / n_support)
    cells = clipped_grid(poly, h, shapely)
    return shapely.get_coordinates(shapely.centroid(cells)), shapely.area(cells), h


#: A stalled tilt is accepted when its mean is this close to the target, relative to the
#: points' extent (1e-8: 1 nm on a 10 cm object).
STALL_TOLERANCE = 1e-8


def tilt_to_com(points, weights, target, tol: float = 1e-10) -> np.ndarray:
    """Reweight ``w_i -> w_i exp(lam . p_i)`` so that the weighted mean is ``target``.

    The tilt is the distribution closest to the original in relative entropy
    with the required mean; it exists for every target strictly inside the
    convex hull of the points and is found by Newton's method on the convex
    log-partition function. The total weight is preserved.

    Parameters
    ----------
    points : array_like, shape (n, 2)
        Support points, finite.
    weights : array_like, shape (n,)
        Their weights, finite and > 0.
    target : array_like, shape (2,)
        The required weighted mean.
    tol : float, optional
        Largest accepted distance of the mean from ``target`` (the points' unit).

    Returns
    -------
    numpy.ndarray, shape (n,)

    Raises
    ------
    ValueError
        If a shape is wrong, a value is not finite, a weight is not > 0, or
        ``target`` is not strictly inside the points' convex hull.
    TypeError
        If ``target`` is not two numbers (``None``, a string).

    Examples
    --------
    >>> import numpy as np
    >>> p = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> w = tilt_to_com(p, np.ones(4), (0.25, 0.5))
    >>> (w @ p / w.sum()).round(9).tolist(), round(float(w.sum()), 9)
    ([0.25, 0.5], 4.0)
    """
    p, w = _points_and_weights(points, weights)
    t = _finite_pair(target, "target", "metres")
    scale = float(np.ptp(p, axis=0).max()) or 1.0
    x = (p - t) / scale
    lam = np.zeros(2)
    logw = np.log(w)
    for _ in range(200):
        z = logw + x @ lam
        q = np.exp(z - z.max())
        q /= q.sum()
        grad = q @ x
        if np.abs(grad).max() * scale <= tol:
            break
        xc = x - grad
        hess = (xc * q[:, None]).T @ xc + 1e-15 * np.eye(2)
        step = np.linalg.solve(hess, -grad)
        # Backtracking on the log-partition function keeps Newton globally convergent;
        # near the solution (tiny decrement) the full step is taken.
        f0 = np.log(np.exp(z - z.max()).sum()) + z.max()
        for _ in range(50 if -(grad @ step) > 1e-16 else 0):
            zn = logw + x @ (lam + step)
            if np.log(np.exp(zn - zn.max()).sum()) + zn.max() <= f0 + 1e-4 * grad @ step:
                break
            step *= 0.5
        if np.array_equal(lam + step, lam):
            break  # stalled at floating-point precision: judged below
        lam = lam + step
    # Newton can stall a hair short of `tol` (0.1 nm off, seen on Obj11) where rounding in
    # the log-partition function hides further progress; that is a solution. A target
    # outside the hull instead drives `lam` off to infinity with the error staying large.
    z = logw + x @ lam
    q = np.exp(z - z.max())
    q /= q.sum()
    if np.abs(q @ x).max() * scale > max(tol, STALL_TOLERANCE * scale):
        raise ValueError(f"target {tuple(t.tolist())} is not strictly inside the support points")
    return q * w.sum()


def _points_and_weights(points, weights) -> tuple[np.ndarray, np.ndarray]:
    """``points`` (n, 2) and ``weights`` (n,) as float arrays, finite, weights > 0."""
    p = np.asarray(points, dtype=float)
    w = np.asarray(weights, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) == 0 or not np.isfinite(p).all():
        raise ValueError(f"points must be finite, of shape (n, 2) with n >= 1, got shape {p.shape}")
    if w.shape != (len(p),):
        raise ValueError(f"weights must have shape ({len(p)},), one per point, got {w.shape}")
    if not (np.isfinite(w).all() and (w > 0).all()):
        bad = np.flatnonzero(~(np.isfinite(w) & (w > 0)))[:5].tolist()
        raise ValueError(
            f"weights must be finite and > 0 (masses); weight(s) {bad} are {w[bad].tolist()}"
        )
    return p, w


def _point_masses(value) -> np.ndarray | None:
    """``(x, y, m)`` rows as a float array of shape (k, 3); ``None`` when there are none."""
    want = "point_masses must be a sequence of (x, y, m) rows (metres, kg)"
    if value is None:
        return None
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{want}, got {type(value).__name__}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as e:  # ragged rows, objects
        raise TypeError(f"{want}, got {value!r}") from e
    if arr.ndim == 0:
        raise TypeError(f"{want}, got {type(value).__name__}")
    if arr.size == 0:
        return None
    if arr.shape == (3,):
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"{want}, got shape {arr.shape}")
    return arr
