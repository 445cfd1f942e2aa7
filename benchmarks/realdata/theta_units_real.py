"""The theta-in-degrees check on real pushes: its false alarms on honest recordings.

``comcore.estimate_posterior`` (``theta_units="auto"``) and ``comcore estimate`` refuse a
recording when every theta multiplied by pi/180 raises its log evidence under the motion model
by more than ``comcore.active._posterior.DEGREES_NATS`` (chosen on simulated recordings by
``benchmarks/calibration/theta_units.py``). This script measures that gain on the MIT push
dataset's recorded pushes (radians, as recorded: every alarm is a false one), for seeded random
subsets of k pushes and all pushes, per plate, and on the same subsets with theta written in
degrees (detections; only the subsets whose every turn is under pi in degrees count, the others
are refused by the simpler check that theta is at most pi).

    python benchmarks/realdata/theta_units_real.py DATA            # all five plates
    python benchmarks/realdata/theta_units_real.py DATA --objects butter --subsets 3  # short

``DATA`` is the dataset folder (``abs/train``, ``abs/test_butter``, ``shapes.json``;
docs/how-to/recordings.md says where it comes from). Nothing is tuned here: the margin is the
library's.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import real_push_runs as runs

import comcore.recordings.mit_push as mp
from comcore.active._posterior import DEGREES_NATS, theta_degrees_nats

OBJECTS = (*runs.SPLITS["train"], *runs.SPLITS["test"])


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("data", help="the dataset folder (abs/train, abs/test_butter, shapes.json)")
    p.add_argument("--objects", default=",".join(OBJECTS))
    p.add_argument("--ks", default="5,8", help="subset sizes (all pushes are always scored)")
    p.add_argument("--subsets", type=int, default=10, help="random subsets per k")
    p.add_argument("--travel", type=float, default=0.03, help="metres after first contact")
    p.add_argument("--resolution", type=float, default=0.0025, help="metres per pixel")
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args(argv)
    runs.use_contacts("disc")
    shapes = runs.outlines(args.data)
    ks = [int(k) for k in args.ks.split(",") if k]
    print(f"margin {DEGREES_NATS:g} nats; gain = log evidence with theta*pi/180 minus as given")
    print("| plate | k | recordings | gain median | gain max | false alarms | "
          "degrees recordings (all turns < pi) | detected |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    totals = np.zeros(4, int)
    start = time.perf_counter()
    for name in args.objects.split(","):
        obj = runs.load_object(
            args.data, name, shapes[name], travel=args.travel, resolution=args.resolution
        )
        n = len(obj.actions)
        sets = {k: runs.subsets(n, k, args.subsets, args.seed, 7) for k in ks if k < n}
        sets["all"] = [np.arange(n)]
        for k, idxs in sets.items():
            honest, degrees = [], []
            for idx in idxs:
                actions, motions = obj.actions[idx], obj.motions["real"][idx]
                options = {"pusher_radius": mp.PUSHER_RADIUS}
                honest.append(theta_degrees_nats(obj.mask, actions, motions, **options))
                as_degrees = motions * [180 / math.pi, 1.0, 1.0]
                if np.all(np.abs(as_degrees[:, 0]) <= math.pi):
                    degrees.append(theta_degrees_nats(obj.mask, actions, as_degrees, **options))
            honest, degrees = np.array(honest), np.array(degrees)
            alarms = int((honest > DEGREES_NATS).sum())
            detected = int((degrees > DEGREES_NATS).sum())
            totals += (len(honest), alarms, len(degrees), detected)
            gains = f"{np.median(honest):.1f} | {honest.max():.1f}"
            print(f"| {name} | {k} | {len(honest)} | {gains} | {alarms} | {len(degrees)} | "
                  f"{detected} |")  # fmt: skip
    print(f"\ntotal: {totals[1]} false alarms in {totals[0]} honest recordings; "
          f"{totals[3]} of {totals[2]} degrees recordings detected "
          f"({time.perf_counter() - start:.0f} s)")  # fmt: skip


if __name__ == "__main__":
    main()
