"""Write comcore/data/examples/: the recording ``comcore estimate --example`` runs on.

A benchmark object (Obj4, low friction, seed 13) drawn by ``simulators.random_simulator``,
40 random pushes (``comcore.sample_pushes``, cone 0.3 rad) each run in the simulator from the
initial pose, the mask as a black-and-white PNG, the pushes and their observed motions as the
CSV ``comcore estimate`` reads, and the true CoM in truth.json (to check the estimate).

Run: ``python docs/figures/make_estimate_example.py`` (needs comcore[sim]). The files are committed;
run it again only to change the example.
"""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

import numpy as np

import comcore

OBJECT, FRICTION, SEED, N_PUSHES, CONE = "Obj4", "low", 13, 40, 0.3


def main(out: Path) -> None:
    import cv2

    import simulators

    rng = np.random.default_rng(SEED)
    sim = simulators.random_simulator(OBJECT, friction=FRICTION, rng=rng)
    mask = sim.mask
    actions = comcore.sample_pushes(mask, N_PUSHES, cone=CONE, rng=rng)
    out.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(str(out / "object.png"), mask.data.astype(np.uint8) * 255)
    with (out / "pushes.csv").open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(["sx", "sy", "ex", "ey", "theta", "tx", "ty"])
        for action in actions:
            motion = sim.push(action).motion
            writer.writerow([f"{v:.3f}" for v in action] + [f"{motion.theta:.5f}",
                            f"{motion.tx:.3f}", f"{motion.ty:.3f}"])  # fmt: skip
    truth = {
        "com_px": [round(float(v), 3) for v in sim.com_px],
        "resolution": mask.resolution,
        "object": OBJECT,
        "friction": FRICTION,
        "mu_contact": round(float(sim.mu_contact), 4),
        "seed": SEED,
        "made_by": "python docs/figures/make_estimate_example.py",
    }
    (out / "truth.json").write_text(json.dumps(truth, indent=2) + "\n", encoding="utf-8")


if __name__ == "__main__":
    root = Path(__file__).resolve().parents[2]
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else root / "comcore" / "data" / "examples")
