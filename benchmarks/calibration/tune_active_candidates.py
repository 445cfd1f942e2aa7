"""benchmarks/calibration/tune_active.py with the real-data candidates' motion models (issue 20, part 3).

The candidates measured on the MIT push dataset's train split (benchmarks/realdata/real_pushes.py
``--models``) change the active estimator's motion model, which the benchmark's ``active``
estimator takes only as ``"default"``, ``"limit-surface"``, ``"ellipsoid"`` or None. This
wrapper adds, for the duration of the run, the names below as values of its ``model``
option, then runs tune_active.py with the arguments given: the simulated benchmark under
a candidate, to check that it does not make the simulated results worse.

* ``model='family'``: ``comcore.LimitSurfaceModel.family(r)`` (tilted and linear spreads);
* ``model='family3'``: tilted, linear and peaked spreads, weighed like the friction;
* ``model='peaked'``: the peaked spread alone;

``r`` is the simulator's pusher radius, as for the default model. Usage (seed 1: the
tuning seed; a few trials while developing)::

    PYTHONPATH=. nice -n 10 python benchmarks/realdata/real_candidates_sim.py --seed 1 --trials 2 \\
        --objects Obj1,Obj7 --conditions exact,pymunk \\
        --estimators "active,active(model='family3')"
"""

from __future__ import annotations

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import tune_active

import comcore
import comcore.bench._builtins as builtins

PRESSURES3 = ("tilted", "linear", "peaked")
_ORIGINAL = builtins._hypothesis_model


def candidate_model(ctx, model):
    """The benchmark's model option, extended by the candidates' names."""
    r = ctx.simulator.pusher_radius
    if model == "family":
        return comcore.LimitSurfaceModel.family(r)
    if model == "family3":
        return tuple(
            comcore.LimitSurfaceModel(r, p, batch_pressures=PRESSURES3) for p in PRESSURES3
        )
    if model == "peaked":
        return comcore.LimitSurfaceModel(r, "peaked")
    return _ORIGINAL(ctx, model)


# The worker processes are forked and see the patch (under spawn they would not, and the
# benchmark would refuse the unknown model name).
builtins._hypothesis_model = candidate_model

if __name__ == "__main__":
    tune_active.main()
