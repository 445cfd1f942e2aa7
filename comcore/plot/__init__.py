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
'Alg. 2 region: CoM (10.5, 10.5) px, 4 of 4 pushes used, status wide'
>>> ax.figure.savefig("estimate.png")  # doctest: +SKIP
"""

from __future__ import annotations

import numpy as np

try:
    from matplotlib.figure import Figure
except ImportError as e:  # pragma: no cover - exercised by tests through sys.modules
    raise ImportError("comcore.plot needs matplotlib: pip install comcore[plot]") from e

from .._mask import Mask
from .._types import Estimate
from .._validation import check_mask, check_point
from ._layout import belief_of, executed_pushes, is_active, number_positions, region_outline
from ._layout import evidence_of as _evidence
from ._layout import window as _window

__all__ = ["belief_of", "executed_pushes", "number_positions", "plot_estimate", "region_outline"]

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
#: Drawing order: the object and belief, then arrows, then the region's outline, the
#: markers and, on top, the push numbers (placed where they hide neither).
ZORDER = {"arrows": 3, "other_arrows": 2.5, "region": 3.5, "markers": 5, "numbers": 6}


def _name(estimate: Estimate, belief: str) -> str:
    if is_active(estimate):
        return "active posterior"
    if belief == "posterior":
        return "posterior"
    if belief == "heatmap":
        return "Alg. 1 heat map"
    return "Alg. 2 region" if estimate.used else "region"


def _arrows(ax, pushes: np.ndarray, color, **style) -> None:
    colors = [color] * len(pushes) if isinstance(color, str) else list(color)
    for (sx, sy, ex, ey), color in zip(pushes, colors):
        arrow = {"arrowstyle": "-|>", "color": color, "lw": style.get("lw", 1.4)}
        arrow.update(alpha=style.get("alpha", 1.0), shrinkA=0, shrinkB=0)
        ax.annotate(
            "", (ex, ey), (sx, sy), zorder=style.get("zorder", ZORDER["arrows"]), arrowprops=arrow
        )


def _numbers(ax, pushes: np.ndarray, colors, places: np.ndarray, fontsize: float, labels) -> None:
    """Number the pushes (white on the arrow's colour) at ``places``: ``labels``, or 1, 2, ..."""
    for k, (point, push, color) in enumerate(zip(places, pushes, colors)):
        line = ([point[0], push[0]], [point[1], push[1]])
        ax.plot(*line, "-", color=color, lw=0.6, alpha=0.5, zorder=ZORDER["arrows"])
        bbox = {"boxstyle": "circle,pad=0.2", "fc": color, "ec": "white", "lw": 0.6}
        text = str(k + 1 if labels is None else labels[k])
        style = {"ha": "center", "va": "center", "zorder": ZORDER["numbers"], "bbox": bbox}
        ax.text(*point, text, color="white", fontsize=fontsize, clip_on=True, **style)


def _marker(ax, point, marker: str, color, label: str) -> None:
    """A cross with a white halo, readable on the grey mask and on a dark heat map."""
    ax.plot(*point, marker, color="white", ms=14, mew=5.0, zorder=ZORDER["markers"])
    ax.plot(*point, marker, color=color, ms=12, mew=2.5, label=label, zorder=ZORDER["markers"])


def _legend_pushes(ax, evidence: np.ndarray, n_others: int, executed: bool) -> None:
    """Legend entries for the arrows (annotations have none of their own)."""
    from matplotlib.lines import Line2D

    if evidence.any():
        what = "pushes executed" if executed else "pushes used"
        ax.add_line(Line2D([], [], color=COLORS["used"], marker=">", label=what + ", in order"))
    if not evidence.all():
        label = "pushes without evidence (missed or failed)"
        ax.add_line(Line2D([], [], color=COLORS["no_evidence"], marker=">", label=label))
    if n_others:
        label = "candidates not executed" if executed else "pushes not used"
        ax.add_line(Line2D([], [], color=COLORS["other"], alpha=0.45, label=label))


def _region_label(estimate: Estimate, belief: str, credible) -> str:
    """What the outlined region is: a credible region, at ``credible`` or the share it holds.

    The share is read from ``posterior.region_image``, what the region was read from (the
    posterior blurred by a systematic error, or bagged): in the posterior itself the region
    holds more than its level (97 % for a 90 % region, say).
    """
    if belief == "posterior" and credible is not None:
        return f"{100 * credible:.0f} % credible region"
    source = None if estimate.posterior is None else estimate.posterior.region_image
    if belief == "posterior" and source is not None and source.shape == estimate.region.shape:
        total = float(source.sum())
        if total > 0:
            share = float(source[estimate.region].sum()) / total
            return f"{100 * share:.0f} % credible region"
    if belief == "heatmap":
        return "calm region (Alg. 1)"
    return "CoM region"


def plot_estimate(
    mask: Mask,
    estimate: Estimate,
    *,
    actions=None,
    truth=None,
    ax=None,
    title: str | None = None,
    view: str = "object",
    credible: float | None = None,
    numbers=None,
):
    """Draw an estimate on its mask: belief, pushes numbered in order, region, estimate, truth.

    Parameters
    ----------
    mask : Mask
        The mask the estimate was computed on (for an active estimate, the first mask).
    estimate : Estimate
        Any estimator's result. The object is coloured by ``posterior.image`` (log
        scale) or ``heatmap.image`` where present, else the region is filled; the
        region is outlined in every case.
    actions : array_like, shape (n, 4), optional
        The pushes the estimator was given (the candidates); ``estimate.used``
        indexes them. Drawn faint blue where not used.
    truth : (float, float), optional
        The true CoM in pixels, drawn as a green cross.
    ax : matplotlib.axes.Axes, optional
        Where to draw; by default a new ``Figure``'s axes sized to the window.
    title : str, optional
        Replaces the default title (estimator kind, CoM, pushes, status if not ok).
    view : {"object", "image"}, optional
        ``"object"`` (default): the object and the pushes (followed at most
        ``PUSH_REACH`` object sizes past it), so that a small object in a wide
        frame is drawn large. ``"image"``: the whole image.
    credible : float, optional
        The level the posterior's credible region was read at (e.g. 0.9), for
        the legend. Default: the share of ``posterior.region_image`` it holds.
    numbers : sequence of int, shape (k,), optional
        The number written on each push the estimate rests on, in order
        (:func:`executed_pushes`), e.g. CSV lines. Default 1, 2, ..., k.

    Returns
    -------
    matplotlib.axes.Axes

    Raises
    ------
    ValueError
        If the mask and the region differ in shape, ``used`` indexes pushes
        beyond ``actions``, or ``view`` is unknown.

    Examples
    --------
    >>> import numpy as np, comcore, comcore.plot
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> est = comcore.Estimate(mask.centroid, mask.centroid_m, mask.data)
    >>> ax = comcore.plot.plot_estimate(mask, est, truth=(12.0, 9.0), title="centroid")
    >>> ax.get_title(), [t.get_text() for t in ax.get_legend().get_texts()]
    ('centroid', ['CoM region', 'estimate (13.5, 13.5)', 'true CoM (12.0, 9.0)'])

    A small object in a wide camera frame is framed, not lost:

    >>> frame = np.zeros((400, 600), bool)
    >>> frame[200:220, 300:330] = True
    >>> wide = comcore.Mask(frame)
    >>> est = comcore.Estimate(wide.centroid, wide.centroid_m, frame)
    >>> ax = comcore.plot.plot_estimate(wide, est)
    >>> [float(v) for v in (*ax.get_xlim(), *ax.get_ylim())]  # 3 px around the object
    [296.5, 332.5, 222.5, 196.5]
    """
    mask, executed, others = _checked(mask, estimate, actions, view, numbers)
    x0, x1, y0, y1 = _window(mask, np.vstack([executed, others]), view)
    if ax is None:
        height = min(max(6.0 * (y1 - y0) / max(x1 - x0, 1e-9), 3.0), 9.0)
        fig = Figure(figsize=(6.0, height + 0.9), dpi=110, layout="constrained")
        ax = fig.add_subplot()
    belief = _draw_belief(ax, mask, estimate)
    _draw_region(ax, estimate, belief, credible)
    _arrows(ax, others, COLORS["other"], lw=0.8, alpha=0.45, zorder=ZORDER["other_arrows"])
    evidence = _evidence(estimate, len(executed))
    colors = [COLORS["used"] if e else COLORS["no_evidence"] for e in evidence]
    _arrows(ax, executed, colors)
    _legend_pushes(ax, evidence, len(others), bool(estimate.pushes))
    x, y = estimate.com
    markers = [(x, y)]
    _marker(ax, (x, y), "x", COLORS["estimate"], f"estimate ({x:.1f}, {y:.1f})")
    if truth is not None:
        tx, ty = check_point(truth, "truth")
        markers.append((tx, ty))
        _marker(ax, (tx, ty), "+", COLORS["truth"], f"true CoM ({tx:.1f}, {ty:.1f})")
    places, fontsize, (x0, x1, y0, y1) = _number_layout(ax, executed, markers, (x0, x1, y0, y1))
    _numbers(ax, executed, colors, places, fontsize, numbers)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y1, y0)
    if title is None:
        title = _title(estimate, belief, len(executed), len(others))
    _label(ax, title)
    return ax


