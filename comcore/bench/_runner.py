"""Run many trials: in this process, on a process pool, or on a Dask cluster."""

from __future__ import annotations

import math
import multiprocessing
import signal
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, replace

from ._options import check_estimator_options, check_estimator_values
from ._registry import PREDICTORS, parse_estimator
from ._trial import (
    DEFAULT_CANDIDATES,
    DEFAULT_CONE,
    DEFAULT_ESTIMATORS,
    TrialSpec,
    run_trial,
)

__all__ = [
    "BenchConfig",
    "BenchInterrupted",
    "BenchResult",
    "check_available",
    "finished_rows",
    "run_benchmark",
    "sort_rows",
]

FRICTIONS = ("low", "high")


@dataclass(frozen=True)
class BenchConfig:
    """A benchmark: which trials to run.

    Trials are every (object, friction, index) with index ``0 .. trials-1``;
    each is seeded from ``(seed, object, friction, index)`` (see
    :func:`comcore.bench.trial_rng`), so the results do not depend on the
    number of workers or on where trials run.

    Examples
    --------
    >>> cfg = BenchConfig(objects=("Obj1", "Obj2"), trials=3, frictions=("low",))
    >>> len(cfg.specs()), cfg.specs()[0].object, cfg.specs()[-1].trial
    (6, 'Obj1', 2)
    """

    objects: tuple[str, ...] = ()
    trials: int = 300
    frictions: tuple[str, ...] = FRICTIONS
    predictor: str = "oracle"
    estimators: tuple[str, ...] = DEFAULT_ESTIMATORS
    candidates: int = DEFAULT_CANDIDATES
    cone: float = DEFAULT_CONE
    seed: int = 0

    def __post_init__(self):
        objects = tuple(self.objects)
        if not objects:
            import simulators

            objects = tuple(simulators.BENCHMARK_OBJECTS)
        object.__setattr__(self, "objects", objects)
        for name in ("trials", "candidates", "seed"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ValueError(f"{name} must be a non-negative integer, got {value!r}")
        frictions = tuple(self.frictions)
        if not frictions or any(f not in FRICTIONS for f in frictions):
            raise ValueError(
                f"frictions must be a non-empty subset of {FRICTIONS}, got {frictions}"
            )
        object.__setattr__(self, "frictions", frictions)
        if self.predictor not in PREDICTORS:
            raise ValueError(
                f"predictor must be one of {sorted(PREDICTORS)}, got {self.predictor!r}"
            )
        estimators = tuple(self.estimators)
        if not estimators or len(set(estimators)) != len(estimators):
            raise ValueError(f"estimators must be distinct and not empty, got {estimators}")
        for label in estimators:
            check_estimator_options(label)  # parses it; unknown options fail before any trial
            check_estimator_values(label)  # a value the estimator refuses, likewise
        object.__setattr__(self, "estimators", estimators)
        if not (0.0 <= self.cone < math.pi / 2):
            raise ValueError(f"cone must be in [0, pi/2), got {self.cone}")

    def specs(self) -> list[TrialSpec]:
        """Every trial, ordered by object, friction and index."""
        return [
            TrialSpec(
                o, f, i, self.seed, self.predictor, self.estimators, self.candidates, self.cone
            )
            for o in self.objects
            for f in self.frictions
            for i in range(self.trials)
        ]


@dataclass(frozen=True)
class BenchResult:
    """Rows of a benchmark (sorted, see :func:`sort_rows`) and how it ran.

    ``cpu_s`` is the CPU time (user + system) of this process and its local
    workers during the run (``None`` on a Dask cluster or without the
    ``resource`` module); on a busy machine it is the contention-free measure.
    """

    config: BenchConfig
    rows: list[dict]
    wall_s: float
    workers: int = 1
    dask: str | None = None
    skipped: dict[str, str] = field(default_factory=dict)
    cpu_s: float | None = None


class BenchInterrupted(KeyboardInterrupt):
    """Ctrl-C stopped :func:`run_benchmark`; ``rows`` holds every row finished before it.

    Attributes
    ----------
    rows : list of dict
        The finished rows (those of ``done`` included), in canonical order.
    trials_done, trials_total : int
        Trials finished (all their estimators' rows in ``rows``) and trials in the run.
    """

    def __init__(self, rows: list[dict], trials_done: int, trials_total: int):
        super().__init__(f"interrupted after {trials_done} of {trials_total} trials")
        self.rows, self.trials_done, self.trials_total = rows, trials_done, trials_total


def check_available(config: BenchConfig) -> tuple[BenchConfig, dict[str, str]]:
    """Drop the estimators this build cannot run; raise if the predictor is missing.

    Returns
    -------
    (BenchConfig, dict)
        The config with the runnable estimators and ``{label: reason}`` for the
        ones dropped.

    Raises
    ------
    RuntimeError
        If the predictor is unavailable or no estimator is left.
    """
    needs_predictor = any(parse_estimator(e)[0].uses_motions for e in config.estimators)
    reason = PREDICTORS[config.predictor].requires() if needs_predictor else None
    if reason:
        raise RuntimeError(f"predictor {config.predictor!r} is unavailable: {reason}")
    skipped = {}
    for label in config.estimators:
        why = parse_estimator(label)[0].requires()
        if why:
            skipped[label] = why
    kept = tuple(e for e in config.estimators if e not in skipped)
    if not kept:
        raise RuntimeError(f"no estimator can run in this build: {skipped}")
    return replace(config, estimators=kept), skipped


def sort_rows(rows: Iterable[dict], config: BenchConfig) -> list[dict]:
    """Rows in the canonical order: object, friction, trial, estimator (config order)."""
    obj = {o: i for i, o in enumerate(config.objects)}
    fri = {f: i for i, f in enumerate(config.frictions)}
    est = {e: i for i, e in enumerate(config.estimators)}
    return sorted(
        rows, key=lambda r: (obj[r["object"]], fri[r["friction"]], r["trial"], est[r["estimator"]])
    )


def _run_chunk(specs: Sequence[TrialSpec]) -> list[dict]:
    rows: list[dict] = []
    for spec in specs:
        rows.extend(run_trial(spec))
    return rows


def _sized_chunk(specs: Sequence[TrialSpec]) -> tuple[list[dict], int]:
    return _run_chunk(specs), len(specs)


def _ignore_sigint() -> None:
    """Pool workers leave Ctrl-C to the parent, which stops them (no traceback from each)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _trial_key(row_or_spec) -> tuple[str, str, int]:
    if isinstance(row_or_spec, TrialSpec):
        return (row_or_spec.object, row_or_spec.friction, row_or_spec.trial)
    return (row_or_spec["object"], row_or_spec["friction"], int(row_or_spec["trial"]))


def finished_rows(rows: Iterable[dict], config: BenchConfig) -> list[dict]:
    """The rows of the trials of ``config`` that hold a row for every estimator.

    What ``--resume`` keeps of an interrupted run: a trial cut off half-way is
    run again whole.
    """
    wanted = {_trial_key(s) for s in config.specs()}
    by_trial: dict[tuple, dict[str, dict]] = {}
    for row in rows:
        key = _trial_key(row)
        if key in wanted and row["estimator"] in config.estimators:
            by_trial.setdefault(key, {})[row["estimator"]] = row
    return [
        row
        for cells in by_trial.values()
        if len(cells) == len(config.estimators)
        for row in cells.values()
    ]


def _chunks(specs: list[TrialSpec], workers: int) -> list[list[TrialSpec]]:
    size = max(1, min(8, len(specs) // (4 * max(workers, 1))))
    return [specs[i : i + size] for i in range(0, len(specs), size)]


def _cpu_seconds() -> float | None:
    """User + system time of this process and its reaped children, or ``None``."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not on Windows
        return None
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


class _NoBar:
    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        return None

    def update(self, n: int) -> None:
        return None


def _progress(total: int, enabled: bool):
    if not enabled:
        return _NoBar()
    try:
        from tqdm.auto import tqdm
    except ImportError as e:
        raise ImportError(
            "the progress bar needs tqdm: pip install comcore[bench] (or pass --no-progress)"
        ) from e
    return tqdm(total=total, unit="trial", smoothing=0.05)


def run_benchmark(
    config: BenchConfig,
    *,
    workers: int = 1,
    dask: str | None = None,
    progress: bool = False,
    on_rows: Callable[[list[dict]], None] | None = None,
    done: Iterable[dict] = (),
) -> BenchResult:
    """Run every trial of ``config`` and return the rows in canonical order.

    Parameters
    ----------
    config : BenchConfig
    workers : int, optional
        Local processes (1: this process). Ignored with ``dask``.
    dask : str, optional
        Address of a Dask scheduler (``"tcp://host:8786"``); the trials are
        submitted in chunks through ``distributed.Client(dask)``.
    progress : bool, optional
        Show a tqdm progress bar (on stderr).
    on_rows : callable, optional
        Called with each finished chunk's rows (e.g. to stream them to disk).
    done : iterable of dict, optional
        Rows of an earlier, interrupted run of the same config: trials that hold
        a row for every estimator are kept and not run again
        (:func:`finished_rows`); the others run.

    Returns
    -------
    BenchResult
        Unavailable estimators are dropped and listed in ``skipped``. ``wall_s``
        and ``cpu_s`` measure this call only.

    Raises
    ------
    BenchInterrupted
        On Ctrl-C (KeyboardInterrupt): local workers are stopped at once, and
        the exception carries the rows finished so far.
    """
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be a positive integer, got {workers!r}")
    config, skipped = check_available(config)
    rows: list[dict] = finished_rows(done, config)
    kept = {_trial_key(r) for r in rows}
    specs = [s for s in config.specs() if _trial_key(s) not in kept]
    n_total = len(kept) + len(specs)
    start, cpu_start = time.perf_counter(), _cpu_seconds()

    def collect(chunk_rows: list[dict], n_trials: int, bar) -> None:
        rows.extend(chunk_rows)
        if on_rows is not None:
            on_rows(chunk_rows)
        bar.update(n_trials)

    try:
        with _progress(len(specs), progress) as bar:
            if dask is not None:
                _run_dask(specs, dask, collect, bar)
            elif workers == 1 or len(specs) <= 1:
                for spec in specs:
                    collect(run_trial(spec), 1, bar)
            else:
                _run_pool(specs, workers, collect, bar)
    except KeyboardInterrupt:
        finished = finished_rows(rows, config)
        n_done = len({_trial_key(r) for r in finished})
        raise BenchInterrupted(sort_rows(finished, config), n_done, n_total) from None
    wall, cpu_end = time.perf_counter() - start, _cpu_seconds()
    cpu = None if dask is not None or cpu_start is None else cpu_end - cpu_start  # type: ignore[operator]
    return BenchResult(config, sort_rows(rows, config), wall, workers, dask, skipped, cpu)


def _run_pool(specs: list[TrialSpec], workers: int, collect, bar) -> None:
    """Chunks of trials on a local process pool; Ctrl-C terminates the workers at once."""
    pool = multiprocessing.get_context().Pool(workers, initializer=_ignore_sigint)
    try:
        for chunk_rows, n_trials in pool.imap_unordered(_sized_chunk, _chunks(specs, workers)):
            collect(chunk_rows, n_trials, bar)
        pool.close()
    except BaseException:
        pool.terminate()  # stop running trials now instead of finishing the queue
        raise
    finally:
        pool.join()


def _run_dask(specs: list[TrialSpec], address: str, collect, bar) -> None:
    try:
        from distributed import Client
        from distributed import as_completed as dask_completed
    except ImportError as e:
        raise ImportError("--dask needs dask.distributed: pip install comcore[bench]") from e
    with Client(address) as client:
        n_workers = max(1, sum(client.nthreads().values()))
        chunks = _chunks(specs, n_workers)
        futures = client.map(_run_chunk, chunks, pure=False)
        sizes = {f.key: len(c) for f, c in zip(futures, chunks)}
        for fut in dask_completed(futures):
            collect(fut.result(), sizes[fut.key], bar)
