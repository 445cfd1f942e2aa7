"""The Markdown report: the paper's Tables I and II with our figures beside theirs."""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from .._status import Status
from ._io import paper_table

__all__ = [
    "ALG1_NOTE",
    "STATUS_NOTE",
    "group_stats",
    "markdown_report",
    "status_cell",
    "summary_table",
    "table_one",
    "table_two",
]

FRICTIONS = ("low", "high")
#: Said wherever Alg. 1's figure is shown (the report, ``comcore demo --compare``).
ALG1_NOTE = (
    "Alg. 1 is not reproduced: its error here is far above the paper's "
    "(docs/results/paper.md says why)."
)
#: What the statuses in the bench's tables mean (the report's and ``conditions.md``'s).
STATUS_NOTE = (
    "Statuses count the trials by the status each ended with (comcore.Status). `ok`: the "
    "pushes were consistent and the estimate's region reached the target radius (6 mm by "
    "default: the 90 % credible region for the active estimator, the final region for "
    "Alg. 2). `wide`: consistent, the region wider (Alg. 2). `budget`: an active estimator "
    "spent its push budget (`StopRule.max_pushes`: 5 unless its label sets another, "
    "`active(max_pushes=8)`) before its credible region reached the target radius: a usable "
    "estimate, its region wider, not a failure; "
    "`exhausted` and `uninformative` likewise stopped wide, with no candidate push left or "
    "none expected to teach more. `unchecked`: Alg. 1, which has no test of its evidence "
    "and is never `ok`. `inconsistent`: no CoM explains the pushes. `error`: the estimator "
    "raised (counted under Errors too)."
)


def group_stats(rows: Iterable[Mapping], keys=("estimator", "object", "friction")) -> dict:
    """Statistics of the rows grouped by ``keys``.

    Returns
    -------
    dict
        ``{key tuple: stats}`` with ``n``, ``error`` (mean, std, min, max,
        median of ``error_cm`` over the rows whose estimator did not raise:
        ``None`` each where every one raised), ``pushes`` (mean, std, min, max of
        ``pushes_used``), ``total_pushes`` (their sum), ``statuses``
        (``{status: rows}`` of every status, ``"ok"`` included, most frequent
        first: ``"ok"``, Alg. 2's ``"wide"``, Alg. 1's ``"unchecked"``, the
        active estimator's ``"budget"`` ...) and ``errors`` (rows with status
        ``"error"``).

    Examples
    --------
    >>> rows = [{"estimator": "a", "error_cm": e, "pushes_used": 2, "total_pushes": 2,
    ...          "status": "ok"} for e in (1.0, 3.0)]
    >>> s = group_stats(rows, keys=("estimator",))[("a",)]
    >>> s["n"], s["error"]["mean"], s["error"]["std"], s["total_pushes"]
    (2, 2.0, 1.0, 4)
    """
    groups: dict[tuple, list[Mapping]] = defaultdict(list)
    for row in rows:
        groups[tuple(row[k] for k in keys)].append(row)
    out = {}
    for key, members in groups.items():
        err = np.array([r["error_cm"] for r in members if r["status"] != Status.ERROR], float)
        pushes = np.array([r["pushes_used"] for r in members], float)
        statuses = Counter(r["status"] for r in members)
        out[key] = {
            "n": len(members),
            "error": _describe(err),
            "pushes": _describe(pushes),
            "total_pushes": int(sum(r["total_pushes"] for r in members)),
            "statuses": {str(k): v for k, v in statuses.most_common()},
            "errors": sum(r["status"] == Status.ERROR for r in members),
        }
    return out


def _describe(values: np.ndarray) -> dict[str, float | None]:
    if not len(values):
        return dict.fromkeys(("mean", "std", "min", "max", "median"))
    return {
        "mean": float(values.mean()),
        "std": float(values.std()),  # population std; the paper does not say which
        "min": float(values.min()),
        "max": float(values.max()),
        "median": float(np.median(values)),
    }


def _number(value: float | None, digits: int) -> str:
    return "–" if value is None else f"{value:.{digits}f}"


def _cell(ours: float | None, paper: float | None, digits: int = 2) -> str:
    text = "–" if ours is None else f"{ours:.{digits}f}"
    return text if paper is None else f"{text} ({paper:g})"


