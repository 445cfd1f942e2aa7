"""CPU seconds per benchmark trial against the number of candidate pushes.

    PYTHONPATH=. python benchmarks/timing/trial_cost.py [--counts 15,20,30,45,60]

Runs trial 7 of every other benchmark object in both friction classes with the default
estimators (oracle predictor) and prints the mean CPU time per trial (process time, so a
busy machine inflates it less than wall time).
"""

from __future__ import annotations

import argparse
import time

import simulators
from comcore.bench import TrialSpec, run_trial


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--counts", default="15,20,30,45,60")
    args = parser.parse_args()
    run_trial(TrialSpec("Obj1", "low", 0, candidates=5))  # imports and caches
    for n in (int(v) for v in args.counts.split(",")):
        start, k = time.process_time(), 0
        for name in simulators.BENCHMARK_OBJECTS[::2]:
            for friction in ("low", "high"):
                run_trial(TrialSpec(name, friction, 7, candidates=n))
                k += 1
        print(f"{n:3d} candidates: {(time.process_time() - start) / k:.3f} CPU s per trial")


if __name__ == "__main__":
    main()
