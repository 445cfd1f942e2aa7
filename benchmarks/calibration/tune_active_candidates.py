"""tune_active.py with the real-data candidates' motion models: the simulated benchmark under each.

The candidate motion models measured on the MIT push dataset's train split
(benchmarks/realdata/real_pushes.py ``--models``) are run on the simulated benchmark, to
check that a candidate does not make the simulated results worse. The benchmark's
``active`` estimator takes its ``model`` option only as ``"default"``,
``"limit-surface"``, ``"ellipsoid"`` or None; this script registers, through the public
registry (``comcore.bench.register_estimator(..., replace=True)``), an ``active`` that also
takes the names below and runs every other value as the benchmark's own ``active`` does,
then runs tune_active.py with the arguments given. The label (and so each trial's random
stream) is the benchmark's own, ``active(model='family3')`` for example.

* ``model='family'``: ``comcore.LimitSurfaceModel.family(r)`` (tilted and linear spreads);
* ``model='family3'``: tilted, linear and peaked spreads, weighed like the friction;
* ``model='peaked'``: the peaked spread alone;

``r`` is the simulator's pusher radius, as for the default model. Usage (seed 1: the
tuning seed; a few trials while developing)::

    PYTHONPATH=. nice -n 10 python benchmarks/calibration/tune_active_candidates.py \\
        --seed 1 --trials 2 --objects Obj1,Obj7 --conditions exact,pymunk \\
        --estimators "active,active(model='family3')"
"""

from __future__ import annotations

import comcore
from comcore.bench import ESTIMATORS, register_estimator

PRESSURES3 = ("tilted", "linear", "peaked")
#: The benchmark's own ``active`` estimator, run for every other value of ``model``.
BENCHMARK_ACTIVE = ESTIMATORS["active"]


def candidate_model(pusher_radius: float, model):
    """The candidate motion model named ``model``; None when it names none of them."""
    r = pusher_radius
    if model == "family":
        return comcore.LimitSurfaceModel.family(r)
    if model == "family3":
        return tuple(
            comcore.LimitSurfaceModel(r, p, batch_pressures=PRESSURES3) for p in PRESSURES3
        )
    if model == "peaked":
        return comcore.LimitSurfaceModel(r, "peaked")
    return None


def active(ctx, model="default", candidates="own", **options):
    """The benchmark's ``active`` estimator, its ``model`` option extended by the candidates."""
    found = candidate_model(ctx.simulator.pusher_radius, model)
    if found is None:
        return BENCHMARK_ACTIVE.run(ctx, model=model, candidates=candidates, **options)
    if candidates not in ("trial", "own"):
        raise ValueError(f"candidates must be 'trial' or 'own', got {candidates!r}")
    return comcore.estimate_active(
        ctx.mask,
        ctx.push,
        ctx.candidates if candidates == "trial" else None,
        model=found,
        rng=ctx.rng,
        **comcore.bench.option_groups(**options),
    )


# At import, so that the worker processes have it too (forked, or importing this main module).
register_estimator(
    "active",
    active,
    description=BENCHMARK_ACTIVE.description,
    uses_motions=BENCHMARK_ACTIVE.uses_motions,
    requires=BENCHMARK_ACTIVE.requires,
    resets=BENCHMARK_ACTIVE.resets,
    replace=True,
)

if __name__ == "__main__":
    import tune_active  # this folder is on the path when run as a script

    tune_active.main()