def _checked(mask, estimate, actions, view, numbers):
    """The checked mask, and the pushes drawn numbered and the others (:func:`plot_estimate`)."""
    mask = check_mask(mask)
    if not isinstance(estimate, Estimate):
        raise TypeError(f"estimate must be a comcore.Estimate, got {type(estimate).__name__}")
    if estimate.region.shape != mask.shape:
        raise ValueError(
            f"estimate.region has shape {estimate.region.shape}, the mask {mask.shape}: "
            "pass the mask the estimate was computed on"
        )
    if view not in ("object", "image"):
        raise ValueError(f"view must be 'object' or 'image', got {view!r}")
    executed, others = executed_pushes(estimate, actions)
    if numbers is not None and len(numbers) != len(executed):
        raise ValueError(
            f"numbers must hold one number per push drawn numbered ({len(executed)}: the "
            f"estimate's pushes, in order), got {len(numbers)}"
        )
    return mask, executed, others


def _draw_belief(ax, mask: Mask, estimate: Estimate) -> str:
    """The object coloured by the belief (or the region filled); the belief's kind."""
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
    return belief


def _draw_region(ax, estimate: Estimate, belief: str, credible) -> None:
    """The region's outline and its legend entry (none for an empty or a whole region)."""
    if not estimate.region.any() or estimate.region.all():
        return
    from matplotlib.collections import LineCollection
    from matplotlib.lines import Line2D

    outline = LineCollection(
        region_outline(estimate.region),
        colors=[COLORS["region"]],
        linewidths=2.0,
        zorder=ZORDER["region"],
        capstyle="projecting",
    )
    ax.add_collection(outline)
    region_label = _region_label(estimate, belief, credible)
    ax.add_line(Line2D([], [], color=COLORS["region"], lw=2.0, label=region_label))


