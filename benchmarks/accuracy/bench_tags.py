"""Accuracy of tag-tracked motions (comcore.camera.track_tag) beside the masks' measure_motion.

Run: ``python benchmarks/accuracy/bench_tags.py [--trials 100] [--seed 0]
[--tag-sizes 20,30,50] [--shape star] [--area 100] [--frame 640x480] [--perspective]
[--blur 0.8] [--noise 3]``.

For each trial a random star-shaped object (``simulators.frames.star_polygon``,
``--area`` cm^2; ``--shape disc``: a disc of that area, whose turn its
outline does not show) carrying an AprilTag 36h11 marker (``--tag-sizes`` mm, the
black border's outer side, at the object's area centroid, turned at random;
an object whose outline does not hold the tag with a cell of margin is drawn
again) is rendered at 1 mm per pixel (``simulators.tag_frames``: 4 x 4
samples a pixel, Gaussian blur ``--blur`` px, noise ``--noise`` grey levels)
at a random pose, then moved by a random push motion (a turn of up to
``--max-turn`` degrees either way about its centroid and a slide of 5 to 30
mm) and rendered again. With ``--perspective`` the camera does not look
straight down (a fixed homography, given to ``track_tag``).

* **tags**: ``track_tag`` on the two frames, the motion from
  ``TagTrack.motion`` with the centroid placed in the tag's frame from the
  first frame's mask (``centroid_in_tag``), as a user would.
* **OpenCV's corners**: the same, with the corners as ``cv2.aruco`` returns
  them (contour refinement) and no edge fit: what the edge fit adds.
* **exact masks**: ``comcore.measure_motion`` on the two frames' exact masks
  (the outline rasterised at pixel centres: the masks' best case, no
  segmentation error).
* **masks from the frames**: ``comcore.measure_motion`` on
  ``comcore.mask_from_image`` of the same two frames (rectified first by
  ``cv2.warpPerspective`` with ``--perspective``; the tag's dark cells are
  holes, filled): the masks a user of the camera gets. A pair where it
  raises (``ImageError``: the tag's dark cells cut a small object in parts)
  is counted.

Motions ``measure_motion`` flags ambiguous are counted and left out of its
figures.

Errors are against the true motion (about the polygon's area centroid):
rotation in degrees, translation of the centroid in mm. A frame whose tag is
not found is counted as lost and its motion left out (never filled). Time:
wall time of ``track_tag`` per frame. Needs the ``sim`` extra (cv2).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import comcore
from comcore.camera import _tags, centroid_in_tag, track_tag
from comcore.conventions import apply_motion
from simulators.frames import star_polygon
from simulators.tag_frames import render_tag_frame

#: The camera of ``--perspective``: comcore pixels -> image pixels (a few percent of tilt).
PERSPECTIVE = np.array([[1.02, 0.04, 10.0], [-0.03, 0.99, 6.0], [6e-5, -4e-5, 1.0]])
RESOLUTION = 0.001  # metres per pixel


def area_centroid(poly: np.ndarray) -> np.ndarray:
    x, y = poly[:, 0], poly[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    return np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (3 * cross.sum())


def draw_object(rng, area_px: float, side: float, shape: str = "star"):
    """A star polygon (or disc) about its area centroid that holds the tag, grown by a cell."""
    while True:
        if shape == "disc":
            a = np.linspace(0, 2 * math.pi, 96, endpoint=False)
            poly = np.sqrt(area_px / math.pi) * np.column_stack([np.cos(a), np.sin(a)])
        else:
            poly = star_polygon(rng, area_px)
        poly = poly - area_centroid(poly)
        turn = rng.uniform(-math.pi, math.pi)
        reach = (0.5 + 1.0 / 8) * side  # half the side and a cell of margin
        corners = apply_motion(
            np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float) * reach, turn, (0, 0), (0, 0)
        )
        dense = np.concatenate(
            [np.linspace(corners[k], corners[(k + 1) % 4], 20) for k in range(4)]
        )
        if _inside(dense, poly).all():
            return poly, turn


def _inside(points, poly):
    x, y = points[:, 0], points[:, 1]
    inside = np.zeros(len(points), bool)
    for (ax, ay), (bx, by) in zip(poly, np.roll(poly, -1, axis=0)):
        crosses = (ay > y) != (by > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            inside ^= crosses & (x < ax + (y - ay) * (bx - ax) / (by - ay))
    return inside


def opencv_pose(image, tag_id, back):
    """The pose from cv2.aruco's own corners (contour refinement), no edge fit."""
    cv2, d = _tags._aruco_dictionary("apriltag_36h11")
    params = cv2.aruco.DetectorParameters()
    params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_CONTOUR
    found, corners = _tags._find(cv2.aruco.ArucoDetector(d, params), image, tag_id)
    return _tags._pose_from_corners(_tags._apply(back, corners)) if found == "found" else None


def motion_error(m, truth) -> tuple[float, float]:
    rot = abs(math.degrees(math.remainder(m.theta - truth.theta, 2 * math.pi)))
    return rot, math.hypot(m.tx - truth.tx, m.ty - truth.ty) * RESOLUTION * 1000


