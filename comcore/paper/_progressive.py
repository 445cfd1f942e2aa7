"""Alg. 2 of the paper: halve the feasible CoM region push by push.

:func:`estimate_progressive` decides as follows where the paper is silent (each is tested):

* The loop goes on while the region is larger than ``area_ratio`` of the object AND
  actions remain (the paper's "or" would never stop); it also stops when no kept action
  has region pixels on both sides of its line (best score 0: no push can cut the region).
* Side counts ``n1, n2`` count region pixels more than ``band`` from the action's line;
  pixels within ``band`` count on neither side.
* The part kept: :func:`comcore.vt.consistent` with the action's contact point, inward
  normal and direction, for the sense of ``theta`` and the friction ``mu``. For a push
  along the normal this is the paper's half-plane; pixels within ``band`` of the deciding
  line stay in the region.
* The ``min_score`` pruning (step 9) uses the scores computed on the region before the
  cut, as the paper's listing does.
* Contradiction: an action with ``|theta| >= min_rotation`` contradicts the estimate when
  no pixel of the estimate's region can produce its sense (with the cuts' ``band`` and
  ``mu``). A chosen one is then skipped instead of applied; one pruned or never reached
  is checked against the final region, first on its own, then together with the other
  left-out ones, as the cuts are: in descending ``|theta|`` (ties in index order) each
  must leave a region pixel that explains it and every surer one (pushes whose regions
  do not intersect are inconsistent even when none of them cuts). The contradicted are
  listed skipped ones first, in the order met, then those checked on their own, then
  together; the fallback estimate is what the other actions give, exactly as if the
  contradicting ones had not been recorded. Dropping an action is not in itself a
  contradiction, and an action turning the object less than ``min_rotation`` (whose
  sense noise may flip) is never called contradicted.
* Consistent senses are not necessarily right: motions with every theta's sign flipped
  are explained by a CoM mirrored through the centroid when the pushes' lines pass near
  it, so such a recording mostly, not always, says ``"inconsistent"``
  (``benchmarks/accuracy/estimate_methods.py --flips 0,all`` counts how often). The
  motions' sizes tell the two apart: ``comcore estimate`` checks every recording's sign,
  and :func:`comcore.estimate_posterior` with its default model calls such a recording
  ``"inconsistent"``.
* Which part of a disconnected final region: the paper takes the largest. Here the parts
  are ranked by (1) the most left-out actions (``|theta| >= min_rotation``, not applied)
  that a single pixel of the part explains; (2) the number of actions turning the object
  less than ``min_rotation`` (their lines pass near the CoM) whose line passes within half
  a pixel diagonal of one of the part's pixel centres; (3) the area; (4) the first in
  row-major order.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._mask import Mask
from .._status import DEFAULT_TARGET_RADIUS, Status, region_reached
from .._types import Estimate, ProgressiveDetails
from .._validation import (
    check_actions,
    check_motions,
    check_mu,
    check_one_object,
    check_physical,
    check_positive,
    check_probability,
)
from ..conventions import DEFAULT_PUSHER_RADIUS, pixel_centres, rotation_sense
from ..geometry._contacts import line_distances, side_counts
from ..geometry._disc_contacts import pusher_contacts, usable_pushes
from ..geometry._regions import best_component, estimate_from_region, label_components
from ..geometry._sampling import HALF_PIXEL_DIAGONAL
from ..vt._voting import _consistent, _consistent_many

__all__ = ["equality_score", "estimate_progressive"]

SELECTIONS = ("equality", "rotation")
#: Pixel-push pairs evaluated at once when checking the left-out pushes (memory bound).
CHUNK_ELEMENTS = 1 << 18
#: About this many region pixels are tried first for each left-out push.
PROBE_PIXELS = 64


def equality_score(n1, n2) -> np.ndarray:
    """The Action Equality Score ``h = 2 sqrt(n1 n2) / (n1 + n2)`` (paper Eq. 1).

    1 for an even split, 0 when a side is empty (also when both are).

    Parameters
    ----------
    n1, n2 : array_like
        Pixel counts on the two sides of a line (finite, >= 0), broadcast
        against each other.

    Returns
    -------
    numpy.ndarray
        Scores in [0, 1], the broadcast shape of ``n1`` and ``n2``.

    Raises
    ------
    ValueError
        If a count is negative, NaN or infinite.

    Examples
    --------
    >>> equality_score([50, 10, 0], [50, 90, 7]).round(3)
    array([1. , 0.6, 0. ])
    >>> equality_score(-1, 5)
    Traceback (most recent call last):
    ...
    ValueError: n1 must hold finite counts >= 0, got -1.0
    """
    n1 = _counts(n1, "n1")
    n2 = _counts(n2, "n2")
    total = n1 + n2
    with np.errstate(invalid="ignore", divide="ignore"):
        h = 2.0 * np.sqrt(n1 * n2) / total
    return np.where(total > 0, h, 0.0)


def _counts(value, name: str) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be array_like of counts; {e}") from e
    bad = ~(np.isfinite(arr) & (arr >= 0))
    if bad.any():
        raise ValueError(f"{name} must hold finite counts >= 0, got {arr[bad].flat[0]}")
    return arr


def estimate_progressive(
    mask: Mask,
    actions,
    motions,
    *,
    area_ratio: float = 0.1,
    band: float = 0.5,
    min_rotation: float = float(np.deg2rad(5.0)),
    min_score: float = 0.6,
    selection: str = "equality",
    mu=None,
    pusher_radius: float = DEFAULT_PUSHER_RADIUS,
    target_radius: float = DEFAULT_TARGET_RADIUS,
) -> Estimate:
    """Estimate the CoM with Alg. 2: cut the feasible region with the best-splitting push.

    Apply, from the whole object, the kept action whose line splits the region most evenly
    (:func:`equality_score`), keeping the part its sense allows (:func:`comcore.vt.consistent`);
    drop it and every action scoring below ``min_score``; repeat until the region is at most
    ``area_ratio`` of the object or no action is left. The CoM: the mean of the final region's
    8-connected part the left-out actions point to (:mod:`comcore.paper._progressive`).

    ``status``: ``"ok"`` if the (feasible) region's radius reached ``target_radius``, else
    ``"wide"``; ``"inconsistent"`` if no region pixel explains an action turning ``min_rotation``
    or more; ``"no_actions"`` (the centroid) if none turns that much (docs/explanation/method.md).

    Parameters
    ----------
    mask : Mask
    actions : Action, sequence of Action, or array_like, shape (n, 4)
        Candidate pushes; each must start outside the object and hit it.
    motions : Motion, sequence of Motion, or array_like, shape (n, 3)
        (Predicted) motion of each push.
    area_ratio : float, optional
        ``s_t``: stop when the region is at most this fraction of the object.
    band : float, optional
        ``d_t`` in pixels: pixels this close to a line count on neither side.
    min_rotation : float, optional
        ``t_theta`` in radians: actions turning the object less are not applied.
    min_score : float, optional
        ``t_h``: actions scoring below it are dropped after each cut.
    selection : {"equality", "rotation"}, optional
        ``"rotation"``: the paper's ablation, ascending ``|theta|``, no pruning.
    mu : None, float or (lo, hi), optional
        Contact friction for the Voting Theorem (default unknown).
    pusher_radius : float, optional
        Radius (metres) of a round pusher (default 4 mm; 0: a point). Pushes that start inside
        the object or miss it are listed in ``skipped``; a ValueError if more than half are.
    target_radius : float, optional
        Radius (metres) the region must reach for ``"ok"`` (default 6 mm).

    Returns
    -------
    Estimate
        ``used``: the applied actions in order; ``progressive``: a :class:`ProgressiveDetails`.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> m = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> acts = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
    >>> e = estimate_progressive(m, acts, [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)])
    >>> e.used, e.status, int(e.region.sum())
    ((0, 1, 2, 3), 'wide', 36)
    >>> # two pushes no CoM explains together: push 0 is reported, the estimate is push 1's half
    >>> e = estimate_progressive(m, [(0, 8, 30, 8), (0, 18, 30, 18)], [(0.2, 3, 0), (-0.2, 3, 0)])
    >>> e.status, e.used, e.progressive.contradicted, e.com
    ('inconsistent', (1,), (0,), (13.5, 20.5))
    """
    mask = check_one_object(mask)
    acts = check_actions(actions)
    mots = check_motions(motions, n=acts.shape[0])
    area_ratio = check_probability(area_ratio, "area_ratio")
    band = check_positive(band, "band", allow_zero=True)
    min_rotation = check_positive(min_rotation, "min_rotation", allow_zero=True)
    min_score = check_probability(min_score, "min_score")
    check_mu(mu)
    if selection not in SELECTIONS:
        raise ValueError(f"selection must be one of {SELECTIONS}, got {selection!r}")
    pusher_radius = check_physical(pusher_radius, "pusher_radius", "pusher_radius", allow_zero=True)
    target_radius = check_physical(target_radius, "target_radius", "target_radius")
    n_actions = acts.shape[0]
    skipped: tuple = ()
    usable = np.ones(n_actions, dtype=bool)
    if n_actions:
        con = pusher_contacts(mask, acts, pusher_radius)
        usable, skipped = usable_pushes(con, "actions")
    theta = mots[:, 0]
    small = np.abs(theta) < min_rotation  # turned too little to trust the sense
    keep = ~small & usable
    if not keep.any():
        return estimate_from_region(
            mask,
            mask.data,
            status=Status.NO_ACTIONS,
            progressive=ProgressiveDetails(region_sizes=(mask.area_px,)),
            skipped=skipped,
        )
    direction = acts[:, 2:] - acts[:, :2]
    unit = direction / np.hypot(direction[:, 0], direction[:, 1])[:, None]
    cone = tuple(float(np.arctan(v)) for v in check_mu(mu))  # cone half-angle range
    cuts = _Cuts(acts, con.point, con.normal, unit, rotation_sense(theta, tol=0.0), cone, band)
    options = {"selection": selection, "area_ratio": area_ratio, "min_score": min_score}
    current, used, contradicted, sizes = _cut(mask, cuts, keep, np.abs(theta), **options)
    done = set(used) | set(contradicted)
    left_out = np.array([i for i in np.flatnonzero(~small) if i not in done], dtype=int)
    region, more = _final_region(current, cuts, left_out, acts[small], np.abs(theta))
    contradicted += more
    if contradicted:
        status = Status.INCONSISTENT
    elif region_reached(np.sqrt(region.sum() / np.pi), target_radius, mask.resolution):
        status = Status.OK
    else:
        status = Status.WIDE
    return estimate_from_region(
        mask,
        region,
        used=used,
        status=status,
        progressive=ProgressiveDetails(tuple(sizes), tuple(contradicted)),
        skipped=skipped,
    )


class _Cuts(NamedTuple):
    """What the Voting Theorem reads of each push to cut the region with it."""

    actions: np.ndarray
    """(n, 4) the pushes, pixels."""
    point: np.ndarray
    """(n, 2) each push's contact point, pixels."""
    normal: np.ndarray
    """(n, 2) the object's unit inward normal at each contact."""
    unit: np.ndarray
    """(n, 2) each push's unit direction."""
    sense: np.ndarray
    """(n,) each push's observed rotation sense: +1, -1 or 0."""
    cone: tuple[float, float]
    """The friction cone's half-angle range, radians: ``atan`` of the ``mu`` range."""
    band: float
    """Pixels within this distance of a deciding line are kept, pixels."""

    def allowed(self, i: int, points: np.ndarray) -> np.ndarray:
        """Which ``points`` (m, 2) push ``i``'s sense allows as the CoM, (m,) bool."""
        r = self.point[i] - points
        sense = int(self.sense[i])
        return _consistent(r, self.normal[i], self.unit[i], sense, *self.cone, band=self.band)

    def explained(self, idx: np.ndarray, points: np.ndarray) -> np.ndarray:
        """Which ``points`` explain each push of ``idx``, (len(idx), len(points)) bool."""
        out = np.zeros((len(idx), len(points)), dtype=bool)
        step = max(1, CHUNK_ELEMENTS // max(len(points), 1))  # memory-bounded chunks
        for j in range(0, len(idx), step):
            k = idx[j : j + step]
            r = self.point[k, None, :] - points
            out[j : j + step] = _consistent_many(
                r, self.normal[k], self.unit[k], self.sense[k], *self.cone, band=self.band
            )
        return out


def _cut(mask: Mask, cuts: _Cuts, keep, turn, *, selection, area_ratio, min_score):
    """Alg. 2's loop: ``(region image, used, contradicted, region sizes)``.

    ``keep`` (n,) the actions that may be applied (updated); ``turn`` each
    action's ``|theta|`` (the order of ``selection="rotation"``).
    """
    current = mask.data.copy()  # the feasible region, as an image
    rotation_order = [int(i) for i in np.argsort(turn, kind="stable") if keep[i]]
    target = area_ratio * mask.area_px
    used: list[int] = []
    contradicted: list[int] = []
    sizes = [mask.area_px]
    while sizes[-1] > target and keep.any():
        if selection == "equality":
            scores = np.full(len(keep), -1.0)
            kept = np.flatnonzero(keep)
            scores[kept] = equality_score(*side_counts(current, cuts.actions[kept], cuts.band))
            chosen = int(np.argmax(scores))
            if scores[chosen] <= 0.0:
                break  # no kept action splits the region: nothing more to learn
            keep &= scores >= min_score
        else:
            chosen = next(i for i in rotation_order if keep[i])
        keep[chosen] = False
        allowed = cuts.allowed(chosen, pixel_centres(current))
        if not allowed.any():
            contradicted.append(chosen)
            continue
        current[current] = allowed  # row-major, like pixel_centres
        used.append(chosen)
        sizes.append(int(allowed.sum()))
    return current, used, contradicted, sizes


def _final_region(current, cuts: _Cuts, left_out, hardly_turning, turn):
    """The part of the cut region ``current`` the data point to, and the left-out contradicted.

    ``left_out``: the informative pushes neither applied nor contradicted yet.
    Those that no pixel of the returned region explains are contradicted, then
    those that no region pixel explains together with the left-out pushes
    turning the object more (``turn``, the ``|theta|`` of each push; ties in
    index order); the parts of a disconnected region are ranked by the left-out
    pushes and the lines of ``hardly_turning`` (:func:`_evidence`).
    """
    # Which of the left-out informative pushes a CoM at each region pixel explains (the
    # applied ones explain every region pixel by construction, the skipped ones none).
    contradicted: list[int] = []
    pts = pixel_centres(current)
    labels, n_parts = label_components(current)
    if n_parts > 1:
        explains = cuts.explained(left_out, pts)
        part = labels[current] - 1  # component of each region pixel (row-major, like pts)
        region = best_component(labels, _evidence(part, n_parts, explains, pts, hardly_turning))
        in_region = region[current]
        contradicted += [int(i) for i, row in zip(left_out, explains) if not row[in_region].any()]
    else:
        region = current
        # A few region pixels settle most pushes; only the others are checked on every pixel.
        probes = pts[:: -(-len(pts) // PROBE_PIXELS)]
        unsettled = left_out[~cuts.explained(left_out, probes).any(axis=1)]
        explains = cuts.explained(unsettled, pts)
        contradicted += [int(i) for i, row in zip(unsettled, explains) if not row.any()]
    # Each left-out push explained on its own may still contradict the others: the applied
    # cuts intersect their regions, so do the left-out ones, the surest (largest |theta|)
    # first; one whose region misses what the surer ones leave is contradicted.
    alive = pixel_centres(region)
    rest = [int(i) for i in left_out if int(i) not in contradicted]
    for i in sorted(rest, key=lambda i: -turn[i]):  # stable: ties in index order
        ok = cuts.explained(np.array([i]), alive)[0]
        if ok.any():
            alive = alive[ok]
        else:
            contradicted.append(i)
    return region, contradicted


def _evidence(part, n_parts, explains, pts, hardly_turning) -> np.ndarray:
    """Per component of the final region: (best pixel's support, crossing lines), (n, 2).

    ``part``: the component (0-based) of each region pixel; ``explains``: (k, m) which
    left-out pushes each pixel explains; ``hardly_turning``: the pushes that turned the
    object less than ``min_rotation``, whose lines pass near the CoM.
    """
    keys = np.zeros((n_parts, 2))
    support = explains.sum(axis=0)
    np.maximum.at(keys[:, 0], part, support)
    if len(hardly_turning):
        crosses = np.abs(line_distances(pts, hardly_turning)) <= HALF_PIXEL_DIAGONAL  # (m, j)
        hit = np.zeros((n_parts, crosses.shape[1]), dtype=bool)
        np.logical_or.at(hit, part, crosses)
        keys[:, 1] = hit.sum(axis=1)
    return keys
