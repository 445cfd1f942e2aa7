"""Accuracy and speed of comcore.measure_motion on simulated 3 cm pushes.

Run: ``python benchmarks/accuracy/bench_measure_motion.py [--trials 3] [--seed 1]
[--resolutions 0.0025,0.001,0.005] [--objects Obj1,Obj7] [--mask-flip 0.2] [--per-object]
[--frame 1280x720]``.

For every benchmark object, friction class and trial, a random simulator
(``simulators.random_simulator``, camera margin ``--margin`` metres so that the
pushed object stays in view) makes one push from ``comcore.sample_pushes``
(3 cm of travel after contact, directions within 0.3 rad of the normal); the
before mask is ``sim.mask``, the after mask ``sim.mask_at(result.pose)`` and the
truth ``result.motion`` (a push that takes the object out of the image is drawn
again, and counted) (about ``sim.mask``'s area centroid, the convention of
``measure_motion``). Theta errors are taken modulo ``2 pi / symmetry`` (the
function returns the smallest rotation consistent with a symmetric outline);
pushes that turned a symmetric object by more than ``pi / symmetry`` are
counted. The figures are on the shapes not flagged ``ambiguous``; the flagged
ones are counted. ``--mask-flip p`` adds mask noise: each outline pixel of both
masks (inside or outside) flipped with probability ``p``, holes filled, the
largest component kept. Time: wall time of one call (``time.perf_counter``) and its
CPU time (``time.process_time``: what it costs on a machine others share).
``--frame WxH`` places both masks in the middle of a camera frame of that size
(the fit works on a window around the two objects, so only the time of
finding that window should grow; the largest difference from the motion
measured on the masks alone is printed). Needs the ``sim`` extra.
"""

from __future__ import annotations

import argparse
import math
import time
from collections import Counter

import numpy as np
from scipy import ndimage

import comcore


def _parse_list(text: str, kind=str) -> list:
    return [kind(item) for item in text.split(",") if item.strip()]


def noisy(mask: comcore.Mask, flip: float, rng: np.random.Generator) -> comcore.Mask:
    """The mask with each outline pixel (inside or outside) flipped with probability ``flip``.

    Holes are then filled and the largest component kept, as mask_from_image does.
    """
    if flip == 0:
        return mask
    data = mask.data
    edge = (data & ~ndimage.binary_erosion(data)) | (ndimage.binary_dilation(data) & ~data)
    out = ndimage.binary_fill_holes(data ^ (edge & (rng.random(data.shape) < flip)))
    return comcore.Mask(comcore.geometry.largest_component(out), resolution=mask.resolution)


def in_frame(mask: comcore.Mask, frame: tuple[int, int] | None) -> comcore.Mask:
    """The mask placed in the middle of a wider camera frame (rows, columns), if one is given."""
    if frame is None:
        return mask
    h, w = mask.shape
    if h > frame[0] or w > frame[1]:
        raise ValueError(f"a {w} x {h} mask does not fit in a {frame[1]} x {frame[0]} frame")
    top, left = (frame[0] - h) // 2, (frame[1] - w) // 2
    data = np.zeros(frame, bool)
    data[top : top + h, left : left + w] = mask.data
    return comcore.Mask(data, resolution=mask.resolution)


