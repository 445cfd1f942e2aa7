"""Where :func:`comcore.plot.plot_estimate` draws things: windows, outlines, number places.

Plain numpy (no matplotlib), so the layout is tested without drawing: which pushes an
estimate rests on, what it believes, the axes' window around the object, the region's
outline along pixel edges and where each push's number goes.
"""

from __future__ import annotations

import numpy as np

from .._mask import Mask
from .._types import Estimate
from .._validation import check_actions

__all__ = [
    "belief_of",
    "evidence_of",
    "executed_pushes",
    "is_active",
    "number_positions",
    "region_outline",
    "window",
]

#: ``view="object"``: pushes widen the window at most this many object sizes past the object.
PUSH_REACH = 0.75
#: ``view="object"``: the margin around the object and its pushes, a share of the window.
MARGIN = 0.08
#: ... and at least this many pixels.
MIN_MARGIN_PX = 3.0
#: A push's number steps back along its line at most this many times to stay clear.
MAX_STEPS = 4


def executed_pushes(estimate: Estimate, actions=None) -> tuple[np.ndarray, np.ndarray]:
    """The pushes an estimate rests on, in order, and the given pushes not among them.

    Where the estimate lists its pushes in ``pushes`` (the active
    estimator's executed pushes, the offline posterior's recorded ones) those
    are they, in order: an active run's ``used`` indexes its candidates, not
    them. For the others they are ``actions[used]`` in the order ``used``
    lists them.

    Returns
    -------
    executed : numpy.ndarray, shape (k, 4)
    others : numpy.ndarray, shape (m, 4)
        The rows of ``actions`` not among them (empty without ``actions``).

    Examples
    --------
    >>> import numpy as np, comcore
    >>> est = comcore.Estimate((1.0, 1.0), (0.0, 0.0), np.ones((3, 3), bool), used=(2, 0))
    >>> done, rest = executed_pushes(est, [(0, 0, 1, 0), (0, 1, 1, 1), (0, 2, 1, 2)])
    >>> done[:, 1].tolist(), rest[:, 1].tolist()
    ([2.0, 0.0], [1.0])
    """
    candidates = check_actions(actions) if actions is not None else np.zeros((0, 4))
    if estimate.pushes:
        done_ = [p.action for p in estimate.pushes if p.outcome != "failed"]
        executed = np.array(done_, dtype=float).reshape(-1, 4)
        if not len(candidates) or not len(executed):
            return executed, candidates
        done = (candidates[:, None, :] == executed[None, :, :]).all(axis=2).any(axis=1)
        return executed, candidates[~done]
    if actions is None:
        return np.zeros((0, 4)), candidates
    bad = [i for i in estimate.used if not 0 <= i < len(candidates)]
    if bad:
        raise ValueError(
            f"estimate.used indexes pushes {bad[:5]} beyond the {len(candidates)} actions given"
        )
    chosen = list(estimate.used)
    return candidates[chosen], np.delete(candidates, chosen, axis=0)


def evidence_of(estimate: Estimate, n_executed: int) -> np.ndarray:
    """Per executed push: did it carry evidence (its record's outcome; all, without records)."""
    outcomes = [p.outcome for p in estimate.pushes if p.outcome != "failed"]
    if len(outcomes) != n_executed:
        return np.ones(n_executed, bool)
    return np.array([o == "evidence" for o in outcomes], bool)


def is_active(estimate: Estimate) -> bool:
    """An active run (it chose and executed its pushes), not the offline posterior."""
    return estimate.posterior is not None and estimate.posterior.pose is not None


def belief_of(estimate: Estimate) -> tuple[str, np.ndarray | None]:
    """What to colour the object with: ``("posterior" | "heatmap", array)`` or ``("region", None)``.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> belief_of(comcore.Estimate((1.0, 1.0), (0.0, 0.0), np.ones((3, 3), bool)))
    ('region', None)
    """
    if estimate.posterior is not None:
        return "posterior", np.asarray(estimate.posterior.image, float)
    if estimate.heatmap is not None:
        return "heatmap", np.asarray(estimate.heatmap.image, float)
    return "region", None


