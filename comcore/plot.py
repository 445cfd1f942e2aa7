"""Pictures of estimates (matplotlib: ``pip install comcore[plot]``).

Not imported by ``import comcore``; import it explicitly::

    import comcore.plot

:func:`plot_estimate` draws any estimator's :class:`~comcore.Estimate` on its
mask: the mask, the pushes (the executed ones numbered in order), what the
estimator believes (Alg. 1's heat map, the active and offline posteriors, or
the CoM region), the estimate and, if given, the true CoM. It draws on a
``matplotlib.figure.Figure`` it creates (no pyplot, no global state) unless an
``ax`` is passed.

Examples
--------
>>> import numpy as np, comcore, comcore.plot
>>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
>>> actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
>>> motions = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)]
>>> est = comcore.estimate_progressive(mask, actions, motions)
>>> ax = comcore.plot.plot_estimate(mask, est, actions=actions, truth=(10.5, 10.5))
>>> ax.get_title()
'Alg. 2 region: CoM (10.5, 10.5) px, 4 of 4 pushes used'
>>> ax.figure.savefig("estimate.png")  # doctest: +SKIP
"""

from __future__ import annotations

import numpy as np

try:
    from matplotlib.figure import Figure
except ImportError as e:  # pragma: no cover - exercised by tests through sys.modules
    raise ImportError("comcore.plot needs matplotlib: pip install comcore[plot]") from e

from ._mask import Mask
from ._types import Estimate
from ._validation import check_actions, check_mask, check_point

__all__ = ["belief_of", "executed_pushes", "plot_estimate"]

#: Up to this many executed pushes are numbered in order (more would hide the picture).
MAX_NUMBERED = 15
#: The posterior is drawn on a log scale down to this fraction of its maximum.
POSTERIOR_FLOOR = 1e-4
#: Colours of the picture's elements.
COLORS = {
    "object": (0.78, 0.78, 0.78),
    "region": (1.0, 0.62, 0.18),
    "used": "tab:red",
    "other": "tab:blue",
    "no_evidence": "tab:gray",
    "estimate": "black",
    "truth": "tab:green",
}


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


def _evidence(estimate: Estimate, n_executed: int) -> np.ndarray:
    """Per executed push: did it carry evidence (its record's outcome; all, without records)."""
    outcomes = [p.outcome for p in estimate.pushes if p.outcome != "failed"]
    if len(outcomes) != n_executed:
        return np.ones(n_executed, bool)
    return np.array([o == "evidence" for o in outcomes], bool)


def _is_active(estimate: Estimate) -> bool:
    """An active run (it chose and executed its pushes), not the offline posterior."""
    return "pose" in estimate.extras


def belief_of(estimate: Estimate) -> tuple[str, np.ndarray | None]:
    """What to colour the object with: ``("posterior" | "heatmap", array)`` or ``("region", None)``.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> belief_of(comcore.Estimate((1.0, 1.0), (0.0, 0.0), np.ones((3, 3), bool)))
    ('region', None)
    """
    for key in ("posterior", "heatmap"):
        if key in estimate.extras:
            return key, np.asarray(estimate.extras[key], float)
    return "region", None


def _name(estimate: Estimate, belief: str) -> str:
    if _is_active(estimate):
        return "active posterior"
    if belief == "posterior":
        return "posterior"
    if belief == "heatmap":
        return "Alg. 1 heat map"
    return "Alg. 2 region" if estimate.used else "region"


def _arrows(ax, pushes: np.ndarray, color, numbered: bool, **style) -> None:
    colors = [color] * len(pushes) if isinstance(color, str) else list(color)
    for k, ((sx, sy, ex, ey), color) in enumerate(zip(pushes, colors)):
        ax.annotate(
            "", (ex, ey), (sx, sy),
            arrowprops={"arrowstyle": "-|>", "color": color, "lw": style.get("lw", 1.4),
                        "alpha": style.get("alpha", 1.0), "shrinkA": 0, "shrinkB": 0},
        )  # fmt: skip
        if numbered:
            ax.text(sx, sy, str(k + 1), color="white", fontsize=7, ha="center", va="center",
                    bbox={"boxstyle": "circle,pad=0.2", "fc": color, "ec": "none"})  # fmt: skip


def _marker(ax, point, marker: str, color, label: str) -> None:
    """A cross with a white halo, readable on the grey mask and on a dark heat map."""
    ax.plot(*point, marker, color="white", ms=14, mew=5.0)
    ax.plot(*point, marker, color=color, ms=12, mew=2.5, label=label)


def _legend_pushes(ax, evidence: np.ndarray, n_others: int, executed: bool) -> None:
    """Legend entries for the arrows (annotations have none of their own)."""
    from matplotlib.lines import Line2D

    if evidence.any():
        what = "pushes executed" if executed else "pushes used"
        if len(evidence) <= MAX_NUMBERED:
            what += ", numbered in order"
        ax.add_line(Line2D([], [], color=COLORS["used"], marker=">", label=what))
    if not evidence.all():
        label = "pushes without evidence (missed or failed)"
        ax.add_line(Line2D([], [], color=COLORS["no_evidence"], marker=">", label=label))
    if n_others:
        label = "candidates not executed" if executed else "pushes not used"
        ax.add_line(Line2D([], [], color=COLORS["other"], alpha=0.45, label=label))


