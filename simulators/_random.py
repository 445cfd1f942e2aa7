"""Random trials: a random mass distribution and contact friction on a footprint."""

from __future__ import annotations

import numpy as np

import comcore

from ._deps import require_shapely
from ._mass import MassDistribution
from ._objects import load_object
from ._shapes import ObjectShape
from ._simulator import PushSimulator

__all__ = [
    "FRICTION_CLASSES",
    "MASS_STYLES",
    "accepted_random_simulator",
    "random_com",
    "random_simulator",
]

#: Contact friction classes (pusher-object): ``mu_contact`` is drawn uniformly in them.
FRICTION_CLASSES = {"low": (0.1, 0.3), "high": (0.5, 0.9)}
#: How the mass is spread before it is tilted to the drawn CoM.
MASS_STYLES = ("uniform", "gradient", "point_masses")
#: A CoM is "well inside" when its depth is at least this fraction of the inradius.
COM_DEPTH_FRACTION = 0.25
#: Draws :func:`accepted_random_simulator` makes before it gives up.
SIMULATOR_ATTEMPTS = 10


def _as_shape(shape_or_name) -> ObjectShape:
    if isinstance(shape_or_name, ObjectShape):
        return shape_or_name
    if isinstance(shape_or_name, str):
        return load_object(shape_or_name)
    raise TypeError(
        "shape_or_name must be a simulators.ObjectShape or a benchmark object name, "
        f"got {type(shape_or_name).__name__}"
    )


def random_com(shape: ObjectShape, rng=None, depth_fraction: float = COM_DEPTH_FRACTION):
    """A point drawn uniformly over the footprint's points that lie well inside it.

    "Well inside" means at least ``depth_fraction`` times the inradius (the
    radius of the largest inscribed disc) from the outline.

    Returns
    -------
    tuple of float
        ``(x, y)`` in metres.

    Raises
    ------
    ValueError
        If ``depth_fraction`` is not in [0, 1) (at 1 only the deepest point is left).
    """
    shapely = require_shapely()
    from shapely.ops import polylabel

    depth_fraction = comcore.checks.check_probability(
        depth_fraction, "depth_fraction", open_high=True
    )
    rng = comcore.checks.check_rng(rng)
    poly = shape.polygon()
    inradius = poly.exterior.distance(polylabel(poly, tolerance=1e-5))
    min_depth = depth_fraction * inradius
    x0, y0, x1, y1 = poly.bounds
    for _ in range(100):
        cand = rng.uniform((x0, y0), (x1, y1), size=(256, 2))
        inside = shapely.contains_xy(poly, cand[:, 0], cand[:, 1])
        cand = cand[inside]
        deep = shapely.distance(poly.exterior, shapely.points(cand)) >= min_depth
        if deep.any():
            p = cand[np.flatnonzero(deep)[0]]
            return (float(p[0]), float(p[1]))
    raise ValueError(  # pragma: no cover
        f"could not draw a CoM at depth_fraction {depth_fraction:g} of the inradius inside "
        "the footprint; choose a smaller depth_fraction"
    )