def run(
    resolution: float, objects, trials: int, seed: int, margin: float, flip: float = 0.0,
    frame: tuple[int, int] | None = None,
) -> list[dict]:
    """One row per push: the errors, the flags and the time of measure_motion.

    With ``frame`` (rows, columns) both masks are placed in a camera frame of
    that size first (the same offset: the motion does not change), and the
    row records how far the motion is from the one measured on the masks
    themselves (``frame_difference``: rounding only).
    """
    import simulators
    from comcore.camera._registration import _measure  # the same fit, with its diagnostics

    rng = np.random.default_rng([seed, round(resolution * 1e6)])
    rows = []
    for name in objects:
        for friction in ("low", "high"):
            for _ in range(trials):
                sim = simulators.random_simulator(
                    name, friction, rng=rng, resolution=resolution, margin=margin
                )
                redrawn = -1
                while True:  # a push that takes the object out of view is drawn again
                    redrawn += 1
                    action = comcore.sample_pushes(sim.mask, 1, cone=0.3, rng=rng)[0]
                    res = sim.push(action)
                    after = sim.mask_at(res.pose)
                    d = after.data
                    if not (d[0].any() or d[-1].any() or d[:, 0].any() or d[:, -1].any()):
                        break
                before = noisy(sim.mask, flip, rng)
                after = noisy(after, flip, rng)
                alone = comcore.measure_motion(before, after) if frame else None
                before, after = in_frame(before, frame), in_frame(after, frame)
                start, start_cpu = time.perf_counter(), time.process_time()
                m = comcore.measure_motion(before, after)
                seconds = time.perf_counter() - start
                cpu_seconds = time.process_time() - start_cpu
                visibility = _measure(before, after)[1]["visibility"]
                period = 2 * math.pi / m.symmetry
                error = abs((m.motion.theta - res.motion.theta + period / 2) % period - period / 2)
                rows.append(
                    {
                        "object": name,
                        "theta_error_deg": math.degrees(error),
                        "translation_error_px": math.hypot(
                            m.motion.tx - res.motion.tx, m.motion.ty - res.motion.ty
                        ),
                        "true_theta_deg": math.degrees(res.motion.theta),
                        "beyond_symmetry": abs(res.motion.theta) > period / 2,
                        "ambiguous": m.ambiguous,
                        "symmetry": m.symmetry,
                        "residual_px": m.residual_px,
                        "seconds": seconds,
                        "cpu_seconds": cpu_seconds,
                        "visibility": visibility,
                        "shape": before.shape,
                        "frame_difference": (
                            0.0 if alone is None
                            else float(np.max(np.abs(np.subtract(m.motion, alone.motion))))
                        ),
                        "redrawn": redrawn,
                    }
                )
    return rows


def report(
    rows: list[dict], resolution: float, trials: int, seed: int, per_object: bool, flip: float,
    framed: bool = False,
) -> None:
    """Print the summary of one resolution (and a line per object if asked)."""
    objects = sorted({r["object"] for r in rows}, key=lambda n: int(n[3:]))
    sizes = np.array([r["shape"] for r in rows])
    noise = f", outline pixels flipped with p={flip:g}" if flip else ""
    print(
        f"resolution {resolution * 1000:g} mm/px{noise}: {len(rows)} pushes "
        f"({len(objects)} objects x 2 friction classes x {trials}, seed {seed}), "
        f"images {sizes.min(axis=0).tolist()} to {sizes.max(axis=0).tolist()} px"
    )
    clear = [r for r in rows if not r["ambiguous"]]
    flagged = Counter(r["object"] for r in rows if r["ambiguous"])
    if clear:
        theta = np.array([r["theta_error_deg"] for r in clear])
        print(
            f"  theta error, {len(clear)} unflagged: median {np.median(theta):.3f} deg, "
            f"p95 {np.percentile(theta, 95):.3f} deg, max {theta.max():.3f} deg"
        )
    shift = np.array([r["translation_error_px"] for r in rows])
    print(
        f"  translation error, all: median {np.median(shift):.3f} px, "
        f"p95 {np.percentile(shift, 95):.3f} px, max {shift.max():.3f} px"
    )
    flagged_text = ", ".join(f"{k} x{v}" for k, v in sorted(flagged.items())) or "none"
    print(f"  flagged ambiguous: {sum(flagged.values())} ({flagged_text})")
    low = min(rows, key=lambda r: r["visibility"])
    high = max(rows, key=lambda r: r["visibility"])
    print(
        f"  rotation visibility: {low['visibility']:.2f} ({low['object']}) to "
        f"{high['visibility']:.2f} ({high['object']})"
    )
    redrawn = sum(r["redrawn"] for r in rows)
    print(f"  pushes redrawn because the object left the camera image: {redrawn}")
    if framed:
        worst = max(r["frame_difference"] for r in rows)
        print(
            "  in the camera frame against the masks alone: largest difference of a motion "
            f"component {worst:.2g}"
        )
    symmetry = Counter(r["symmetry"] for r in rows)
    beyond = sum(r["beyond_symmetry"] for r in rows)
    print(
        f"  symmetry reported: {dict(sorted(symmetry.items()))}; pushes turning a symmetric "
        f"object beyond pi/n: {beyond}"
    )
    seconds = np.array([r["seconds"] for r in rows]) * 1000
    cpu = np.array([r["cpu_seconds"] for r in rows]) * 1000
    print(
        f"  time per call: median {np.median(seconds):.1f} ms wall "
        f"(p10 {np.percentile(seconds, 10):.1f}, p90 {np.percentile(seconds, 90):.1f}), "
        f"{np.median(cpu):.1f} ms CPU"
    )
    if per_object:
        for name in objects:
            mine = [r for r in rows if r["object"] == name]
            theta = [r["theta_error_deg"] for r in mine if not r["ambiguous"]]
            shift = [r["translation_error_px"] for r in mine]
            theta_text = f"{np.median(theta):.3f}" if theta else "-"
            print(
                f"    {name}: theta median {theta_text} deg, translation median "
                f"{np.median(shift):.3f} px, symmetry {sorted({r['symmetry'] for r in mine})}, "
                f"ambiguous {sum(r['ambiguous'] for r in mine)}/{len(mine)}"
            )


