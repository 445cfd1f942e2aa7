"""How often comcore.mask_from_image finds the right object in camera frames, and how fast.

Run: ``python benchmarks/accuracy/bench_mask_from_image.py [--frames 20] [--seed 1]
[--conditions "even,gradient 60"] [--options default,otsu,background,roi]
[--iou 0.9] [--width 1280 --height 720] [--failures]``.

Frames come from ``simulators/frames.py`` (one generator for the tests and this
script): one object of ``--share`` of the frame (0.2 % of 1280 x 720 by
default), dark on a light table or bright on a dark one, blurred, under
each condition of ``simulators.frames.CONDITIONS`` (even light, a gradient of 60
or 100 grey levels across the frame, vignetting, a shadow over one side of
the frame, the object's cast shadow, a textured table, strong noise, all at
once, and the empty table). Frame ``i`` of condition ``c`` is drawn from
``numpy.random.default_rng([seed, c, i])``; the thresholds of
``comcore/camera/_object.py`` were tuned on seed 0, the figures in
docs/results/camera.md are for seed 1.

A frame with an object counts as found when the mask's intersection over
union with the true mask (the polygon at pixel centres) is at least
``--iou``; an empty table counts when ``mask_from_image`` raises an
ImageError saying "no object". Each option is a way to call it:

* ``default``: ``mask_from_image(image)`` (``threshold="auto"``);
* ``otsu``: ``threshold="otsu"``, one level for the whole frame (comcore 0.1);
* ``background``: ``background=`` the empty table (same light, fresh noise,
  exposure within 2 %, no shadows: taken with the arm away);
* ``roi``: ``roi=`` a box around where the object lies (at least 160 px,
  2.5 object radii each way, off-centre);
* ``background+roi``: both.

Time: the median wall time of one call (``time.perf_counter``) over every
frame of an option, and its CPU time (``time.process_time``).
"""

from __future__ import annotations

import argparse
import time
from collections import Counter

import numpy as np

import comcore
from simulators.frames import CONDITIONS, iou, make_frame

OPTIONS = {
    "default": lambda frame: {},
    "otsu": lambda frame: {"threshold": "otsu"},
    "background": lambda frame: {"background": frame.background},
    "roi": lambda frame: {"roi": frame.roi},
    "background+roi": lambda frame: {"background": frame.background, "roi": frame.roi},
}


def _split(text: str) -> list[str]:
    return [item.strip() for item in text.split(",") if item.strip()]


def run_one(frame, option: str) -> dict:
    """Call mask_from_image on one frame with one option: IoU or error, and times."""
    kwargs = OPTIONS[option](frame)
    start, start_cpu = time.perf_counter(), time.process_time()
    try:
        mask = comcore.mask_from_image(frame.image, **kwargs)
        error = None
    except comcore.ImageError as e:
        mask, error = None, str(e)
    seconds = time.perf_counter() - start
    cpu = time.process_time() - start_cpu
    if frame.truth is None:
        score = 0.0
        found = error is not None and error.startswith("no object")
    else:
        score = 0.0 if mask is None else iou(mask.data, frame.truth)
        found = None
    return {"iou": score, "error": error, "seconds": seconds, "cpu": cpu, "found": found}


def _cause(error: str | None) -> str:
    if error is None:
        return "a mask"
    for words in ("no object", "touches the image border", "touches the edge of roi",
                  "speckled", "several objects", "no bright pixel", "no dark pixel"):  # fmt: skip
        if words in error:
            return words
    return error[:40]


def main(argv=None) -> None:
    """Parse the options, run every condition and option, print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=20, help="frames per condition")
    parser.add_argument("--seed", type=int, default=1, help="seed (tuning used seed 0)")
    parser.add_argument("--conditions", default="", help="comma-separated (default: all)")
    parser.add_argument("--options", default=",".join(OPTIONS), help="comma-separated")
    parser.add_argument("--iou", type=float, default=0.9, help="IoU that counts as found")
    parser.add_argument("--width", type=int, default=1280, help="frame width, px")
    parser.add_argument("--height", type=int, default=720, help="frame height, px")
    parser.add_argument("--share", type=float, default=0.002, help="object's share of the frame")
    parser.add_argument("--failures", action="store_true", help="list what the misses were")
    args = parser.parse_args(argv)
    conditions = _split(args.conditions) or list(CONDITIONS)
    options = _split(args.options)
    for name in conditions:
        if name not in CONDITIONS:
            parser.error(f"unknown condition {name!r}; known: {', '.join(CONDITIONS)}")
    for name in options:
        if name not in OPTIONS:
            parser.error(f"unknown option {name!r}; known: {', '.join(OPTIONS)}")
    if args.frames < 1 or not 0 < args.iou <= 1 or not 0 < args.share < 0.5:
        parser.error("--frames must be >= 1, --iou in (0, 1], --share in (0, 0.5)")
    shape = (args.height, args.width)
    print(
        f"mask_from_image: {args.frames} frames per condition, {args.width} x {args.height} px, "
        f"object {100 * args.share:g} % of the frame, seed {args.seed}; found = IoU >= "
        f"{args.iou:g} with the true mask (empty table: 'no object' said)"
    )
    print("| condition | " + " | ".join(options) + " |")
    print("| --- |" + " --- |" * len(options))
    times = {option: [] for option in options}
    causes = {option: Counter() for option in options}
    for name in conditions:
        c = list(CONDITIONS).index(name)
        kwargs = {"share": args.share, **CONDITIONS[name]}
        frames = [
            make_frame(np.random.default_rng([args.seed, c, i]), shape=shape, **kwargs)
            for i in range(args.frames)
        ]
        cells = []
        for option in options:
            rows = [run_one(frame, option) for frame in frames]
            times[option] += [(r["seconds"], r["cpu"]) for r in rows]
            if frames[0].truth is None:
                hits = sum(r["found"] for r in rows)
                cells.append(f"{hits}/{len(rows)}")
                causes[option].update(
                    f"{name}: {_cause(r['error'])}" for r in rows if not r["found"]
                )
            else:
                scores = np.array([r["iou"] for r in rows])
                hits = int((scores >= args.iou).sum())
                cells.append(f"{hits}/{len(rows)} ({np.median(scores):.3f})")
                causes[option].update(
                    f"{name}: {_cause(r['error'])}" + ("" if r["error"] else f" IoU {r['iou']:.2f}")
                    for r in rows if r["iou"] < args.iou
                )  # fmt: skip
        print(f"| {name} | " + " | ".join(cells) + " |")
    print("cells: frames found / frames (median IoU over all of them, 0 for an error)")
    for option in options:
        wall = 1000 * np.median([t for t, _ in times[option]])
        cpu = 1000 * np.median([t for _, t in times[option]])
        print(f"time per call, {option}: median {wall:.1f} ms wall, {cpu:.1f} ms CPU")
    if args.failures:
        for option in options:
            for what, n in sorted(causes[option].items()):
                print(f"  miss, {option}: {what} x{n}")


if __name__ == "__main__":
    main()
