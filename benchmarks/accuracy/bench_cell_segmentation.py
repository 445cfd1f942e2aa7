"""mask_from_image on a robot cell's frames: IoU per condition and option over N seeds.

Run: ``python benchmarks/accuracy/bench_cell_segmentation.py [--seeds 5]``.

Frames from ``tests/camera/cell_frames.py`` (tilted camera, wood-grain table, lamp
gradient, noise, a soft shadow, the arm in view; conditions: one object, a low-contrast
object, two objects). Each cell: the IoU with the true mask, or the refusal's first words.
"""

from __future__ import annotations

import argparse

import numpy as np

import comcore
from tests.camera.cell_frames import CONDITIONS, iou, make_cell_frame

OPTIONS = {
    "background+box": lambda f: {"background": f.background, "roi": f.box},
    "background": lambda f: {"background": f.background},
    "box": lambda f: {"roi": f.box},
    "none": lambda f: {},
}


def main(argv=None) -> None:
    """Print one row per condition and seed."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    args = parser.parse_args(argv)
    print("| condition | seed | " + " | ".join(OPTIONS) + " |")
    print("| --- | --- |" + " --- |" * len(OPTIONS))
    for condition in CONDITIONS:
        for seed in range(args.seeds):
            frame = make_cell_frame(np.random.default_rng([21, seed]), condition)
            cells = []
            for make in OPTIONS.values():
                try:
                    mask = comcore.mask_from_image(frame.image, **make(frame))
                    cells.append(f"{iou(mask.data, frame.truth):.3f}")
                except comcore.ImageError as e:
                    cells.append("refused: " + str(e).split(":")[0])
            print(f"| {condition} | {seed} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