def random_polygon(rng: np.random.Generator, size: float) -> np.ndarray:
    """A star-shaped, regular or rectangular polygon about the origin, ``size`` px across."""
    kind = rng.choice(["star", "regular", "rectangle"])
    if kind == "rectangle":
        aspect = rng.uniform(1.2, 4.0)
        half = 1 / aspect
        return np.array([[-1, -half], [1, -half], [1, half], [-1, half]]) * size
    k = int(rng.integers(3, 10 if kind == "star" else 9))
    if kind == "star":
        angles = np.sort(rng.uniform(0, 2 * np.pi, k))
        radii = rng.uniform(0.45, 1.0, k) * size
    else:
        angles, radii = np.arange(k) * 2 * np.pi / k, np.full(k, size)
    return np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])


def calibrate(n: int, seed: int) -> None:
    """The figures behind OUTLINE_NOISE_PX and REFERENCE_RESIDUAL_PX, and disc visibilities."""
    from comcore.camera._registration import _measure

    rng = np.random.default_rng(seed)
    scores, residuals, clear_errors = [], [], []
    while len(scores) < n:
        size = rng.uniform(8, 50)
        side = int(2 * size + 40)
        centre = np.array([side / 2, side / 2])
        v0 = comcore.apply_motion(random_polygon(rng, size) + centre, rng.uniform(0, 2 * np.pi),
                                  (0.0, 0.0), centre)  # fmt: skip
        img = comcore.geometry.rasterise_polygon(v0, (side, side))
        if img.sum() < 30 or comcore.geometry.largest_component(img).sum() != img.sum():
            continue
        before = comcore.Mask(img)
        theta, shift = rng.uniform(-0.5, 0.5), rng.uniform(-5, 5, 2)
        img = comcore.geometry.rasterise_polygon(
            comcore.apply_motion(v0, theta, shift, before.centroid), (side, side)
        )
        if comcore.geometry.largest_component(img).sum() != img.sum():
            continue
        m, info = _measure(before, comcore.Mask(img))
        period = 2 * math.pi / m.symmetry
        error = abs((m.motion.theta - theta + period / 2) % period - period / 2)
        scores.append(error * math.sqrt(info["theta_information"]))
        residuals.append(m.residual_px)
        if not m.ambiguous:
            clear_errors.append(math.degrees(error))
    print(
        f"{n} random polygons (seed {seed}, 8 to 50 px): 68th percentile of |theta error| * "
        f"sqrt(information) {np.percentile(scores, 68):.3f} px; residual_px median "
        f"{np.median(residuals):.3f}, 90th percentile {np.percentile(residuals, 90):.3f} px"
    )
    if clear_errors:
        print(
            f"  theta error, {len(clear_errors)} unflagged: median {np.median(clear_errors):.3f} "
            f"deg, p95 {np.percentile(clear_errors, 95):.3f} deg, max {max(clear_errors):.3f} deg"
        )
    shapes = [(f"disc radius {r} px", r, 1.0, 180) for r in (6, 15, 40)]
    shapes += [("ellipse 1.1:1", 25, 1.1, 120), ("ellipse 1.2:1", 25, 1.2, 120)]
    shapes += [("regular octagon", 25, 1.0, 8), ("regular hexagon", 30, 1.0, 6)]
    for label, radius, aspect, k in shapes:
        t = np.arange(k) * 2 * np.pi / k + 0.37
        v0 = np.column_stack([radius * aspect * np.cos(t), radius * np.sin(t)]) + 60.0
        before = comcore.Mask(comcore.geometry.rasterise_polygon(v0, (120, 120)))
        moved = comcore.apply_motion(v0, 0.2, (2.0, 1.0), before.centroid)
        after = comcore.Mask(comcore.geometry.rasterise_polygon(moved, (120, 120)))
        _, info = _measure(before, after)
        print(f"  {label}: visibility {info['visibility']:.2f}")


