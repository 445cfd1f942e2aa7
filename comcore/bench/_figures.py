"""Figures of the report (matplotlib, PNG): the paper's Figs. 5-7 and error per object."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ._io import paper_table
from ._report import group_stats
from ._trial import TrialOutcome

__all__ = ["figure_errors", "figure_heatmap", "figure_pushes", "figure_segmentation"]


def _figure(width: float, height: float):
    try:
        from matplotlib.figure import Figure
    except ImportError as e:
        raise ImportError("figures need matplotlib: pip install comcore[plot]") from e
    return Figure(figsize=(width, height), dpi=110, layout="constrained")


def _crop(mask_data: np.ndarray, margin: int = 3) -> tuple[slice, slice]:
    rows, cols = np.nonzero(mask_data)
    h, w = mask_data.shape
    return (
        slice(max(rows.min() - margin, 0), min(rows.max() + margin + 1, h)),
        slice(max(cols.min() - margin, 0), min(cols.max() + margin + 1, w)),
    )


def _markers(ax, outcome: TrialOutcome, estimate, window) -> None:
    ys, xs = window
    true = outcome.context.simulator.com_px
    ax.plot(true[0] - xs.start, true[1] - ys.start, "g+", ms=14, mew=2.5, label="true CoM")
    ax.plot(
        estimate.com[0] - xs.start,
        estimate.com[1] - ys.start,
        "rx",
        ms=11,
        mew=2.5,
        label="estimate",
    )


def _caption(outcome: TrialOutcome, estimate) -> str:
    ctx = outcome.context
    err = estimate.error_px(ctx.simulator.com_px)
    cm = err * ctx.mask.resolution * 100
    trial = f"{ctx.object} ({ctx.friction} friction, trial {ctx.trial})"
    return f"{trial}: error {err:.2f} px = {cm:.2f} cm"


def _heatmap_of(outcome: TrialOutcome, estimator: str):
    """The estimator's estimate and its :class:`comcore.paper.HeatmapDetails` (Alg. 1's)."""
    est = outcome.estimates[estimator]
    if est.heatmap is None:
        raise ValueError(f"estimator {estimator!r} has no heat map (Alg. 1's, 'alg1', has)")
    return est, est.heatmap


def figure_heatmap(outcome: TrialOutcome, path, estimator: str = "alg1") -> Path:
    """Fig. 5: the normalised heat map S of Alg. 1 for one trial, with both CoMs."""
    est, details = _heatmap_of(outcome, estimator)
    heat = np.asarray(details.image, float)
    data = outcome.context.mask.data
    window = _crop(data)
    aspect = (window[0].stop - window[0].start) / (window[1].stop - window[1].start)
    fig = _figure(6.5, 5.0 * aspect + 1.6)
    ax = fig.add_subplot()
    shown = np.ma.masked_where(~data, heat)[window]
    image = ax.imshow(shown, cmap="viridis", vmin=0, vmax=1, interpolation="nearest")
    fig.colorbar(image, ax=ax, label="normalised $S_\\theta$", shrink=0.9)
    _markers(ax, outcome, est, window)
    ax.set_title("Alg. 1 heat map: " + _caption(outcome, est), fontsize=9)
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncol=2, fontsize=8)
    ax.set_xlabel("x (pixels)")
    ax.set_ylabel("y (pixels, down)")
    fig.savefig(path)
    return Path(path)


def figure_segmentation(outcome: TrialOutcome, path, estimator: str = "alg1") -> Path:
    """Fig. 6: the thresholded pixels (top) and the largest connected region (bottom)."""
    est, details = _heatmap_of(outcome, estimator)
    data = outcome.context.mask.data
    window = _crop(data)
    aspect = (window[0].stop - window[0].start) / (window[1].stop - window[1].start)
    fig = _figure(5.5, 2 * 5.0 * aspect + 1.8)
    layers = (
        ("segmented points", details.segmented),
        ("largest connected region", est.region),
    )
    for k, (title, chosen) in enumerate(layers):
        ax = fig.add_subplot(2, 1, k + 1)
        image = data.astype(float) * 0.35 + np.asarray(chosen, float) * 0.65
        ax.imshow(image[window], cmap="Greys", vmin=0, vmax=1, interpolation="nearest")
        _markers(ax, outcome, est, window)
        ax.set_title(title, fontsize=10)
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncol=2, fontsize=8)
    fig.suptitle(_caption(outcome, est), fontsize=9)
    fig.savefig(path)
    return Path(path)


def _objects(rows: Sequence[Mapping]) -> list[str]:
    return list(dict.fromkeys(r["object"] for r in rows))


def _frictions(rows: Sequence[Mapping]) -> list[str]:
    return [f for f in ("low", "high") if any(r["friction"] == f for r in rows)]


def figure_pushes(
    rows: Sequence[Mapping], path, proposed: str = "alg2", ablation: str = "alg2-rotation"
) -> Path:
    """Fig. 7: mean, min and max pushes per object, equality score (dashed) vs rotation order."""
    stats = group_stats(rows)
    objects, frictions = _objects(rows), _frictions(rows)
    fig = _figure(8.0, 3.2 * len(frictions) + 0.6)
    x = np.arange(1, len(objects) + 1)
    for k, friction in enumerate(frictions):
        ax = fig.add_subplot(len(frictions), 1, k + 1)
        for name, style, color in ((proposed, "--", "C0"), (ablation, "-", "C3")):
            cells = [stats.get((name, o, friction)) for o in objects]
            if not all(cells):
                continue
            for stat, marker in (("mean", "o"), ("min", "v"), ("max", "^")):
                values = [c["pushes"][stat] for c in cells]  # type: ignore[index]
                label = f"{name} {stat}"
                ax.plot(x, values, style, color=color, marker=marker, ms=4, label=label)
        paper = paper_table(2)
        if all(o in paper for o in objects):
            values = [paper[o][f"{friction}_push_mean"] for o in objects]
            ax.plot(x, values, ":", color="k", marker="s", ms=3, label="paper's Alg. 2 mean")
        ax.set_xticks(x, objects, rotation=60, fontsize=7)
        ax.set_ylabel("pushes used")
        ax.set_title(
            f"{friction} friction: equality score (dashed) vs rotation order (solid)", fontsize=9
        )
        ax.grid(alpha=0.3)
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncol=4, fontsize=7)
    fig.savefig(path)
    return Path(path)


def figure_errors(rows: Sequence[Mapping], path) -> Path:
    """Mean error per object (bars: one standard deviation) for every estimator.

    Black markers: the paper's mean error of Alg. 1 (Table I) and Alg. 2 (Table II)
    above the bars of ``alg1`` and ``alg2``.
    """
    stats = group_stats(rows)
    objects, frictions = _objects(rows), _frictions(rows)
    estimators = list(dict.fromkeys(r["estimator"] for r in rows))
    fig = _figure(9.0, 3.4 * len(frictions) + 0.5)
    x = np.arange(len(objects))
    width = 0.8 / max(len(estimators), 1)
    for k, friction in enumerate(frictions):
        ax = fig.add_subplot(len(frictions), 1, k + 1)
        for j, name in enumerate(estimators):
            cells = [stats.get((name, o, friction)) for o in objects]
            ran = [c if c and c["error"]["mean"] is not None else None for c in cells]
            mean = [c["error"]["mean"] if c else np.nan for c in ran]
            std = [c["error"]["std"] if c else 0.0 for c in ran]
            offset = x + (j - (len(estimators) - 1) / 2) * width
            ax.bar(offset, mean, width, yerr=std, label=name, capsize=1.5, error_kw={"lw": 0.6})
            table, column = {"alg1": (1, "{}_mean_cm"), "alg2": (2, "{}_err_mean_cm")}.get(
                name, (0, "")
            )
            if table:
                paper = paper_table(table)
                values = [
                    paper[o][column.format(friction)] if o in paper else np.nan for o in objects
                ]
                marker = "k_" if table == 1 else "k*"
                label = f"paper's {'Alg. 1' if table == 1 else 'Alg. 2'} mean"
                ax.plot(offset, values, marker, ms=7, mew=1.5, label=label)
        ax.set_xticks(x, objects, rotation=60, fontsize=7)
        ax.set_ylabel("error (cm)")
        ax.set_title(f"{friction} friction: CoM error per object (mean ± std)", fontsize=9)
        ax.grid(axis="y", alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=min(len(labels), 6), fontsize=7)
    fig.savefig(path)
    return Path(path)
