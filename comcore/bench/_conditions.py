"""The benchmark under realism conditions (``--conditions``): the runs and their tables.

The conditions themselves (what each changes, how the trial's object answers
under it) are in :mod:`comcore.bench._realism`.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field, fields, replace

import numpy as np

from .._status import Status
from ._realism import CONDITIONS, Condition, parse_condition
from ._registry import parse_estimator, split_estimators
from ._report import STATUS_NOTE, status_cell
from ._runner import BenchConfig, BenchResult, run_benchmark
from ._trial import TrialSpec

__all__ = [
    "ConditionConfig",
    "conditions_table",
    "friction_table",
    "run_conditions",
    "run_conditions_command",
]


@dataclass(frozen=True)
class ConditionConfig(BenchConfig):
    """A :class:`~comcore.bench.BenchConfig` whose trials run under one condition."""

    condition: Condition = field(default_factory=lambda: CONDITIONS["exact"])

    def specs(self) -> list[TrialSpec]:
        """The config's trials, each under :attr:`condition`."""
        return [replace(s, condition=self.condition) for s in super().specs()]


def run_conditions(
    config: BenchConfig, conditions, *, workers: int = 1, progress: bool = False, on_rows=None
) -> tuple[dict[str, BenchResult], dict[str, dict[str, str]]]:
    """Run ``config``'s trials once per condition (the same trials in each).

    Parameters
    ----------
    config : BenchConfig
    conditions : str or sequence of str or Condition
        Condition labels (``"exact,pusher-error"``, ``"all"``) or :class:`Condition` objects.
    workers, progress, on_rows
        As for :func:`comcore.bench.run_benchmark`.

    Returns
    -------
    (dict, dict)
        ``{condition: BenchResult}`` and ``{condition: {estimator: why it was not run}}``.
    """
    if isinstance(conditions, str):
        conditions = list(CONDITIONS) if conditions == "all" else split_estimators(conditions)
    parsed = [c if isinstance(c, Condition) else parse_condition(c) for c in conditions]
    if not parsed:
        raise ValueError("conditions must name at least one condition")
    names = [c.name for c in parsed]
    if len(set(names)) != len(names):
        raise ValueError(f"conditions must be distinct, got {names}")
    results, unfit = {}, {}
    base = {f.name: getattr(config, f.name) for f in fields(BenchConfig)}
    for cond in parsed:
        keep, why = [], {}
        for label in config.estimators:
            reason = cond.fits(parse_estimator(label)[0])
            if reason:
                why[label] = reason
            else:
                keep.append(label)
        unfit[cond.name] = why
        if not keep:
            continue
        cfg = ConditionConfig(**{**base, "estimators": tuple(keep)}, condition=cond)
        results[cond.name] = run_benchmark(cfg, workers=workers, progress=progress, on_rows=on_rows)
    return results, unfit


def conditions_table(results, unfit=None, command: str = "") -> str:
    """``conditions.md``: one table per condition, the estimators as rows."""
    unfit = unfit or {}
    lines = ["# Realism conditions", ""]
    if command:
        lines += ["```bash", command, "```", ""]
    lines += [
        "Every condition runs the same trials (same seeds, objects, mass distributions and "
        "friction). *region holds the CoM*: share of trials whose 90 % credible region "
        "(`Estimate.region`) contains the true CoM pixel, for estimators that report a "
        "credible region (n/a for the others). *ok > 1 cm*: share of trials that stopped "
        "with status `ok` and an error over 1 cm. *failed*: trials that ended in an error or "
        "with a push the robot could not execute. *statuses*: the trials by status. " + STATUS_NOTE,
        "",
    ]
    for name in list(dict.fromkeys([*results, *unfit])):
        result = results.get(name)
        cond = result.config.condition if result is not None else parse_condition(name)
        lines += [f"## {name}", "", cond.description, ""]
        lines += [
            "| estimator | trials | mean error (cm) | median | mean pushes | region holds the CoM "
            "| ok > 1 cm | failed | statuses |",
            "|---|---|---|---|---|---|---|---|---|",
        ]
        for label in result.config.estimators if result is not None else ():
            rows = [r for r in result.rows if r["estimator"] == label]
            err = np.array([r["error_cm"] for r in rows if r["status"] != Status.ERROR], float)
            pushes = np.array([r["total_pushes"] for r in rows], float)
            credible = [r for r in rows if r["credible_radius_cm"] is not None]
            cover = np.mean([bool(r["covered"]) for r in credible]) if credible else None
            bad_ok = np.mean([r["status"] == Status.OK and r["error_cm"] > 1.0 for r in rows])
            failed = sum(r["status"] == Status.ERROR or (r["push_failures"] or 0) > 0 for r in rows)
            lines.append(
                f"| `{label}` | {len(rows)} | "
                + (f"{err.mean():.3f} | {np.median(err):.3f} | " if len(err) else "– | – | ")
                + f"{pushes.mean():.2f} | "
                + ("n/a" if cover is None else f"{100 * cover:.0f} %")
                + f" | {100 * bad_ok:.1f} % | {failed} | {_statuses(rows)} |"
            )
        for label, reason in unfit.get(name, {}).items():
            lines.append(f"| `{label}` | not run: {reason} | | | | | | | |")
        lines.append("")
        predicted = [
            e
            for e in (result.config.estimators if result is not None else ())
            if parse_estimator(e)[0].uses_motions
        ]
        if predicted and not cond.plain:
            names = ", ".join(f"`{e}`" for e in predicted)
            source = (
                "this condition's observations of every candidate, each pushed from the "
                "initial pose (an optimistic stand-in for a predictor)"
                if result.config.predictor == "oracle"
                else f"the {result.config.predictor!r} predictor's, conditioned on prior "
                "pushes observed under this condition"
            )
            lines += [f"{names} work on predicted motions of every candidate: here {source}.", ""]
    return "\n".join(lines)