def main(argv=None) -> None:
    """Parse the options, run every resolution and print its summary."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=3, help="pushes per object and friction")
    parser.add_argument("--seed", type=int, default=1, help="seed (tuning used seed 0)")
    parser.add_argument("--resolutions", default="0.0025", help="metres per pixel, comma-separated")
    parser.add_argument("--objects", default="", help="comma-separated (default: all 20)")
    parser.add_argument("--margin", type=float, default=0.08, help="camera margin, metres")
    parser.add_argument(
        "--mask-flip", type=float, default=0.0, help="mask noise: outline pixel flip probability"
    )
    parser.add_argument("--per-object", action="store_true", help="one line per object too")
    parser.add_argument(
        "--frame", default="", metavar="WxH",
        help="place both masks in a camera frame of W x H pixels (e.g. 1280x720) first",
    )  # fmt: skip
    parser.add_argument(
        "--calibrate", type=int, default=0, metavar="N",
        help="instead: the calibration on N random polygons (seed --seed; it used 0)",
    )  # fmt: skip
    args = parser.parse_args(argv)
    if args.trials < 1:
        parser.error(f"--trials must be at least 1, got {args.trials}")
    if not 0 <= args.mask_flip <= 1:
        parser.error(f"--mask-flip must be in [0, 1], got {args.mask_flip}")
    frame = None
    if args.frame:
        try:
            width, height = (int(v) for v in args.frame.lower().split("x"))
        except ValueError:
            parser.error(f"--frame must be W x H in pixels, like 1280x720, got {args.frame!r}")
        frame = (height, width)
    if args.calibrate:
        calibrate(args.calibrate, args.seed)
        return
    import simulators

    objects = _parse_list(args.objects) or list(simulators.BENCHMARK_OBJECTS)
    for resolution in _parse_list(args.resolutions, float):
        rows = run(resolution, objects, args.trials, args.seed, args.margin, args.mask_flip, frame)
        report(
            rows, resolution, args.trials, args.seed, args.per_object, args.mask_flip,
            framed=frame is not None,
        )  # fmt: skip


if __name__ == "__main__":
    main()
