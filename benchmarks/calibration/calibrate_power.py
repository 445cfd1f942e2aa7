"""Choose a fixed model power per condition from runs with a known CoM.

Loads the runs ``benchmarks/calibration/tune_active.py --keep-pushes`` recorded and, per
condition, scores their pushes again under fixed powers of the model's
likelihood with :func:`comcore.calibrate_model_weight`, as a user would with
calibration objects whose CoM they measured: how often each power's 90 %
region held the CoM, its mean radius and error, and the recommended power (the
largest that held the CoM at least 90 % of the time). Calibrate on seed 1, then
measure the recommended powers on seed 0 (docs/explanation/calibration.md).

Usage::

    PYTHONPATH=. python benchmarks/calibration/tune_active.py --seed 1 --trials 2 \\
        --conditions exact,pymunk --estimators active --keep-pushes runs.pkl
    PYTHONPATH=. python benchmarks/calibration/calibrate_power.py runs.pkl
"""

from __future__ import annotations

import argparse
import pickle
import time
from concurrent.futures import ProcessPoolExecutor

from replay import has_evidence  # this folder is on the path


def _calibrate(job):
    import comcore

    cond, kept, powers = job
    records = []
    for k in kept:
        mask = comcore.Mask(k["mask"], resolution=k["resolution"])
        # the session's record as an Estimate holds it: its pushes, with the camera's readings
        est = comcore.Estimate(com=mask.centroid, com_m=mask.centroid_m, region=mask.data,
                               pushes=k["pushes"])  # fmt: skip
        records.append((mask, est, k["true_px"]))
    return cond, comcore.calibrate_model_weight(records, pusher_radius=0.004, powers=powers)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("runs", help="pickle written by tune_active.py --keep-pushes")
    p.add_argument("--powers", default="0.25,0.4,0.6,0.8,1.0")
    p.add_argument("--conditions", default=None, help="only these (comma-separated)")
    p.add_argument("--workers", type=int, default=2)
    args = p.parse_args(argv)
    powers = tuple(float(v) for v in args.powers.split(","))
    with open(args.runs, "rb") as f:
        rows = [r for r in pickle.load(f) if r.get("pushes_kept") is not None]
    rows = [r for r in rows if has_evidence(r["pushes_kept"])]
    conds = list(dict.fromkeys(r["condition"] for r in rows))
    if args.conditions:
        conds = [c for c in conds if c in args.conditions.split(",")]
    start = time.time()
    jobs = [(c, [r["pushes_kept"] for r in rows if r["condition"] == c], powers) for c in conds]
    with ProcessPoolExecutor(args.workers) as pool:
        for cond, cal in pool.map(_calibrate, jobs):
            cells = " | ".join(
                f"{p:g}: {100 * c:.0f} % (>= {100 * lo:.0f} %) / {1000 * r:.2f} mm / "
                f"{100 * e:.3f} cm"
                for p, c, lo, r, e in zip(
                    cal.powers, cal.coverage, cal.coverage_low, cal.radius_m, cal.error_m
                )
            )
            print(f"{cond:15s} n={cal.n_objects} recommended {cal.recommended:g} | {cells}")
    print(f"{len(rows)} runs, {time.time() - start:.0f} s")


if __name__ == "__main__":
    main()
