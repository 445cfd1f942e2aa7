"""Alg. 2 of the paper: halve the feasible CoM region push by push."""

from __future__ import annotations

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
from ..conventions import pixel_centres, rotation_sense
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
    pusher_radius: float = 0.0,
    target_radius: float = DEFAULT_TARGET_RADIUS,
) -> Estimate:
    """Estimate the CoM with Alg. 2: cut the feasible region with the best-splitting push.

    Starting from the whole object, repeatedly pick the kept action whose line
    splits the current region most evenly (highest :func:`equality_score`),
    keep the part the Voting Theorem allows for its (predicted) rotation sense,
    and drop the chosen action and every action that scored below
    ``min_score``. Stop when the region is at most ``area_ratio`` of the
    object or no action is left. The CoM is the mean of one 8-connected part
    of the final region: the part the data point to (see below), the largest
    when they do not tell the parts apart.

    Choices where the paper is silent (each is tested):

    * Loop condition: go on while the region is larger than ``area_ratio`` of
      the object AND actions remain (the paper's "or" would never stop).
    * Side counts ``n1, n2`` count region pixels more than ``band`` from the
      action's line; pixels within ``band`` count on neither side.
    * Which part to keep: :func:`comcore.vt.consistent` with the action's
      contact point, inward normal and direction, for the sense of ``theta``
      and the friction spec ``mu`` (unknown by default). For a push along the
      normal this is the paper's half-plane; pixels within ``band`` of the
      deciding line stay in the region.
    * The ``min_score`` pruning (step 9) uses the scores computed on the
      region before the cut, as the paper's listing does.
    * Contradiction. An action with ``|theta| >= min_rotation`` contradicts
      the estimate when no pixel of the estimate's region can produce its
      sense (with the ``band`` and ``mu`` of the cuts): no CoM in the region
      explains it. This is checked for every such action, applied or not:
      one that is chosen is then skipped instead of applied (its allowed part
      misses the current region); one that is pruned (low score) or never
      reached is checked against the final region, first on its own, then
      together with the other left-out ones, as the cuts are: in descending
      ``|theta|`` (ties in index order) each must leave a region pixel that
      explains it and every surer one, else it contradicts them (pushes whose
      regions do not intersect are inconsistent even when none of them cuts,
      e.g. when none splits the object, as along its edges). Either way it
      is listed in ``progressive.contradicted`` (skipped ones first, in the
      order met, then those checked on their own, then together) and
      ``status`` is ``"inconsistent"``. The fallback estimate is the one the
      other actions give, exactly as if the contradicting ones had not been
      recorded: the region the applied cuts leave and its mean, never a NaN.
      Dropping an action is not in itself a contradiction: pruned or
      unreached actions that one region pixel explains together leave
      ``"ok"`` (or ``"wide"``), and
      actions turning the object less than ``min_rotation`` (whose sense
      noise may flip) are never called contradicted.
    * What ``"ok"`` says: what it says everywhere (:class:`comcore.Status`):
      the data are consistent and the region reached ``target_radius``. The
      region is the final one, the part of the cut region the CoM is the mean
      of (``Estimate.region``): ``"ok"`` when its equivalent-circle radius
      ``sqrt(area / pi)`` is at most ``target_radius`` (metres, the sessions'
      6 mm by default), ``"wide"`` when it is larger (the loop's own stop,
      ``area_ratio`` of the object, is no promise of a radius). It is a
      feasible region, not a credible one: the CoM is in it when every
      applied sense is right. Consistent means no action's sense contradicts
      the region: the senses are consistent, not necessarily right. Recorded motions with every
      theta's sign flipped (theta counter-clockwise with the y axis up) are
      explained by a CoM mirrored through the centroid when the pushes' lines
      pass near it, so such a recording mostly, not always, says
      ``"inconsistent"`` (``benchmarks/accuracy/estimate_methods.py --flips 0,all``
      counts how often). The senses cannot
      tell those two; the motions' sizes can: ``comcore estimate`` checks every
      recording's sign for every method, and :func:`comcore.estimate_posterior`
      with its default model calls such a recording ``"inconsistent"``.
    * Which part of a disconnected final region: the paper takes the largest.
      Here the parts are ranked by the evidence first, area only after it:
      (1) the most left-out actions (``|theta| >= min_rotation``, not
      applied) that a single pixel of the part explains; (2) the number of
      actions turning the object less than ``min_rotation`` (their lines pass
      near the CoM, the premise of ``min_rotation`` and of Alg. 1) whose line
      crosses the part, i.e. passes within half a pixel diagonal of one of
      its pixel centres; (3) the area; (4) the first in row-major order.
    * The loop also stops when no kept action has region pixels on both
      sides of its line (best score 0): such a push cannot cut the region.
    * No action with ``|theta| >= min_rotation``: the estimate is the mask's
      centroid and ``status == "no_actions"``.
    * ``selection="rotation"`` is the paper's ablation (Fig. 7): actions are
      taken in ascending ``|theta|`` with no score pruning.

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
        ``d_t`` in pixels.
    min_rotation : float, optional
        ``t_theta`` in radians: actions turning the object less are dropped.
    min_score : float, optional
        ``t_h``: actions scoring below it are dropped after each cut.
    selection : {"equality", "rotation"}, optional
    mu : None, float or (lo, hi), optional
        Contact friction for the Voting Theorem (default unknown).
    pusher_radius : float, optional
        Radius (metres) of a round pusher: each push's contact is where its
        disc first touches the object (:func:`comcore.geometry.disc_contacts`), so a
        grazing push whose leading line misses the mask is still scored. The
        default 0 is the paper's point pusher on the leading line. Pushes
        that start inside the object or never touch it are left out and
        reported in ``skipped``; a ValueError if more than half are.
    target_radius : float, optional
        Radius (metres) the final region must reach for ``"ok"`` (above); a
        wider one is ``"wide"``. Default 6 mm, the sessions'
        ``StopRule.target_radius``.

    Returns
    -------
    Estimate
        ``used`` lists the applied actions in order; ``progressive``
        (:class:`comcore.paper.ProgressiveDetails`) holds ``region_sizes``
        (pixels after each cut, starting with the object) and ``contradicted``
        (the contradicting actions). ``status`` is
        ``"ok"``, ``"wide"``, ``"inconsistent"`` or ``"no_actions"`` (never
        ``"ok"`` without a usable push).

    Examples
    --------
    >>> import numpy as np
    >>> from comcore import Mask
    >>> m = Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> acts = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
    >>> mots = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)]
    >>> e = estimate_progressive(m, acts, mots)
    >>> e.used, e.status, int(e.region.sum())
    ((0, 1, 2, 3), 'wide', 36)

    Consistent, but the 36 px left (radius 3.4 px of 2.5 mm, 8.5 mm) are wider
    than the default 6 mm target; against 1 cm the same answer is ``"ok"``:

    >>> estimate_progressive(m, acts, mots, target_radius=0.01).status
    'ok'

    Two pushes that no CoM explains together: the CoM below row 18 (push 1,
    clockwise) and above row 8 (push 0, counter-clockwise). Push 1 is applied,
    push 0 then has every region pixel on one side and is dropped, and is
    reported; the estimate is push 1's half:

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

    current = mask.data.copy()  # the feasible region, as an image
    rotation_order = [int(i) for i in np.argsort(np.abs(theta), kind="stable") if keep[i]]
    target = area_ratio * mask.area_px
    used: list[int] = []
    contradicted: list[int] = []
    sizes = [mask.area_px]
    direction = acts[:, 2:] - acts[:, :2]
    unit = direction / np.hypot(direction[:, 0], direction[:, 1])[:, None]
    cone = tuple(float(np.arctan(v)) for v in check_mu(mu))  # cone half-angle range
    a_lo, a_hi = cone
    sense = rotation_sense(theta, tol=0.0)

    while sizes[-1] > target and keep.any():
        if selection == "equality":
            scores = np.full(n_actions, -1.0)
            kept = np.flatnonzero(keep)
            scores[kept] = equality_score(*side_counts(current, acts[kept], band))
            chosen = int(np.argmax(scores))
            if scores[chosen] <= 0.0:
                break  # no kept action splits the region: nothing more to learn
            keep &= scores >= min_score
        else:
            chosen = next(i for i in rotation_order if keep[i])
        keep[chosen] = False
        r = con.point[chosen] - pixel_centres(current)
        allowed = _consistent(
            r, con.normal[chosen], unit[chosen], int(sense[chosen]), a_lo, a_hi, band=band
        )
        if not allowed.any():
            contradicted.append(chosen)
            continue
        current[current] = allowed  # row-major, like pixel_centres
        used.append(chosen)
        sizes.append(int(allowed.sum()))

    region = _final_region(
        current, used, contradicted, small, acts, con, unit, sense, cone, band, np.abs(theta)
    )
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


def _final_region(current, used, contradicted, small, acts, con, unit, sense, cone, band, turn):
    """The part of the cut region ``current`` the data point to; ``contradicted`` grows.

    Left-out informative pushes that no pixel of the returned region explains
    are appended to ``contradicted``, then those that no region pixel explains
    together with the left-out pushes turning the object more (``turn``, the
    ``|theta|`` of each push; ties in index order); the parts of a disconnected
    region are ranked as :func:`estimate_progressive` says.
    """
    a_lo, a_hi = cone
    # Which of the left-out informative pushes a CoM at each region pixel explains (the
    # applied ones explain every region pixel by construction, the skipped ones none).
    done = set(used) | set(contradicted)
    left_out = np.array([i for i in np.flatnonzero(~small) if i not in done], dtype=int)

    def explained(idx, points):  # (len(idx), len(points)) bool, in memory-bounded chunks
        out = np.zeros((len(idx), len(points)), dtype=bool)
        step = max(1, CHUNK_ELEMENTS // max(len(points), 1))
        for j in range(0, len(idx), step):
            k = idx[j : j + step]
            r = con.point[k, None, :] - points
            out[j : j + step] = _consistent_many(
                r, con.normal[k], unit[k], sense[k], a_lo, a_hi, band=band
            )
        return out

    pts = pixel_centres(current)
    labels, n_parts = label_components(current)
    if n_parts > 1:
        explains = explained(left_out, pts)
        part = labels[current] - 1  # component of each region pixel (row-major, like pts)
        region = best_component(labels, _evidence(part, n_parts, explains, pts, acts[small]))
        in_region = region[current]
        contradicted += [int(i) for i, row in zip(left_out, explains) if not row[in_region].any()]
    else:
        region = current
        # A few region pixels settle most pushes; only the others are checked on every pixel.
        probes = pts[:: -(-len(pts) // PROBE_PIXELS)]
        unsettled = left_out[~explained(left_out, probes).any(axis=1)]
        explains = explained(unsettled, pts)
        contradicted += [int(i) for i, row in zip(unsettled, explains) if not row.any()]
    # Each left-out push explained on its own may still contradict the others: the applied
    # cuts intersect their regions, so do the left-out ones, the surest (largest |theta|)
    # first; one whose region misses what the surer ones leave is contradicted.
    alive = pixel_centres(region)
    rest = [int(i) for i in left_out if int(i) not in contradicted]
    for i in sorted(rest, key=lambda i: -turn[i]):  # stable: ties in index order
        ok = explained(np.array([i]), alive)[0]
        if ok.any():
            alive = alive[ok]
        else:
            contradicted.append(i)
    return region


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