def number_positions(pushes, size: float, avoid=()) -> np.ndarray:
    """Where to write each push's number: behind its start, on its own line, apart.

    A push starts outside the object, so its number goes on the push's line
    just behind the start: outside the object, clear of the estimate and the
    truth (inside it), and read with its arrow. Pushes are placed in order; a
    number that would touch one already placed, or a point of ``avoid``, moves
    further back along its line (at most ``MAX_STEPS`` steps; where every
    place touches something, the one farthest from the others).

    Parameters
    ----------
    pushes : array_like, shape (n, 4)
    size : float
        A number's diameter in data units (pixels).
    avoid : array_like, shape (m, 2), optional
        Points the numbers keep ``size`` away from (the markers).

    Returns
    -------
    numpy.ndarray, shape (n, 2)

    Examples
    --------
    Two pushes from the same start: the second number steps back along its line.

    >>> number_positions([(0, 0, 10, 0), (0, 0, 10, 0)], size=2.0).tolist()
    [[-1.0, 0.0], [-3.0, 0.0]]
    """
    pushes = np.asarray(pushes, float).reshape(-1, 4)
    taken = np.asarray(avoid, float).reshape(-1, 2)
    out = np.zeros((len(pushes), 2))
    steps = 0.5 + np.arange(MAX_STEPS + 1)
    for k, (sx, sy, ex, ey) in enumerate(pushes):
        back = -np.array([ex - sx, ey - sy]) / max(float(np.hypot(ex - sx, ey - sy)), 1e-12)
        places = np.array([sx, sy]) + steps[:, None] * size * back  # (steps, 2)
        if len(taken):
            gap = np.hypot(*(places[:, None] - taken[None]).transpose(2, 0, 1)).min(axis=1)
        else:
            gap = np.full(len(places), np.inf)
        free = np.flatnonzero(gap >= size)
        out[k] = places[free[0] if len(free) else int(np.argmax(gap))]
        taken = np.vstack([taken, out[k]])
    return out


def region_outline(region) -> np.ndarray:
    """The outline of a pixel region along the pixels' edges, as line segments.

    Parameters
    ----------
    region : array_like of bool, shape (H, W)

    Returns
    -------
    numpy.ndarray, shape (k, 2, 2)
        Each segment's two ends ``(x, y)`` in pixels (a pixel's edges lie half a
        pixel from its centre): a matplotlib ``LineCollection``'s segments.

    Examples
    --------
    One pixel has four edges:

    >>> region_outline([[False, True]]).tolist()
    [[[0.5, -0.5], [0.5, 0.5]], [[1.5, -0.5], [1.5, 0.5]], [[0.5, -0.5], [1.5, -0.5]], [[0.5, 0.5], [1.5, 0.5]]]
    """  # noqa: E501
    padded = np.pad(np.asarray(region, bool), 1)
    rows, cols = np.nonzero(padded[:, 1:] != padded[:, :-1])  # an edge right of (row, col)
    x, y = cols - 0.5, rows - 1.0
    vertical = np.stack([np.column_stack([x, y - 0.5]), np.column_stack([x, y + 0.5])], axis=1)
    rows, cols = np.nonzero(padded[1:, :] != padded[:-1, :])  # an edge below (row, col)
    x, y = cols - 1.0, rows - 0.5
    horizontal = np.stack([np.column_stack([x - 0.5, y]), np.column_stack([x + 0.5, y])], axis=1)
    return np.concatenate([vertical, horizontal]).astype(float)


def window(mask: Mask, pushes: np.ndarray, view: str) -> tuple[float, float, float, float]:
    """``(x0, x1, y0, y1)`` of the axes: the object and its pushes, or the whole image."""
    h, w = mask.shape
    if view == "image":
        x0, x1, y0, y1 = -0.5, w - 0.5, -0.5, h - 0.5
        if len(pushes):  # widened to the push starts that lie near the image
            margin = 0.25 * max(h, w)
            xs, ys = pushes[:, [0, 2]], pushes[:, [1, 3]]
            x0 = max(min(x0, xs.min() - 1), -0.5 - margin)
            x1 = min(max(x1, xs.max() + 1), w - 0.5 + margin)
            y0 = max(min(y0, ys.min() - 1), -0.5 - margin)
            y1 = min(max(y1, ys.max() + 1), h - 0.5 + margin)
        return x0, x1, y0, y1
    rows, cols = np.nonzero(mask.data)
    x0, x1 = cols.min() - 0.5, cols.max() + 0.5
    y0, y1 = rows.min() - 0.5, rows.max() + 0.5
    if len(pushes):
        reach = PUSH_REACH * max(x1 - x0, y1 - y0)
        xs = np.clip(pushes[:, [0, 2]], x0 - reach, x1 + reach)
        ys = np.clip(pushes[:, [1, 3]], y0 - reach, y1 + reach)
        x0, x1 = min(x0, xs.min()), max(x1, xs.max())
        y0, y1 = min(y0, ys.min()), max(y1, ys.max())
    pad = max(MARGIN * max(x1 - x0, y1 - y0), MIN_MARGIN_PX)
    return x0 - pad, x1 + pad, y0 - pad, y1 + pad