def plot_estimate(
    mask: Mask,
    estimate: Estimate,
    *,
    actions=None,
    truth=None,
    ax=None,
    title: str | None = None,
):
    """Draw an estimate on its mask: belief, pushes, estimate and truth.

    Parameters
    ----------
    mask : Mask
        The mask the estimate was computed on (for an active estimate, the first mask).
    estimate : Estimate
        Any estimator's result. The object is coloured by ``extras["posterior"]``
        (active and offline posterior) or ``extras["heatmap"]`` (Alg. 1) where
        present, with the CoM region outlined; otherwise the region is filled.
    actions : array_like, shape (n, 4), optional
        The pushes the estimator was given (the candidates); ``estimate.used``
        indexes them. Drawn faint blue where not used.
    truth : (float, float), optional
        The true CoM in pixels, drawn as a green cross.
    ax : matplotlib.axes.Axes, optional
        Where to draw; by default a new ``Figure``'s axes (``ax.figure.savefig``).
    title : str, optional
        Replaces the default title (estimator kind, CoM, pushes used).

    Returns
    -------
    matplotlib.axes.Axes

    Raises
    ------
    ValueError
        If the mask and the estimate's region differ in shape, or ``used``
        indexes pushes beyond ``actions``.

    Examples
    --------
    >>> import numpy as np, comcore, comcore.plot
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> est = comcore.Estimate(mask.centroid, mask.centroid_m, mask.data)
    >>> ax = comcore.plot.plot_estimate(mask, est, truth=(12.0, 9.0), title="centroid")
    >>> ax.get_title(), [t.get_text() for t in ax.get_legend().get_texts()]
    ('centroid', ['estimate (13.5, 13.5)', 'true CoM (12.0, 9.0)'])
    """
    mask = check_mask(mask)
    if not isinstance(estimate, Estimate):
        raise TypeError(f"estimate must be a comcore.Estimate, got {type(estimate).__name__}")
    if estimate.region.shape != mask.shape:
        raise ValueError(
            f"estimate.region has shape {estimate.region.shape}, the mask {mask.shape}: "
            "pass the mask the estimate was computed on"
        )
    executed, others = executed_pushes(estimate, actions)
    if ax is None:
        h, w = mask.shape
        fig = Figure(figsize=(6.0, min(6.0 * h / max(w, 1), 9.0) + 0.9), dpi=110,
                     layout="constrained")  # fmt: skip
        ax = fig.add_subplot()
    belief, values = belief_of(estimate)
    image = np.ones((*mask.shape, 3))
    image[mask.data] = COLORS["object"]
    if values is None:
        image[estimate.region & mask.data] = COLORS["region"]
    ax.imshow(image, interpolation="nearest")
    if values is not None and values.shape == mask.shape:
        shown = np.ma.masked_where(~mask.data, values / max(float(np.nanmax(values)), 1e-300))
        if belief == "posterior":  # a posterior spans decades: a log scale shows its shape
            from matplotlib.colors import LogNorm

            norm, label = LogNorm(POSTERIOR_FLOOR, 1.0, clip=True), "posterior / its maximum"
        else:
            norm, label = None, "normalised heat map"
        kwargs = {"norm": norm} if norm is not None else {"vmin": 0, "vmax": 1}
        picture = ax.imshow(shown, cmap="viridis", interpolation="nearest", **kwargs)
        ax.figure.colorbar(picture, ax=ax, shrink=0.8, label=label)
    if estimate.region.any() and not estimate.region.all():
        ax.contour(estimate.region.astype(float), levels=[0.5], colors=[COLORS["region"]],
                   linewidths=1.5)  # fmt: skip
    _arrows(ax, others, COLORS["other"], False, lw=0.8, alpha=0.45)
    evidence = _evidence(estimate, len(executed))
    colors = [COLORS["used"] if e else COLORS["no_evidence"] for e in evidence]
    _arrows(ax, executed, colors, len(executed) <= MAX_NUMBERED)
    _legend_pushes(ax, evidence, len(others), "actions" in estimate.extras)
    x, y = estimate.com
    _marker(ax, (x, y), "x", COLORS["estimate"], f"estimate ({x:.1f}, {y:.1f})")
    if truth is not None:
        tx, ty = check_point(truth, "truth")
        _marker(ax, (tx, ty), "+", COLORS["truth"], f"true CoM ({tx:.1f}, {ty:.1f})")
    _limits(ax, mask, np.vstack([executed, others]))
    ax.set_xlabel("x (pixels)")
    ax.set_ylabel("y (pixels, down)")
    n_all = len(executed) + len(others)
    used = f"{len(executed)} of {n_all} pushes used" if n_all else "no push"
    if _is_active(estimate):
        used = f"{len(executed)} pushes executed"
    if title is None:
        title = f"{_name(estimate, belief)}: CoM ({x:.1f}, {y:.1f}) px, {used}"
    ax.set_title(title, fontsize=9, wrap=True)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), fontsize=8, ncol=2)
    return ax


def _limits(ax, mask: Mask, pushes: np.ndarray) -> None:
    """The image, widened to the push starts that lie near it."""
    h, w = mask.shape
    x0, x1, y0, y1 = -0.5, w - 0.5, -0.5, h - 0.5
    if len(pushes):
        margin = 0.25 * max(h, w)
        xs, ys = pushes[:, [0, 2]], pushes[:, [1, 3]]
        x0 = max(min(x0, xs.min() - 1), -0.5 - margin)
        x1 = min(max(x1, xs.max() + 1), w - 0.5 + margin)
        y0 = max(min(y0, ys.min() - 1), -0.5 - margin)
        y1 = min(max(y1, ys.max() + 1), h - 0.5 + margin)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y1, y0)