def run_conditions_command(args, config: BenchConfig, skipped: dict[str, str]) -> int:
    """``comcore bench --conditions ...``: run, write ``conditions.md`` and the rows.

    Writes ``conditions.md`` (one table per condition) and ``conditions.jsonl``
    (every row, with its ``condition``) into ``args.out``; returns the exit status
    (2 on a bad condition).
    """
    import json
    import shlex
    import sys
    from pathlib import Path

    if args.dask:
        print("comcore bench: --conditions runs locally (drop --dask)", file=sys.stderr)
        return 2
    try:
        labels = list(CONDITIONS) if args.conditions == "all" else split_estimators(args.conditions)
        conditions = [parse_condition(label) for label in labels]
        if not conditions:
            raise ValueError("conditions: name at least one condition")
    except ValueError as e:
        print(f"comcore bench: {e}", file=sys.stderr)
        return 2
    for label, reason in skipped.items():
        print(f"comcore bench: skipping estimator {label!r}: {reason}", file=sys.stderr)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    n = len(config.specs())
    print(
        f"comcore bench: {len(conditions)} condition(s) x {n} trials x "
        f"{len(config.estimators)} estimators on {args.workers} worker(s)"
    )
    partial = out / "conditions.partial.jsonl"
    with partial.open("w", encoding="utf-8") as stream:

        def on_rows(rows):
            stream.writelines(json.dumps(r) + "\n" for r in rows)
            stream.flush()

        try:
            results, unfit = run_conditions(
                config,
                conditions,
                workers=args.workers,
                progress=not args.no_progress,
                on_rows=on_rows,
            )
        except ValueError as e:
            print(f"comcore bench: {e}", file=sys.stderr)
            return 2
    rows = [row for result in results.values() for row in result.rows]
    with (out / "conditions.jsonl").open("w", encoding="utf-8") as stream:
        stream.writelines(json.dumps(r) + "\n" for r in rows)
    partial.unlink()
    argv = sys.argv[2:] if sys.argv[1:2] == ["bench"] else []
    command = "comcore bench " + shlex.join(argv) if argv else ""
    text = conditions_table(results, unfit, command=command)
    wall = sum(r.wall_s for r in results.values())
    text += f"\nWall time {wall:.0f} s on {args.workers} worker(s).\n"
    (out / "conditions.md").write_text(text, encoding="utf-8")
    print(text)
    print(f"conditions: {out / 'conditions.md'}; rows: {out / 'conditions.jsonl'}")
    return 0


def _statuses(rows) -> str:
    """The trials of ``rows`` by status, by name (``"ok 3, budget 2"``; :data:`STATUS_NOTE`)."""
    return status_cell({"statuses": dict(Counter(str(r["status"]) for r in rows).most_common())})


def friction_table(rows, baseline: str | None = None) -> str:
    """A Markdown table of result rows by estimator and friction class (and both).

    Parameters
    ----------
    rows : iterable of dict or str or os.PathLike
        Result rows, or a ``conditions.jsonl`` / ``results.jsonl`` file of them.
    baseline : str, optional
        An estimator label: the "both" rows then give each mean error as a ratio of
        its, and each mean push count as a difference.

    Examples
    --------
    >>> rows = [{"estimator": "a", "friction": f, "error_cm": e, "total_pushes": 3,
    ...          "covered": True, "status": "ok", "push_failures": 0}
    ...         for f, e in (("low", 0.2), ("high", 0.4))]
    >>> print(friction_table(rows).splitlines()[-1])
    | `a` | both | 0.300 | 0.300 | 0.40 | 3.00 | 100 % | 0.0 % | 0 | ok 2 |
    """
    import json
    import os

    if isinstance(rows, (str, os.PathLike)):
        with open(rows, encoding="utf-8") as stream:
            rows = [json.loads(line) for line in stream if line.strip()]
    rows = list(rows)
    labels = list(dict.fromkeys(r["estimator"] for r in rows))
    frictions = [f for f in ("low", "high") if any(r["friction"] == f for r in rows)]
    lines = [
        "| estimator | friction | mean error (cm) | median | max | pushes "
        "| region holds the CoM | ok > 1 cm | failed | statuses |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    base = None
    if baseline is not None:
        ref = [r for r in rows if r["estimator"] == baseline]
        if not ref:
            raise ValueError(f"baseline {baseline!r} is not among the estimators {labels}")
        base = (
            float(np.mean([r["error_cm"] for r in ref])),
            float(np.mean([r["total_pushes"] for r in ref])),
        )
    for friction in [*frictions, "both"]:
        for label in labels:
            sel = [
                r for r in rows if r["estimator"] == label and friction in ("both", r["friction"])
            ]
            err = np.array([r["error_cm"] for r in sel], float)
            pushes = np.array([r["total_pushes"] for r in sel], float)
            mean, push = f"{err.mean():.3f}", f"{pushes.mean():.2f}"
            if friction == "both" and base is not None and label != baseline:
                mean += f" ({err.mean() / base[0]:.2f} x)"
                push += f" ({pushes.mean() - base[1]:+.2f})"
            cover = np.mean([bool(r["covered"]) for r in sel])
            bad = np.mean([r["status"] == Status.OK and r["error_cm"] > 1.0 for r in sel])
            failed = sum(r["status"] == Status.ERROR or (r["push_failures"] or 0) > 0 for r in sel)
            lines.append(
                f"| `{label}` | {friction} | {mean} | {np.median(err):.3f} | {err.max():.2f} | "
                f"{push} | {100 * cover:.0f} % | {100 * bad:.1f} % | {failed} | {_statuses(sel)} |"
            )
    return "\n".join(lines)
