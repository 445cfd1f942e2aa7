"""The cost of an ActiveSession's first push on a wide camera frame: next_push and observe.

Run: ``python benchmarks/timing/bench_first_observe.py [--objects 5] [--repeats 1] [--seed 1]
[--width 1280 --height 720] [--share 0.002] [--resolution 0.001] [--crop PAD]``.

For each of ``--objects`` random star-shaped objects (``simulators/frames.py``,
``--share`` of the frame: 0.2 % of 1280 x 720 at 1 mm per pixel is a 4 cm
object), the first mask is the object at a random place and turn, the second
the same object turned by 0.05 rad and moved by (3, -2) px (a push's worth).
A session ``ActiveSession(mask, pusher_radius=0.004)`` is made, asked for
``next_push()`` and given ``observe(second)``; each step is timed (wall,
``time.perf_counter``, and CPU, ``time.process_time``), and the medians are
printed, with the median of the three together (the first push's whole cost).
With ``--repeats R`` each object's session is timed R times, each on fresh
copies of its masks (a mask's fields are cached per Mask object). One session
on a small mask runs first, untimed (imports, caches that are not per mask).
With ``--crop PAD`` both masks are cut to the first one's bounding box grown
by PAD pixels first: what the session costs on a mask cropped by the caller.
The machine's load shows in the wall times: compare wall with CPU.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import comcore
from simulators.frames import star_polygon

#: The second mask: the first turned by this (radians) about its centroid and moved (px).
TURN, SHIFT = 0.05, (3.0, -2.0)


def masks(rng, shape, share, resolution):
    """The object in the frame, and the same object turned and moved: two Masks."""
    h, w = shape
    poly = star_polygon(rng, share * h * w)
    poly = comcore.apply_motion(poly, rng.uniform(0, 2 * np.pi), (0.0, 0.0), (0.0, 0.0))
    reach = np.hypot(poly[:, 0], poly[:, 1]).max() + 20
    poly = poly + rng.uniform([reach, reach], [w - reach, h - reach])
    first = comcore.Mask(comcore.geometry.rasterise_polygon(poly, shape), resolution=resolution)
    moved = comcore.apply_motion(poly, TURN, SHIFT, first.centroid)
    moved_pixels = comcore.geometry.rasterise_polygon(moved, shape)
    return first, comcore.Mask(moved_pixels, resolution=resolution)


def crop(first, second, pad):
    """Both masks cut to the first one's bounding box grown by ``pad`` pixels."""
    rows = np.flatnonzero(first.data.any(axis=1))
    cols = np.flatnonzero(first.data.any(axis=0))
    box = (
        slice(max(rows[0] - pad, 0), rows[-1] + pad + 1),
        slice(max(cols[0] - pad, 0), cols[-1] + pad + 1),
    )
    return tuple(comcore.Mask(m.data[box], resolution=m.resolution) for m in (first, second))


def timed(step):
    """``step()``'s result, wall and CPU seconds."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = step()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def main(argv=None) -> None:
    """Time the first push of a session on each object; print the medians."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=5, help="objects (one session each)")
    parser.add_argument("--repeats", type=int, default=1, help="timed sessions per object")
    parser.add_argument("--seed", type=int, default=1, help="seed of the objects")
    parser.add_argument("--width", type=int, default=1280, help="frame width, px")
    parser.add_argument("--height", type=int, default=720, help="frame height, px")
    parser.add_argument("--share", type=float, default=0.002, help="object's share of the frame")
    parser.add_argument("--resolution", type=float, default=0.001, help="metres per pixel")
    parser.add_argument(
        "--crop", type=int, default=None, metavar="PAD",
        help="cut both masks to the object's box grown by PAD px first",
    )  # fmt: skip
    args = parser.parse_args(argv)
    if args.objects < 1 or args.repeats < 1 or not 0 < args.share < 0.2:
        parser.error("--objects and --repeats must be >= 1 and --share in (0, 0.2)")
    rng = np.random.default_rng(args.seed)
    warm = comcore.Mask(np.pad(np.ones((20, 30), bool), 10), resolution=0.0025)
    comcore.ActiveSession(warm, pusher_radius=0.004).next_push()
    rows = []
    for _ in range(args.objects):
        first, second = masks(rng, (args.height, args.width), args.share, args.resolution)
        if args.crop is not None:
            first, second = crop(first, second, args.crop)
        masks_ = (first, second)
        for _ in range(args.repeats):
            first, second = (comcore.Mask(m.data, resolution=m.resolution) for m in masks_)
            session, *made = timed(lambda m=first: comcore.ActiveSession(m, pusher_radius=0.004))
            _, *asked = timed(session.next_push)
            _, *observed = timed(lambda second=second, session=session: session.observe(second))
            rows.append((made, asked, observed, first.shape, first.area_px))
    widths, heights = [r[3][1] for r in rows], [r[3][0] for r in rows]
    print(
        f"first push of {len(rows)} sessions ({args.objects} objects x {args.repeats}, seed "
        f"{args.seed}): masks {min(widths)}-"
        f"{max(widths)} x {min(heights)}-{max(heights)} px, objects {min(r[4] for r in rows)} "
        f"to {max(r[4] for r in rows)} px, {args.resolution * 1000:g} mm/px, pusher radius 4 mm"
    )
    for k, name in enumerate(("ActiveSession(mask)", "next_push()", "observe(mask)")):
        wall = 1000 * np.median([r[k][0] for r in rows])
        cpu = 1000 * np.median([r[k][1] for r in rows])
        print(f"  {name}: median {wall:.0f} ms wall, {cpu:.0f} ms CPU")
    wall = 1000 * np.median([sum(r[k][0] for k in range(3)) for r in rows])
    cpu = 1000 * np.median([sum(r[k][1] for k in range(3)) for r in rows])
    print(f"  all three: median {wall:.0f} ms wall, {cpu:.0f} ms CPU")


if __name__ == "__main__":
    main()