def run(args, side: float) -> dict:
    rng = np.random.default_rng([args.seed, round(side * 10)])
    rows, cols = args.frame[1], args.frame[0]
    camera = PERSPECTIVE if args.perspective else np.eye(3)
    back = np.linalg.inv(camera)
    out = {"tags": [], "opencv": [], "exact": [], "segmented": [], "lost": 0, "frames": 0}
    out["ambiguous"] = {"exact": 0, "segmented": 0}
    out["unsegmented"] = 0
    cv2 = _tags._cv2()
    seconds = 0.0
    for _ in range(args.trials):
        poly, turn = draw_object(rng, args.area * 100.0, side, args.shape)
        tag_id = int(rng.integers(0, 587))
        reach = np.hypot(poly[:, 0], poly[:, 1]).max() + 35
        start = rng.uniform([reach, reach], [cols - reach, rows - reach])
        theta0 = rng.uniform(-math.pi, math.pi)
        dtheta = math.radians(rng.uniform(-args.max_turn, args.max_turn))
        angle = rng.uniform(-math.pi, math.pi)
        slide = rng.uniform(5.0, 30.0) * np.array([math.cos(angle), math.sin(angle)])
        end = np.clip(start + slide, reach, [cols - reach, rows - reach])
        poses = [(theta0, start), (theta0 + dtheta, end)]
        frames, masks = [], []
        for theta, at in poses:
            outline = apply_motion(poly, theta, at, (0.0, 0.0))
            frames.append(
                render_tag_frame(
                    outline,
                    at,
                    theta + turn,
                    side,
                    tag_id=tag_id,
                    shape=(rows, cols),
                    image_from_pixels=camera,
                    blur=args.blur,
                    noise=args.noise,
                    rng=rng,
                )
            )
            raster = comcore.geometry.rasterise_polygon(outline, (rows, cols))
            masks.append(comcore.Mask(raster, resolution=RESOLUTION))
        truth = comcore.Motion(dtheta, *(end - start))
        tic = time.perf_counter()
        track = track_tag(frames, tag_id, pixels_from_image=back)
        seconds += time.perf_counter() - tic
        out["frames"] += 2
        out["lost"] += len(track.lost)
        if not track.lost:
            offset = centroid_in_tag(track.poses[0], masks[0])
            out["tags"].append(motion_error(track.motion(0, 1, offset), truth))
        raw = [opencv_pose(f, tag_id, back) for f in frames]
        if None not in raw:
            offset = centroid_in_tag(raw[0], masks[0])
            out["opencv"].append(motion_error(_tags.motion_from_tags(*raw, offset), truth))
        try:
            seen = [
                comcore.mask_from_image(
                    cv2.warpPerspective(f, back, (cols, rows), flags=cv2.INTER_LINEAR)
                    if args.perspective
                    else f,
                    object="bright",
                    resolution=RESOLUTION,
                )
                for f in frames
            ]
        except comcore.ImageError:  # e.g. the tag's dark cells cut a small object in parts
            out["unsegmented"] += 1
            seen = None
        for kind, pair in (("exact", masks), ("segmented", seen)):
            if pair is None:
                continue
            measured = comcore.measure_motion(*pair)
            if measured.ambiguous:
                out["ambiguous"][kind] += 1
            else:
                out[kind].append(motion_error(measured.motion, truth))
    out["ms_per_frame"] = 1000 * seconds / max(out["frames"], 1)
    return out


def summary(name: str, errors) -> str:
    if not errors:
        return f"  {name}: no motions"
    e = np.asarray(errors)
    med, p90 = np.median(e, axis=0), np.percentile(e, 90, axis=0)
    return (
        f"  {name} ({len(e)} motions): rotation median {med[0]:.3f} deg, p90 {p90[0]:.3f} deg; "
        f"translation median {med[1]:.3f} mm, p90 {p90[1]:.3f} mm"
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--tag-sizes", default="20,30,50", help="marker sides, mm")
    parser.add_argument("--shape", choices=("star", "disc"), default="star")
    parser.add_argument("--area", type=float, default=100.0, help="object area, cm^2")
    parser.add_argument("--frame", default="640x480", help="WxH pixels")
    parser.add_argument("--perspective", action="store_true")
    parser.add_argument("--blur", type=float, default=0.8)
    parser.add_argument("--noise", type=float, default=3.0)
    parser.add_argument("--max-turn", type=float, default=30.0, help="degrees")
    args = parser.parse_args(argv)
    args.frame = tuple(int(v) for v in args.frame.lower().split("x"))
    camera = "perspective" if args.perspective else "straight down"
    for side_mm in (float(v) for v in args.tag_sizes.split(",") if v.strip()):
        side = side_mm / (RESOLUTION * 1000)
        result = run(args, side)
        print(
            f"tag {side_mm:g} mm ({side / 8:.2f} px per cell) on a {args.shape} of "
            f"{args.area:g} cm^2, 1 mm/px, {camera}, "
            f"{args.trials} motions (seed {args.seed}), blur {args.blur:g} px, "
            f"noise {args.noise:g}"
        )
        print(summary("tags", result["tags"]))
        print(summary("OpenCV's corners", result["opencv"]))
        print(summary("exact masks", result["exact"]))
        print(summary("masks from the frames", result["segmented"]))
        flagged = result["ambiguous"]
        print(
            f"  lost frames: {result['lost']} of {result['frames']}; masks flagged ambiguous: "
            f"{flagged['exact']} exact, {flagged['segmented']} from the frames; "
            f"frame pairs mask_from_image refused: {result['unsegmented']}; "
            f"track_tag {result['ms_per_frame']:.1f} ms per frame"
        )


if __name__ == "__main__":
    main()