def random_simulator(
    shape_or_name,
    friction="low",
    rng=None,
    resolution: float = comcore.conventions.DEFAULT_RESOLUTION,
    **options,
) -> PushSimulator:
    """A simulator of one random trial on a footprint (what benchmarks draw).

    The contact friction ``mu_contact`` is uniform in the friction class. The
    mass is uniform, uniform with a random linear density gradient, or uniform
    plus one to three point masses (each 20 % to 150 % of the body's mass),
    each style equally likely; it is then exponentially tilted so that the CoM
    lands on a point drawn uniformly over the footprint's points well inside
    it (:func:`random_com`).

    Parameters
    ----------
    shape_or_name : ObjectShape or str
        A footprint or a benchmark object's name (``"Obj1"`` ... ``"Obj20"``).
    friction : {"low", "high"} or (lo, hi), optional
        Friction class (see :data:`FRICTION_CLASSES`) or an explicit range.
    rng : None, int or numpy.random.Generator, optional
    resolution : float, optional
        Metres per pixel of the mask.
    **options
        Passed to :class:`PushSimulator` (``pusher_radius``, ``settings``, ...).

    Examples
    --------
    >>> sim = random_simulator("Obj3", friction="high", rng=1)
    >>> 0.5 <= sim.mu_contact <= 0.9, bool(sim.mask.contains([sim.com_px])[0])
    (True, True)
    """
    shape = _as_shape(shape_or_name)
    if isinstance(friction, str):
        if friction not in FRICTION_CLASSES:
            raise ValueError(
                f"friction must be one of {sorted(FRICTION_CLASSES)}, got {friction!r}"
            )
        lo, hi = FRICTION_CLASSES[friction]
    else:
        lo, hi = comcore.checks.check_mu(friction, "friction")
    rng = comcore.checks.check_rng(rng)
    mu = float(rng.uniform(lo, hi))
    style = MASS_STYLES[int(rng.integers(len(MASS_STYLES)))]
    point_masses: list[tuple[float, float, float]] = []
    gradient = np.zeros(2)
    if style == "gradient":
        x0, y0, x1, y1 = shape.bounds_m
        span = max(x1 - x0, y1 - y0)
        gradient = rng.normal(size=2) / span * rng.uniform(0.5, 1.8)
        c = np.asarray(shape.centroid_m)
        lowest = float(np.min((shape.vertices_m - c) @ gradient))
        if lowest < -0.9:  # keep the density positive everywhere on the outline
            gradient *= 0.9 / -lowest
    elif style == "point_masses":
        for _ in range(int(rng.integers(1, 4))):
            x, y = random_com(shape, rng)
            point_masses.append((x, y, float(rng.uniform(0.2, 1.5))))
    target = random_com(shape, rng)
    mass = MassDistribution.on_shape(
        shape,
        point_masses=point_masses,
        density_gradient=gradient,
        com=target,
        n_support=options.pop("n_support", 96),
    )
    return PushSimulator(shape, mass, mu_contact=mu, resolution=resolution, **options)


def accepted_random_simulator(
    shape_or_name,
    friction="low",
    rng=None,
    *,
    attempts: int = SIMULATOR_ATTEMPTS,
    on_refusal=None,
    **options,
) -> PushSimulator:
    """:func:`random_simulator`, drawn again while the simulator refuses the draw.

    A draw is refused with a ValueError when the drawn mass distribution
    cannot be built (the tilt cannot put the CoM on the drawn point) or,
    for a footprint drawn afresh each attempt, when the footprint is not a
    valid polygon. The first draw that is accepted is returned, so whatever
    is accepted at the first attempt is exactly ``random_simulator``'s draw.

    Parameters
    ----------
    shape_or_name : ObjectShape, str or callable
        As for :func:`random_simulator`, or ``shape_or_name(attempt)`` returning
        one: a footprint drawn afresh at each attempt (``attempt`` counts from 0).
    friction : {"low", "high"} or (lo, hi), optional
    rng : None, int, numpy.random.Generator or callable, optional
        One stream for every attempt (a redraw continues it), or
        ``rng(attempt)`` returning each attempt's own seed or Generator (so that
        a redraw does not depend on how much the refused draw took).
    attempts : int, optional
        Draws before giving up (>= 1).
    on_refusal : callable, optional
        ``on_refusal(attempt, error)`` after each refused draw (to report it).
    **options
        Passed to :func:`random_simulator`.

    Returns
    -------
    PushSimulator

    Raises
    ------
    RuntimeError
        If every attempt is refused (chained from the last refusal, whose
        message it repeats: a bad argument is refused at every attempt).

    Examples
    --------
    >>> sim = accepted_random_simulator("Obj3", "high", rng=lambda attempt: [1, attempt])
    >>> 0.5 <= sim.mu_contact <= 0.9
    True
    >>> refusals = []
    >>> accepted_random_simulator("Obj3", rng=1, resolution=-1.0, attempts=2,
    ...                           on_refusal=lambda k, e: refusals.append(k))
    Traceback (most recent call last):
    ...
    RuntimeError: no random simulator accepted in 2 attempt(s); the last refusal: ...
    >>> refusals
    [0, 1]
    """
    if isinstance(attempts, bool) or not isinstance(attempts, (int, np.integer)):
        raise TypeError(f"attempts must be an integer, got {type(attempts).__name__}")
    if attempts < 1:
        raise ValueError(f"attempts must be >= 1, got {attempts}")
    stream = None if callable(rng) else comcore.checks.check_rng(rng)
    error: ValueError | None = None
    for attempt in range(int(attempts)):
        try:
            shape = shape_or_name(attempt) if callable(shape_or_name) else shape_or_name
            own = stream if stream is not None else rng(attempt)
            return random_simulator(shape, friction, rng=own, **options)
        except ValueError as e:
            error = e
            if on_refusal is not None:
                on_refusal(attempt, e)
    raise RuntimeError(
        f"no random simulator accepted in {attempts} attempt(s); the last refusal: {error}"
    ) from error