def _ratio(ours: float | None, paper: float | None) -> str:
    return "–" if ours is None or not paper else f"{ours / paper:.2f}"


def _markdown(header: Sequence[str], body: Sequence[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in body]
    return "\n".join(lines)


def _objects(rows: Sequence[Mapping]) -> list[str]:
    return list(dict.fromkeys(r["object"] for r in rows))


def _size(rows: Sequence[Mapping], name: str, paper: Mapping) -> str:
    ours = np.mean([r["area_cm2"] for r in rows if r["object"] == name])
    return f"{ours:.1f}" + (f" ({paper[name]['size_cm2']:g})" if name in paper else "")


def table_one(rows: Sequence[Mapping], estimator: str = "alg1") -> str:
    """Table I (Alg. 1's error in cm) in the paper's layout: ``ours (paper)`` and ratio."""
    stats = group_stats(r for r in rows if r["estimator"] == estimator)
    paper = paper_table(1)
    frictions = [f for f in FRICTIONS if any(r["friction"] == f for r in rows)]
    header = ["Object", "Size cm²"]
    for f in frictions:
        header += [f"{f} mean", "std", "min", "max", "mean ratio"]
    body = []
    for name in _objects(rows):
        line = [name, _size(rows, name, paper)]
        for f in frictions:
            s = stats.get((estimator, name, f))
            p = paper.get(name)
            for stat in ("mean", "std", "min", "max"):
                ours = s["error"][stat] if s else None
                line.append(_cell(ours, p[f"{f}_{stat}_cm"] if p else None))
            line.append(_ratio(s["error"]["mean"] if s else None, p[f"{f}_mean_cm"] if p else None))
        body.append(line)
    return _markdown(header, body)


def table_two(rows: Sequence[Mapping], estimator: str = "alg2") -> str:
    """Table II (Alg. 2's error in cm and pushes used) in the paper's layout, with ratios."""
    stats = group_stats(r for r in rows if r["estimator"] == estimator)
    paper = paper_table(2)
    frictions = [f for f in FRICTIONS if any(r["friction"] == f for r in rows)]
    header = ["Object", "Size cm²"]
    for f in frictions:
        header += [f"{f} err mean", "std", "min", "max", "pushes mean", "std", "min", "max"]
        header += ["err ratio", "push ratio"]
    body = []
    for name in _objects(rows):
        line = [name, _size(rows, name, paper)]
        for f in frictions:
            s, p = stats.get((estimator, name, f)), paper.get(name)
            for group, column in (("error", "err_{}_cm"), ("pushes", "push_{}")):
                for stat in ("mean", "std", "min", "max"):
                    ours = s[group][stat] if s else None
                    theirs = p[f"{f}_" + column.format(stat)] if p else None
                    digits = 0 if group == "pushes" and stat in ("min", "max") else 2
                    line.append(_cell(ours, theirs, digits))
            for group, column in (("error", "err_mean_cm"), ("pushes", "push_mean")):
                ours = s[group]["mean"] if s else None
                line.append(_ratio(ours, p[f"{f}_{column}"] if p else None))
        body.append(line)
    return _markdown(header, body)


def status_cell(stats: Mapping) -> str:
    """The "Statuses" cell: every status by name with its count, most frequent first.

    Examples
    --------
    >>> status_cell({"statuses": {"ok": 158, "budget": 42}})
    'ok 158, budget 42'
    >>> status_cell({"statuses": {"unchecked": 20}})
    'unchecked 20'
    >>> status_cell({"statuses": {}})
    '–'
    """
    statuses = stats.get("statuses", {})
    return ", ".join(f"{k} {v}" for k, v in statuses.items()) or "–"


def summary_table(rows: Sequence[Mapping]) -> str:
    """One line per estimator and friction: error, pushes, real pushes in total, statuses.

    "Statuses" counts the trials by the status each ended with, by name
    (``"ok 158, budget 42"``; :data:`STATUS_NOTE` says what each means): every
    ``alg1`` trial is ``"unchecked"`` (Alg. 1 has no test of its evidence), an
    active estimator's may be ``"budget"`` (the push budget spent before the
    target radius: usable, wider), Alg. 2's ``"wide"``, ... The error columns
    cover the trials whose estimator did not raise (``–`` where none).
    """
    stats = group_stats(rows, keys=("estimator", "friction"))
    header = [
        "Estimator", "Friction", "Trials", "Error mean cm", "median", "std", "max",
        "Pushes used mean", "Real pushes in total", "Statuses", "Errors",
    ]  # fmt: skip
    body = []
    for (name, friction), s in stats.items():
        e, p = s["error"], s["pushes"]
        body.append(
            [name, friction, str(s["n"])]
            + [_number(e[stat], 3) for stat in ("mean", "median", "std", "max")]
            + [f"{p['mean']:.2f}", str(s["total_pushes"]), status_cell(s), str(s["errors"])]
        )
    return _markdown(header, body)


def _cpu_text(meta: Mapping, rows: Sequence[Mapping]) -> str:
    cpu = meta.get("cpu_s")
    trials = len({(r["object"], r["friction"], r["trial"]) for r in rows})
    if cpu is None or not trials:
        return ""
    return f" (CPU time {cpu:.1f} s, {cpu / trials:.3f} s per trial)"


def markdown_report(rows: Sequence[Mapping], meta: Mapping, figures: Mapping[str, str]) -> str:
    """The whole report.

    Parameters
    ----------
    rows : sequence of dict
        Result rows (:data:`comcore.bench.ROW_FIELDS`).
    meta : mapping
        ``command``, ``config`` (mapping), ``wall_s``, ``workers``, ``machine``,
        ``skipped`` (label -> reason).
    figures : mapping
        Caption -> relative path of each PNG.
    """
    config = meta.get("config", {})
    estimators = list(dict.fromkeys(r["estimator"] for r in rows))
    parts = [
        "# comcore bench report",
        f"Command: `{meta.get('command', '')}`",
        f"Predictor `{config.get('predictor')}`, {config.get('candidates')} candidate pushes "
        f"per trial (cone ±{config.get('cone')} rad), {config.get('trials')} trials per object "
        f"and friction class, {len(_objects(rows))} objects, seed {config.get('seed')}.",
        f"Wall time {meta.get('wall_s', 0.0):.1f} s with {meta.get('workers')} worker(s) "
        f"on {meta.get('machine', 'this machine')}{_cpu_text(meta, rows)}; "
        f"{len(rows)} result rows.",
        "Errors are distances from the estimate to the true CoM in cm, over the trials whose "
        "estimator did not raise (`–` where every one raised); cells read "
        "`ours (paper)`; ratios are ours / paper. std is the population standard deviation.",
        "## Summary",
        "Real pushes count the pushes run on the object: a learned predictor's prior pushes "
        "plus the pushes an estimator used (Alg. 1 uses every candidate), or, for an estimator "
        "that pushes the object itself, the pushes it executed. "
        + STATUS_NOTE
        + " (docs/how-to/benchmark.md, docs/results/active.md).",
        summary_table(rows),
    ]
    if "alg1" in estimators:
        parts.append(ALG1_NOTE)
    if "alg1" in estimators:
        parts += ["## Table I: Alg. 1 (`alg1`), error in cm", ALG1_NOTE, table_one(rows, "alg1")]
    if "alg2" in estimators:
        parts += ["## Table II: Alg. 2 (`alg2`), error in cm and pushes", table_two(rows, "alg2")]
    if figures:
        parts.append("## Figures")
        parts += [f"![{caption}]({path})\n\n*{caption}*" for caption, path in figures.items()]
    notes = [f"- `{label}` skipped: {why}" for label, why in meta.get("skipped", {}).items()]
    redrawn = {(r["object"], r["friction"], r["trial"]) for r in rows if "draw" in r["message"]}
    if redrawn:
        notes.append(f"- {len(redrawn)} trial(s) redrew the random simulator after a failed draw.")
    failed = [r for r in rows if r["status"] == Status.ERROR]
    notes += [
        f"- error in {r['object']} {r['friction']} trial {r['trial']} `{r['estimator']}`: "
        f"{r['message']}"
        for r in failed[:20]
    ]
    if notes:
        parts += ["## Notes", "\n".join(notes)]
    return "\n\n".join(parts) + "\n"