def _title(estimate: Estimate, belief: str, n_executed: int, n_others: int) -> str:
    """The default title: estimator kind, CoM, pushes, and the status when it is not ``ok``."""
    x, y = estimate.com
    n_all = n_executed + n_others
    used = f"{n_executed} of {n_all} pushes used" if n_all else "no push"
    if is_active(estimate):
        used = f"{n_executed} pushes executed"
    title = f"{_name(estimate, belief)}: CoM ({x:.1f}, {y:.1f}) px, {used}"
    if not estimate.ok:
        title += f", status {estimate.status}"
    return title


def _label(ax, title: str) -> None:
    """Axis labels, the title, and the legend under the x label whatever the axes' height."""
    from matplotlib.transforms import ScaledTranslation

    ax.set_xlabel("x (pixels)")
    ax.set_ylabel("y (pixels, down)")
    ax.set_title(title, fontsize=9)
    below = ax.transAxes + ScaledTranslation(0.0, -0.45, ax.figure.dpi_scale_trans)
    ax.legend(
        loc="upper center", bbox_to_anchor=(0.5, 0.0), bbox_transform=below, fontsize=8, ncol=2
    )


def _number_layout(ax, pushes: np.ndarray, markers, window):
    """Numbers' places and font size; the window widened to hold them (sized as drawn)."""
    fontsize = 7.0 if len(pushes) <= 20 else 5.5
    if not len(pushes):
        return np.zeros((0, 2)), fontsize, window
    box = ax.get_window_extent()  # display pixels, before the final layout
    inches = max(min(box.width, box.height) / ax.figure.dpi, 0.5)
    circle_in = fontsize * 2.0 / 72.0  # a number's circle, inches (about)
    x0, x1, y0, y1 = base = window
    for _ in range(3):  # the window grows to hold the numbers; their size grows with it
        size = circle_in * max(x1 - x0, y1 - y0) / inches
        places = number_positions(pushes, size, markers)
        x0 = min(base[0], places[:, 0].min() - size)
        x1 = max(base[1], places[:, 0].max() + size)
        y0 = min(base[2], places[:, 1].min() - size)
        y1 = max(base[3], places[:, 1].max() + size)
    return places, fontsize, (x0, x1, y0, y1)
