"""``comcore bench``: the paper's evaluation in the simulator, with a report beside the paper's."""

from __future__ import annotations

import argparse
import json
import os
import shlex
import sys
from pathlib import Path

HELP = (
    "run the paper's benchmark in the simulator (Tables I-II, Figs. 5-7) and write results, "
    "figures and a report (needs comcore[sim,bench,plot])"
)

#: What ``--quick`` runs unless told otherwise (200 trials). Beside the paper's estimators
#: (the default ``--estimators``) it runs ``extra_estimators``: the active estimator the
#: README recommends, with its defaults.
QUICK = {
    "objects": "Obj1,Obj4,Obj7,Obj12,Obj19",
    "trials": 20,
    "extra_estimators": ("active",),
}
#: Options every built-in estimator gets from the benchmark itself (not for the user to set).
#: The bench sets the stream itself; the option groups are objects a label cannot spell (their
#: fields are options of their own: ``active(max_pushes=3)``).
SET_BY_THE_BENCHMARK = frozenset({"rng", "likelihood", "stop", "choice"})


def _positive_int(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text}")
    return value


def _count(text: str) -> int:
    value = int(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected an integer >= 0, got {text}")
    return value


def estimators_help(width: int = 79) -> str:
    """The registered estimators, what each is and its options; the predictors (``--help``).

    Examples
    --------
    >>> text = estimators_help()
    >>> "alg1" in text and "length_scale, threshold" in text and "oracle" in text
    True
    """
    import textwrap

    from . import _builtins  # noqa: F401  (registers the built-in estimators)
    from ._options import accepted_options
    from ._registry import ESTIMATORS, PREDICTORS

    lines = [
        "estimators (--estimators 'name,name(key=value, ...)'; 'all' runs every one):",
    ]
    indent = " " * 4
    for name, spec in ESTIMATORS.items():
        lines += textwrap.wrap(
            f"{name}: {spec.description}", width, initial_indent="  ", subsequent_indent=indent
        )
        accepted = accepted_options(spec)
        if accepted is None:
            options = "any keyword its function takes"
        else:
            options = ", ".join(sorted(accepted - SET_BY_THE_BENCHMARK)) or "none"
        lines += textwrap.wrap(
            f"options: {options}", width, initial_indent=indent, subsequent_indent=indent + "  "
        )
    lines.append("")
    lines += textwrap.wrap(
        "predictors (--predictor: the motions of the candidates that alg1 and alg2 work "
        "on; the active estimators push the object instead): " + ", ".join(PREDICTORS),
        width,
    )
    quick = ",".join(QUICK["extra_estimators"])
    lines += textwrap.wrap(
        f"--quick runs {QUICK['objects']} x {QUICK['trials']} trials per friction class, the "
        f"default estimators plus {quick} (unless --estimators is given).",
        width,
    )
    return "\n".join(lines)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``comcore bench``; ``--help`` lists the estimators and their options."""
    from ._trial import DEFAULT_CANDIDATES, DEFAULT_CONE, DEFAULT_ESTIMATORS

    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.epilog = estimators_help()
    add = parser.add_argument
    add("--objects", help="comma-separated object names, or 'all' (default: all 20)")
    add("--trials", type=_count, help="trials per object and friction class (default 300)")
    add("--friction", choices=("low", "high", "both"), default="both")
    add("--predictor", default="oracle", help="oracle, ellipsoid or anp (default oracle)")
    add(
        "--estimators",
        help="comma-separated estimator labels, e.g. 'alg1(threshold=0.2),alg2', or 'all' "
        f"(default {','.join(DEFAULT_ESTIMATORS)}; with --quick also "
        f"{','.join(QUICK['extra_estimators'])}); the list is below",
    )
    add("--candidates", type=_count, default=DEFAULT_CANDIDATES, help="candidate pushes per trial")
    add(
        "--cone", type=float, default=DEFAULT_CONE, help="push directions: radians about the normal"
    )
    add("--seed", type=_count, default=0)
    add("--workers", type=_positive_int, default=os.cpu_count() or 1, help="local processes")
    add("--out", default="bench-out", help="output folder (default bench-out)")
    add("--format", choices=("jsonl", "parquet"), default="jsonl", help="results file format")
    add(
        "--quick",
        action="store_true",
        help="5 objects x 20 trials per friction class, the active estimator beside the "
        "paper's (measured: 5 min 33 s with 2 workers on a 2-core machine at load average 7)",
    )
    add("--dask", metavar="ADDRESS", help="run the trials on this Dask scheduler")
    add("--no-figures", action="store_true", help="skip the PNG figures")
    add("--no-progress", action="store_true", help="no progress bar")
    add(
        "--conditions",
        metavar="LIST",
        help="run the same trials under realism conditions and write conditions.md: "
        "exact,pymunk,pusher-error,motion-noise,mask-noise,resolution-0.1,no-reset "
        "(docs/results/active.md); all: these; mujoco: MuJoCo's physics and rendered frames "
        "(needs comcore[mujoco], docs/results/simulators.md)",
    )
    add(
        "--resume",
        action="store_true",
        help="finish the interrupted run in --out (same options): keep its finished trials "
        "and run the others",
    )


def _config(args):
    import simulators

    from ._registry import ESTIMATORS, split_estimators
    from ._runner import BenchConfig
    from ._trial import DEFAULT_ESTIMATORS

    objects = args.objects or (QUICK["objects"] if args.quick else "all")
    names = (
        tuple(simulators.BENCHMARK_OBJECTS)
        if objects == "all"
        else tuple(o.strip() for o in objects.split(",") if o.strip())
    )
    unknown = [o for o in names if o not in simulators.BENCHMARK_OBJECTS]
    if unknown or not names:
        raise ValueError(f"--objects: unknown object(s) {unknown}; expected Obj1..Obj20 or 'all'")
    trials = args.trials if args.trials is not None else (QUICK["trials"] if args.quick else 300)
    if args.estimators is None:
        extra = QUICK["extra_estimators"] if args.quick else ()
        estimators = (*DEFAULT_ESTIMATORS, *extra)
    elif args.estimators == "all":
        estimators = tuple(ESTIMATORS)
    else:
        estimators = tuple(split_estimators(args.estimators))
    frictions = ("low", "high") if args.friction == "both" else (args.friction,)
    return BenchConfig(
        objects=names,
        trials=trials,
        frictions=frictions,
        predictor=args.predictor,
        estimators=estimators,
        candidates=args.candidates,
        cone=args.cone,
        seed=args.seed,
    )


def run(args) -> int:
    """Run the benchmark; returns the exit status (2 on bad options or a missing extra)."""
    try:
        import simulators  # noqa: F401

        from ._runner import check_available
    except ImportError as e:
        print(
            f"comcore bench needs the simulator: pip install comcore[sim,bench] ({e})",
            file=sys.stderr,
        )
        return 2
    missing = missing_extras(args)
    if missing:
        print(f"comcore bench: {missing}", file=sys.stderr)
        return 2
    try:
        config = _config(args)
        checked, skipped = check_available(config)
    except (ValueError, RuntimeError) as e:
        print(f"comcore bench: {e}", file=sys.stderr)
        return 2
    try:
        Path(args.out).mkdir(parents=True, exist_ok=True)
    except OSError as e:
        print(f"comcore bench: --out {args.out}: cannot write there ({e})", file=sys.stderr)
        return 2
    if getattr(args, "conditions", None):
        from ._conditions import run_conditions_command

        return run_conditions_command(args, checked, skipped)
    for label, reason in skipped.items():
        print(f"comcore bench: skipping estimator {label!r}: {reason}", file=sys.stderr)
    return _run_trials(args, config, checked)


def _run_trials(args, config, checked) -> int:
    """Run the checked configuration's trials, streaming their rows; the exit status."""
    from ._runner import BenchInterrupted, finished_rows, run_benchmark

    out = Path(args.out)
    partial = out / "results.partial.jsonl"
    try:
        done = _previous_rows(args, config, out, partial)
        out.mkdir(parents=True, exist_ok=True)
        (out / STATE).write_text(json.dumps({"config": _jsonable(config)}) + "\n", "utf-8")
        stream = partial.open("w", encoding="utf-8")
    except ValueError as e:
        print(f"comcore bench: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"comcore bench: --out {out}: cannot write there ({e})", file=sys.stderr)
        return 2
    n_trials = len(checked.specs())
    where = f"Dask at {args.dask}" if args.dask else f"{args.workers} worker(s)"
    kept = finished_rows(done, checked)
    again = f" ({len(kept)} rows kept from the interrupted run)" if args.resume else ""
    print(
        f"comcore bench: {n_trials} trials x {len(checked.estimators)} estimators on {where}"
        + again
    )
    with stream:

        def on_rows(rows):
            stream.writelines(json.dumps(r) + "\n" for r in rows)
            stream.flush()

        on_rows(kept)
        try:
            result = run_benchmark(
                config,
                workers=args.workers,
                dask=args.dask,
                progress=not args.no_progress,
                on_rows=on_rows,
                done=done,
            )
        except BenchInterrupted as e:
            print(
                f"comcore bench: interrupted after {e.trials_done} of {e.trials_total} trials; "
                f"their rows are in {partial}; the same command with --resume finishes the run",
                file=sys.stderr,
            )
            return 130
        except (ImportError, OSError) as e:
            print(f"comcore bench: {e}", file=sys.stderr)
            return 2
    return _save(args, result, out, partial)


def _save(args, result, out: Path, partial: Path) -> int:
    """Write the finished run's results and report, print its summary; the exit status."""
    from ._outputs import save_benchmark

    command = "comcore bench " + shlex.join(sys.argv[2:]) if sys.argv[1:2] == ["bench"] else ""
    try:
        paths = save_benchmark(
            result,
            out,
            fmt=args.format,
            command=command or _command_of(args),
            figures=not args.no_figures,
        )
    except OSError as e:
        print(f"comcore bench: --out {out}: cannot write the results ({e})", file=sys.stderr)
        return 2
    partial.unlink()
    (out / STATE).unlink(missing_ok=True)
    from ._report import ALG1_NOTE, summary_table

    print(summary_table(result.rows))
    if any(r["estimator"] == "alg1" for r in result.rows):
        print(ALG1_NOTE)
    print(
        f"wall time {result.wall_s:.1f} s; report: {paths['report']}; results: {paths['results']}"
    )
    return 0


#: Modules a run needs, by the extra that installs them; ``None``: always needed.
NEEDS = {
    "sim": ("shapely", "trimesh", "lxml", "svg.path", "networkx"),
    "bench": ("tqdm",),
    "plot": ("matplotlib",),
}


def missing_extras(args) -> str:
    """What this run needs and cannot import, with the ``pip install`` that fixes it ("" if none).

    tqdm only with a progress bar, matplotlib only with figures, pyarrow only for
    Parquet, dask.distributed only with ``--dask``.
    """
    import importlib

    wanted = [(m, "sim") for m in NEEDS["sim"]]
    if not args.no_progress:
        wanted.append(("tqdm", "bench"))
    if not args.no_figures:
        wanted.append(("matplotlib", "plot"))
    if args.format == "parquet":
        wanted.append(("pyarrow", "bench"))
    if args.dask:
        wanted.append(("distributed", "bench"))
    missing: dict[str, str] = {}
    for module, extra in wanted:
        try:
            importlib.import_module(module)
        except ImportError:
            missing[module] = extra
    if not missing:
        return ""
    extras = ",".join(sorted(set(missing.values())))
    flags = (("--no-progress", "tqdm"), ("--no-figures", "matplotlib"))
    skip = [flag for flag, module in flags if module in missing]
    alternative = f" (or pass {' '.join(skip)})" if skip else ""
    return (
        f"this run needs {', '.join(missing)}, not installed: pip install comcore[{extras}]"
        f"{alternative}"
    )


#: In ``--out`` while a run goes: its configuration, to check a ``--resume`` against.
STATE = "run.partial.json"


def _jsonable(config) -> dict:
    import dataclasses

    return json.loads(json.dumps(dataclasses.asdict(config), default=repr))


def _previous_rows(args, config, out: Path, partial: Path) -> list[dict]:
    """The rows of the interrupted run ``--resume`` continues (none without ``--resume``)."""
    if not args.resume:
        if partial.exists():
            print(
                f"comcore bench: starting afresh; the unfinished run in {out} is replaced "
                "(--resume continues it instead)",
                file=sys.stderr,
            )
        return []
    if not partial.exists():
        done = " (its results.jsonl is complete)" if (out / "results.jsonl").exists() else ""
        raise ValueError(f"--resume: no interrupted run in {out}{done}")
    state = out / STATE
    saved = json.loads(state.read_text("utf-8"))["config"] if state.exists() else None
    if saved != _jsonable(config):
        raise ValueError(
            f"--resume: the run in {out} had other options ({saved}); give the same options, "
            "or another --out"
        )
    rows = []
    with partial.open(encoding="utf-8") as f:
        for line in f:
            try:
                rows.append(json.loads(line))
            except json.JSONDecodeError:  # the last line of a run killed mid-write
                break
    return rows


def _command_of(args) -> str:
    """The options of a run as a command line (when not started from the shell)."""
    parts = ["comcore", "bench"]
    for key, value in sorted(vars(args).items()):
        if key.startswith("_") or key == "command" or value in (None, False):
            continue
        flag = "--" + key.replace("_", "-")
        parts += [flag] if value is True else [flag, str(value)]
    return shlex.join(parts)
