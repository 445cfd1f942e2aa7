"""The paper's evaluation as a library: trials, registries, reports (``comcore bench``).

Not imported by ``import comcore``: it needs the simulator (``comcore[sim]``)
to run trials, and tqdm, matplotlib, pyarrow or dask for progress bars,
figures, Parquet files and clusters (``comcore[bench,plot]``), each imported
only where it is used.

Examples
--------
>>> from comcore.bench import BenchConfig, run_benchmark
>>> result = run_benchmark(BenchConfig(objects=("Obj3",), trials=1, frictions=("low",),
...                                    candidates=8, estimators=("alg2", "centroid")))
>>> [(r["estimator"], r["status"]) for r in result.rows]
[('alg2', 'wide'), ('centroid', 'unchecked')]
"""

from ._conditions import friction_table, run_conditions
from ._realism import CONDITIONS, OPTIONAL_CONDITIONS, Condition, parse_condition
from ._registry import (
    ESTIMATORS,
    PREDICTORS,
    EstimatorSpec,
    PredictorSpec,
    TrialContext,
    option_groups,
    parse_estimator,
    register_estimator,
    split_estimators,
)
from ._runner import BenchConfig, BenchResult, check_available, run_benchmark, sort_rows
from ._trial import (
    DEFAULT_CANDIDATES,
    DEFAULT_CONE,
    DEFAULT_ESTIMATORS,
    ROW_FIELDS,
    TrialOutcome,
    TrialSpec,
    run_trial,
    trial_rng,
)

__all__ = [
    "CONDITIONS",
    "DEFAULT_CANDIDATES",
    "DEFAULT_CONE",
    "DEFAULT_ESTIMATORS",
    "ESTIMATORS",
    "OPTIONAL_CONDITIONS",
    "PREDICTORS",
    "ROW_FIELDS",
    "BenchConfig",
    "BenchResult",
    "Condition",
    "EstimatorSpec",
    "PredictorSpec",
    "TrialContext",
    "TrialOutcome",
    "TrialSpec",
    "check_available",
    "friction_table",
    "option_groups",
    "parse_condition",
    "parse_estimator",
    "register_estimator",
    "run_benchmark",
    "run_conditions",
    "run_trial",
    "sort_rows",
    "split_estimators",
    "trial_rng",
]
