"""Which camera masks ``ActiveSession.observe`` refuses: honest noisy masks, foreign masks.

For each benchmark object (low friction): ``simulators.SimulatedRobot`` with noisy camera
masks (``--mask-noise``, the benchmark's 0.5 by default) drives an ``ActiveSession`` (its
defaults) for up to ``--pushes`` pushes; every mask the camera gives after a push is observed.
A refusal of one of these honest masks is a false refusal. Then, with a push waiting, the
session is shown foreign masks: every other benchmark object's first mask placed where the
object is (centroid on centroid), and a single pixel; each must be refused, the session left
unchanged (its next push the same).

    python benchmarks/accuracy/observe_refusal.py --seed 1     # the thresholds were chosen on these
    python benchmarks/accuracy/observe_refusal.py --seed 0     # reported
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import comcore
from comcore.camera._pose_tracking import MAX_AREA_CHANGE, MAX_RESIDUAL_PX, measure_pose


def _placed(mask: comcore.Mask, shape, centre) -> np.ndarray:
    """``mask``'s object moved so that its centroid lies at ``centre`` in an image of ``shape``."""
    out = np.zeros(shape, bool)
    rows, cols = np.nonzero(mask.data)
    rr = np.rint(rows - mask.centroid[1] + centre[1]).astype(int)
    cc = np.rint(cols - mask.centroid[0] + centre[0]).astype(int)
    inside = (rr >= 1) & (rr < shape[0] - 1) & (cc >= 1) & (cc < shape[1] - 1)
    out[rr[inside], cc[inside]] = True
    return out


def _refused(session, mask) -> bool:
    """Whether ``observe(mask)`` refuses ``mask`` as not the object (the session unchanged)."""
    before = session.next_push()
    try:
        session.observe(mask)
    except ValueError as e:
        if "not the first mask's object" not in str(e):
            raise
        if session.next_push() != before or session.status != "waiting_observation":
            raise RuntimeError("a refused mask changed the session") from e
        return True
    return False


def main(argv=None) -> None:
    import simulators

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--objects", default=",".join(simulators.BENCHMARK_OBJECTS))
    parser.add_argument("--pushes", type=int, default=5)
    parser.add_argument("--mask-noise", type=float, default=0.5)
    args = parser.parse_args(argv)
    names = [o.strip() for o in args.objects.split(",") if o.strip()]
    start = time.perf_counter()
    firsts, residuals, areas, false_refusals = {}, [], [], []
    for i, name in enumerate(names):
        sim = simulators.random_simulator(name, "low", rng=[args.seed, i])
        robot = simulators.SimulatedRobot(sim, mask_noise=args.mask_noise, rng=[args.seed, i])
        first = firsts[name] = robot.camera_mask()
        session = comcore.ActiveSession(
            first, stop=comcore.StopRule(max_pushes=args.pushes), rng=[args.seed, i]
        )
        while not session.done:
            robot.execute(session.next_push())
            mask = robot.camera_mask()
            reading = measure_pose(first, mask, session.pose)
            residuals.append(reading.residual_px)
            areas.append(mask.area_px / first.area_px - 1.0)
            if _refused(session, mask):
                false_refusals.append(name)
                break
    foreign = {"another object": [0, 0], "a single pixel": [0, 0]}
    for name, first in firsts.items():
        session = comcore.ActiveSession(first, rng=args.seed)
        for other, mask in firsts.items():
            if other != name:
                placed = comcore.Mask(_placed(mask, first.shape, first.centroid), first.resolution)
                foreign["another object"][0] += _refused(session, placed)
                foreign["another object"][1] += 1
        pixel = np.zeros(first.shape, bool)
        pixel[round(first.centroid[1]), round(first.centroid[0])] = True
        foreign["a single pixel"][0] += _refused(session, comcore.Mask(pixel, first.resolution))
        foreign["a single pixel"][1] += 1
    r, a = np.asarray(residuals), np.abs(areas)
    print(f"seed {args.seed}, mask_noise {args.mask_noise:g}, {len(names)} objects, "
          f"{time.perf_counter() - start:.0f} s; thresholds: residual {MAX_RESIDUAL_PX:g} px, "
          f"area change {100 * MAX_AREA_CHANGE:.0f} %")  # fmt: skip
    print(f"honest masks: {len(r)}; residual median {np.median(r):.2f} px, max {r.max():.2f} px; "
          f"area change max {100 * a.max():.1f} %; refused {len(false_refusals)} "
          f"({100 * len(false_refusals) / len(r):.1f} %) {false_refusals}")  # fmt: skip
    for what, (refused, n) in foreign.items():
        print(f"{what}: refused {refused} of {n} ({100 * refused / n:.1f} %)")


if __name__ == "__main__":
    main()
