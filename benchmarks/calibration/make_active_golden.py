"""Record estimate_active's outputs on a few fixed cases (tests/data/active_golden.json).

The refactor of estimate_active onto comcore.ActiveSession must reproduce these
(tests/active/test_blocking.py::test_estimate_active_reproduces_the_golden_record). Run once,
before a change that is meant to keep the results, and commit the JSON::

    PYTHONPATH=. python benchmarks/calibration/make_active_golden.py            # write
    PYTHONPATH=. python benchmarks/calibration/make_active_golden.py --check    # compare
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

import comcore

OUT = Path(__file__).resolve().parents[2] / "tests" / "data" / "active_golden.json"
#: The noise of the estimator as it was when the record was made (in physical
#: units since: no pusher error, no tracking noise on top of the fitted scales).
LEGACY = {
    "likelihood": comcore.Likelihood(pusher_error=0.0, motion_noise=(0.0, 0.0), model_weight=1.0),
    "stop": comcore.StopRule(target_radius=0.0045),
    "model": None,
    "pusher_radius": 0.0,  # contacts on the leading point's line, as then (not the disc's)
}


def toy_case(seed: int):
    """A toy robot: 0.1 rad in the Voting Theorem's sense, on an object with no symmetry.

    A square would offer pushes whose gains tie exactly, and which of them rounding picks
    differs between CPUs (numpy's SIMD paths): the record would hold on one machine only.
    """
    data = np.zeros((46, 46), bool)
    data[8:38, 8:38] = True
    data[8:17, 27:38] = False  # a notch in one corner
    data[30:38, 8:12] = False  # a smaller one in the opposite corner
    data[17:21, 38:41] = True  # a tab
    mask = comcore.Mask(data)
    true_com = np.array([17.0, 20.0])

    def push(action):
        c = comcore.geometry.contacts(mask, action)
        s = comcore.vt.predicted_sense(true_com, c.point[0], c.normal[0], action.direction, 0.3)
        return comcore.Motion(0.1 * s, 0.0, 0.0)

    options = {**LEGACY, "rng": seed}
    options["stop"] = comcore.StopRule(max_pushes=8, target_radius=0.0045)
    return mask, push, options


def sim_case(seed: int, with_model: bool):
    """Obj7, low friction, the simulator as the robot (reset before every push)."""
    import simulators

    sim = simulators.random_simulator("Obj7", "low", rng=0)
    options = {"rng": seed, **LEGACY}
    if with_model:
        from predictors import EllipsoidPredictor

        options["model"] = EllipsoidPredictor(pusher_radius=sim.pusher_radius)
    return sim.mask, (lambda a: sim.push(a).motion), options


CASES = {
    "toy-0": lambda: toy_case(0),
    "toy-3": lambda: toy_case(3),
    "sim-0": lambda: sim_case(0, False),
    "sim-1": lambda: sim_case(1, False),
    "sim-model-0": lambda: sim_case(0, True),
    "sim-model-2": lambda: sim_case(2, True),
}


def summary(est) -> dict:
    """What the golden record keeps of an Estimate."""
    return {
        "com": list(est.com),
        "used": list(est.used),
        "status": est.status,
        "credible_radius_px": est.posterior.credible_radius_px,
        "entropies": [h.entropy_bits for h in est.posterior.history],
        "motions": [list(p.motion) for p in est.pushes if p.outcome != "failed"],
    }


def run(name: str) -> dict:
    """The summary of one named case."""
    mask, push, options = CASES[name]()
    return summary(comcore.estimate_active(mask, push, **options))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare instead of writing")
    args = parser.parse_args(argv)
    results = {name: run(name) for name in CASES}
    if args.check:
        golden = json.loads(OUT.read_text())
        for name, got in results.items():
            want = golden[name]
            same = got["used"] == want["used"] and got["status"] == want["status"]
            same &= np.allclose(got["com"], want["com"], atol=1e-9, rtol=0)
            print(f"{name}: {'same' if same else 'DIFFERENT'}")
        return
    OUT.write_text(json.dumps(results, indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
