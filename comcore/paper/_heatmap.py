"""Alg. 1 of the paper: the distance-weighted rotation heat map."""

from __future__ import annotations

import numpy as np

from .._mask import Mask
from .._status import Status
from .._types import Estimate, HeatmapDetails
from .._validation import (
    check_actions,
    check_mask,
    check_motions,
    check_one_object,
    check_positive,
    check_probability,
)
from ..geometry._contacts import contacts, line_distances
from ..geometry._regions import estimate_from_region, largest_component

__all__ = ["estimate_heatmap", "rotation_heatmap"]

#: Alg. 1's status when it found a region: the heat map has no test of the motions
#: (any motions give a calm region), so its answer is never ``"ok"``.
UNCHECKED = Status.UNCHECKED

#: Smallest ``length_scale`` (pixels): below it the weight ``exp(-d / length_scale)`` of a
#: pixel half a pixel from a push line underflows float32 (is below its smallest normal
#: number), so a line between pixel centres would weigh nothing anywhere. About 0.0057 px.
MIN_LENGTH_SCALE_PX = 0.5 / float(-np.log(np.finfo(np.float32).tiny))


def _check_length_scale(length_scale) -> float:
    length_scale = check_positive(length_scale, "length_scale")
    if length_scale < MIN_LENGTH_SCALE_PX:
        raise ValueError(
            f"length_scale must be at least {MIN_LENGTH_SCALE_PX:.4g} px, got {length_scale:g}: "
            "below it the weight exp(-d / length_scale) of a pixel half a pixel from a push "
            "line underflows float32 and the heat map no longer sees the pushes"
        )
    return length_scale


def rotation_heatmap(mask: Mask, actions, motions, length_scale: float = 1.0) -> np.ndarray:
    """The normalised heat map ``S`` of Alg. 1 (lines 1-6).

    ``S(p) = sum_a exp(-d(p, line_a) / length_scale) * |theta_a|`` over the
    object's pixels, then scaled to [0, 1] over the object. Pixels off the
    object are 0. If ``S`` is constant over the object the map is all zeros.

    Parameters
    ----------
    mask : Mask
    actions : array_like, shape (n, 4)
    motions : array_like, shape (n, 3)
    length_scale : float, optional
        Decay length of the distance weight in pixels (paper: 1 px), finite
        and at least ``MIN_LENGTH_SCALE_PX`` (about 0.0057 px).

    Returns
    -------
    numpy.ndarray of float, shape (H, W)

    Raises
    ------
    ValueError
        If ``length_scale`` is not finite, or so small that the weight of a
        pixel half a pixel from a push line underflows float32 (the map is
        computed in float32; it would come out flat whatever the pushes).
    """
    mask = check_mask(mask)
    acts = check_actions(actions)
    mots = check_motions(motions, n=acts.shape[0])
    length_scale = _check_length_scale(length_scale)
    dist = line_distances(mask.pixels, acts, np.float32)  # (m, n): pixels x actions
    np.abs(dist, out=dist)
    dist *= np.float32(-1.0 / length_scale)
    np.exp(dist, out=dist)
    score = dist @ np.abs(mots[:, 0]).astype(np.float32)
    lo, hi = float(score.min()), float(score.max())
    norm = (score - lo) / (hi - lo) if hi > lo else np.zeros_like(score)
    out = np.zeros(mask.shape, dtype=float)
    out[mask.data] = norm  # mask.pixels is row-major, like boolean indexing
    return out


def estimate_heatmap(
    mask: Mask,
    actions,
    motions,
    *,
    threshold: float = 0.1,
    length_scale: float = 1.0,
) -> Estimate:
    """Estimate the CoM with Alg. 1: the calmest region of the rotation heat map.

    Every action's line weights its predicted ``|theta|`` by ``exp(-d /
    length_scale)`` at each object pixel (``d``: pixel-to-line distance);
    the sum is normalised to [0, 1], pixels below ``threshold`` are segmented,
    and the CoM is the mean of the largest 8-connected segment.

    Choices where the paper is silent: every given action is used (Alg. 1's
    ``A_keep`` is all actions); the threshold's default 0.1 is ours (the paper
    gives no value for Alg. 1); connectivity is 8-neighbour.

    Alg. 1 has no test of its evidence: any motions, right or wrong (a
    theta sign flipped, x and y swapped, a predictor gone astray), give some
    calm region, and nothing in the heat map tells them apart. Its status is
    therefore never ``"ok"``: ``"unchecked"`` says the answer is the paper's,
    unverified. Where you need an answer that says when the motions
    contradict it, use :func:`comcore.estimate_progressive` (Alg. 2:
    ``"inconsistent"``) or :func:`comcore.estimate_posterior`
    (``"inconsistent"``).

    Parameters
    ----------
    mask : Mask
    actions : Action, sequence of Action, or array_like, shape (n, 4)
        Pushes; each must start outside the object and hit it.
    motions : Motion, sequence of Motion, or array_like, shape (n, 3)
        The (predicted) motion of each push.
    threshold : float, optional
        Segmentation threshold ``s_t`` in [0, 1].
    length_scale : float, optional
        Distance decay in pixels (paper: 1 px); at least
        ``MIN_LENGTH_SCALE_PX`` (about 0.0057 px, see :func:`rotation_heatmap`).

    Returns
    -------
    Estimate
        ``status`` ``"unchecked"`` (:data:`UNCHECKED`): a region was found, its
        evidence not tested (``ok`` is ``False``). With no actions, or a heat
        map that is flat over the object, the result is the mask's centroid
        with ``status`` ``"no_actions"`` or ``"flat_heatmap"``.
        ``heatmap`` (:class:`comcore.paper.HeatmapDetails`) holds ``S`` (H, W)
        and the thresholded pixels before the connected-component step.

    Examples
    --------
    Pushes along every row and column of a square turn it in proportion to
    their distance from the centre; the calm region is around the centre.

    >>> import numpy as np
    >>> from comcore import Mask
    >>> m = Mask(np.pad(np.ones((21, 21), bool), 5))
    >>> acts = [(0, r, 40, r) for r in range(5, 26)] + [(c, 0, c, 40) for c in range(5, 26)]
    >>> mots = [(0.02 * abs(k - 15), 3, 0) for k in range(5, 26)] * 2
    >>> e = estimate_heatmap(m, acts, mots)
    >>> e.status, e.ok, e.com
    ('unchecked', False, (15.0, 15.0))
    """
    mask = check_one_object(mask)
    acts = check_actions(actions)
    mots = check_motions(motions, n=acts.shape[0])
    threshold = check_probability(threshold, "threshold")
    length_scale = _check_length_scale(length_scale)
    if acts.shape[0] == 0:
        return estimate_from_region(mask, mask.data, status=Status.NO_ACTIONS)
    contacts(mask, acts).require_hits("actions")
    heat = rotation_heatmap(mask, acts, mots, length_scale)
    segmented = mask.data & (heat < threshold)
    status = UNCHECKED
    if not heat.any():
        status, segmented = Status.FLAT_HEATMAP, mask.data
    region = largest_component(segmented)
    return estimate_from_region(
        mask,
        region,
        used=range(acts.shape[0]),
        status=status,
        heatmap=HeatmapDetails(image=heat, segmented=segmented),
    )
