"""Everything a benchmark run leaves in its output folder."""

from __future__ import annotations

import dataclasses
import json
import os
import platform
import sys
from pathlib import Path

from ._figures import figure_errors, figure_heatmap, figure_pushes, figure_segmentation
from ._io import write_rows
from ._registry import parse_estimator
from ._report import markdown_report
from ._runner import BenchConfig, BenchResult
from ._trial import TrialSpec, run_trial

__all__ = ["example_trial", "machine_description", "save_benchmark"]

#: The object of the paper's Figs. 5 and 6, shown when the run includes it.
FIGURE_OBJECT = "Obj19"


def machine_description() -> str:
    """CPU model, core count, OS and Python version of this machine."""
    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            model = next(line.split(":", 1)[1].strip() for line in f if "model name" in line)
    except (OSError, StopIteration):
        pass
    return (
        f"{os.cpu_count()} CPU cores ({model}), {platform.system()}, "
        f"Python {sys.version.split()[0]}"
    )


def example_trial(config: BenchConfig, trial: int = 0):
    """Re-run one trial of ``config`` with Alg. 1 kept (for Figs. 5 and 6).

    The trial is the first of ``Obj19`` (the paper's example object) if the
    run includes it, else of the first object; trials are deterministic, so
    it is the very trial of the results.
    """
    obj = FIGURE_OBJECT if FIGURE_OBJECT in config.objects else config.objects[0]
    label = next((e for e in config.estimators if parse_estimator(e)[0].name == "alg1"), "alg1")
    spec = TrialSpec(
        obj,
        config.frictions[0],
        trial,
        config.seed,
        config.predictor,
        (label,),
        config.candidates,
        config.cone,
    )
    return run_trial(spec, keep=True), label


def save_benchmark(
    result: BenchResult,
    out,
    *,
    fmt: str = "jsonl",
    command: str = "",
    figures: bool = True,
) -> dict[str, Path]:
    """Write results, ``run.json``, figures and ``report.md`` into the folder ``out``.

    Returns
    -------
    dict
        ``{"results": path, "meta": path, "report": path, <figure name>: path}``.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"results": write_rows(result.rows, out / f"results.{fmt}")}
    meta = {
        "command": command,
        "config": dataclasses.asdict(result.config),
        "wall_s": result.wall_s,
        "cpu_s": result.cpu_s,
        "workers": result.workers if result.dask is None else f"dask {result.dask}",
        "machine": machine_description(),
        "skipped": result.skipped,
        "rows": len(result.rows),
    }
    paths["meta"] = out / "run.json"
    paths["meta"].write_text(json.dumps(meta, indent=2) + "\n", encoding="utf-8")
    captions: dict[str, str] = {}
    if figures and result.rows:
        estimators = {parse_estimator(e)[0].name for e in result.config.estimators}
        if "alg1" in estimators and result.config.candidates > 0:
            outcome, label = example_trial(result.config)
            paths["fig5"] = figure_heatmap(outcome, out / "bench_fig5_heatmap.png", label)
            paths["fig6"] = figure_segmentation(outcome, out / "bench_fig6_segmentation.png", label)
            captions["Fig. 5: Alg. 1 heat map of one trial"] = "bench_fig5_heatmap.png"
            captions["Fig. 6: Alg. 1 segmentation of the same trial"] = (
                "bench_fig6_segmentation.png"
            )
        if {"alg2", "alg2-rotation"} <= set(result.config.estimators):
            paths["fig7"] = figure_pushes(result.rows, out / "bench_fig7_pushes.png")
            captions["Fig. 7: pushes used, equality score vs rotation order"] = (
                "bench_fig7_pushes.png"
            )
        paths["errors"] = figure_errors(result.rows, out / "bench_error_per_object.png")
        captions["Error per object and estimator"] = "bench_error_per_object.png"
    paths["report"] = out / "report.md"
    paths["report"].write_text(markdown_report(result.rows, meta, captions), encoding="utf-8")
    return paths
