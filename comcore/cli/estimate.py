"""``comcore estimate``: the CoM of your own object from a mask image and a CSV of pushes.

The mask is a PNG (or any image OpenCV or matplotlib reads) seen from above:
pixels brighter than 127 in grayscale are the object. The CSV has one row per
push with the columns ``sx, sy, ex, ey`` (the pusher's path in pixels, x =
column, y = row down) and ``theta, tx, ty`` (the observed rotation in radians,
counter-clockwise on screen, and the displacement of the mask's area centroid
in pixels): the conventions of :mod:`comcore._conventions`.
"""

from __future__ import annotations

import csv
import json
import math
import sys
from pathlib import Path

import numpy as np

import comcore

HELP = "estimate the CoM of your object from a mask image and a CSV of observed pushes"

COLUMNS = ("sx", "sy", "ex", "ey", "theta", "tx", "ty")
METHODS = ("alg1", "alg2", "alg2-rotation", "centroid")


class InputError(ValueError):
    """A problem with the user's files, reported as one line on stderr."""


class NoPlotting(InputError):
    """matplotlib, which draws the overlay, is not installed."""


def add_arguments(parser) -> None:
    """Options of ``comcore estimate``."""
    add = parser.add_argument
    add("--mask", required=True, help="image of the object seen from above (> 127 = object)")
    add("--pushes", required=True, help="CSV with columns " + ", ".join(COLUMNS))
    add("--resolution", type=float, default=comcore.DEFAULT_RESOLUTION, help="metres per pixel")
    add("--method", choices=METHODS, default="alg2", help="estimator (default alg2)")
    add("--json", action="store_true", help="print one JSON object instead of text")
    picture = parser.add_mutually_exclusive_group()
    picture.add_argument(
        "--overlay",
        metavar="PNG",
        help="where to write the picture of the mask, pushes, region and estimate "
        "(default: MASK_STEM-overlay.png next to the mask)",
    )
    picture.add_argument("--no-overlay", action="store_true", help="write no picture")


def overlay_path(args) -> Path | None:
    """Where the overlay goes: ``--overlay``, else ``<mask stem>-overlay.png`` beside the mask.

    ``None`` with ``--no-overlay``.

    Examples
    --------
    >>> import argparse
    >>> str(overlay_path(argparse.Namespace(mask="data/cup.png", overlay=None, no_overlay=False)))
    'data/cup-overlay.png'
    >>> overlay_path(argparse.Namespace(mask="cup.png", overlay=None, no_overlay=True)) is None
    True
    """
    if getattr(args, "no_overlay", False):
        return None
    if getattr(args, "overlay", None):
        return Path(args.overlay)
    mask = Path(args.mask)
    return mask.with_name(f"{mask.stem}-overlay.png")


def read_mask(path, resolution: float) -> comcore.Mask:
    """The object mask of an image file: grayscale > 127 is the object."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"--mask: no such file: {path}")
    image = None
    try:
        import cv2

        image = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    except ImportError:
        try:
            from matplotlib import image as mpimg

            rgb = np.asarray(mpimg.imread(path), float)
            rgb = rgb * 255.0 if rgb.max() <= 1.0 else rgb
            image = rgb if rgb.ndim == 2 else rgb[..., :3].mean(axis=2)
        except ImportError as e:
            raise InputError("--mask: reading images needs pip install comcore[sim]") from e
        except Exception:  # matplotlib raises several types on a bad file
            image = None
    if image is None:
        raise InputError(f"--mask: cannot read {path} as an image")
    try:
        return comcore.Mask(np.asarray(image) > 127, resolution=resolution)
    except (TypeError, ValueError) as e:
        raise InputError(f"--mask: {path}: {e} (object pixels must be brighter than 127)") from e


def read_pushes(path) -> tuple[np.ndarray, np.ndarray]:
    """Actions (n, 4) and motions (n, 3) from a CSV with the columns :data:`COLUMNS`."""
    path = Path(path)
    try:
        with path.open(newline="", encoding="utf-8-sig") as f:
            reader = csv.DictReader(f)
            header = [h.strip() for h in (reader.fieldnames or [])]
            missing = [c for c in COLUMNS if c not in header]
            if missing:
                raise InputError(
                    f"--pushes: {path} lacks column(s) {', '.join(missing)}; "
                    f"expected {', '.join(COLUMNS)}, got {', '.join(header) or 'no header'}"
                )
            rows = [{k.strip(): v for k, v in row.items() if k} for row in reader]
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise InputError(f"--pushes: cannot read {path}: {e}") from e
    if not rows:
        raise InputError(f"--pushes: {path} holds no push")
    values = np.empty((len(rows), len(COLUMNS)))
    for i, row in enumerate(rows):
        for j, column in enumerate(COLUMNS):
            text = (row.get(column) or "").strip()
            try:
                values[i, j] = float(text)
            except ValueError:
                raise InputError(
                    f"--pushes: {path} line {i + 2}, column {column}: {text!r} is not a number"
                ) from None
            if not math.isfinite(values[i, j]):
                raise InputError(
                    f"--pushes: {path} line {i + 2}, column {column}: {text!r} is not finite"
                )
    return values[:, :4], values[:, 4:]


def estimate(mask: comcore.Mask, actions, motions, method: str) -> comcore.Estimate:
    """Run one of :data:`METHODS` on the observed pushes."""
    if method == "alg1":
        return comcore.estimate_heatmap(mask, actions, motions)
    if method in ("alg2", "alg2-rotation"):
        selection = "rotation" if method == "alg2-rotation" else "equality"
        return comcore.estimate_progressive(mask, actions, motions, selection=selection)
    if method == "centroid":
        return comcore.Estimate(com=mask.centroid, com_m=mask.centroid_m, region=mask.data)
    raise ValueError(f"method must be one of {METHODS}, got {method!r}")


def write_overlay(path, mask: comcore.Mask, actions, est: comcore.Estimate, title: str) -> Path:
    """A PNG of the mask (grey), the region (orange), the pushes (arrows) and the estimate."""
    try:
        from matplotlib.figure import Figure
    except ImportError as e:
        raise NoPlotting("the overlay needs matplotlib: pip install comcore[plot]") from e
    h, w = mask.shape
    fig = Figure(figsize=(6.0, 6.0 * h / max(w, 1) + 0.6), dpi=110, layout="constrained")
    ax = fig.add_subplot()
    image = np.ones((h, w, 3))
    image[mask.data] = (0.6, 0.6, 0.6)
    image[est.region & mask.data] = (1.0, 0.65, 0.2)
    ax.imshow(image, interpolation="nearest")
    for k, (sx, sy, ex, ey) in enumerate(np.asarray(actions, float)):
        color = "tab:red" if k in est.used else "tab:blue"
        ax.annotate("", (ex, ey), (sx, sy), arrowprops={"arrowstyle": "->", "color": color})
    ax.plot(*est.com, "kx", ms=12, mew=2.5, label=f"estimate ({est.com[0]:.1f}, {est.com[1]:.1f})")
    ax.set_xlim(-0.5, w - 0.5)
    ax.set_ylim(h - 0.5, -0.5)
    ax.set_title(title + "\nred: pushes used, blue: other pushes, orange: CoM region", fontsize=9)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.06), fontsize=8)
    fig.savefig(path)
    return Path(path)


def run(args) -> int:
    """Run ``comcore estimate``; 0 on success, 2 on a bad file or option, 1 if estimation fails."""
    try:
        if not (math.isfinite(args.resolution) and args.resolution > 0):
            raise InputError(f"--resolution must be a positive number, got {args.resolution}")
        mask = read_mask(args.mask, args.resolution)
        actions, motions = read_pushes(args.pushes)
    except InputError as e:
        print(f"comcore estimate: {e}", file=sys.stderr)
        return 2
    try:
        est = estimate(mask, actions, motions, args.method)
    except (TypeError, ValueError) as e:
        print(f"comcore estimate: the pushes do not fit the mask: {e}", file=sys.stderr)
        return 1
    result = {
        "com_px": list(est.com),
        "com_m": list(est.com_m),
        "method": args.method,
        "status": est.status,
        "used": list(est.used),
        "n_pushes": len(actions),
        "resolution": mask.resolution,
        "overlay": None,
    }
    overlay = overlay_path(args)
    if overlay is not None:
        try:
            title = f"{args.method}: CoM ({est.com[0]:.1f}, {est.com[1]:.1f}) px"
            write_overlay(overlay, mask, actions, est, title)
            result["overlay"] = str(overlay)
        except NoPlotting as e:
            if args.overlay:  # asked for by name: an error
                print(f"comcore estimate: cannot write the overlay {overlay}: {e}", file=sys.stderr)
                return 2
            print(f"comcore estimate: no overlay written ({e}; --no-overlay skips it)",
                  file=sys.stderr)  # fmt: skip
            overlay = None
        except (InputError, OSError, ValueError) as e:
            print(f"comcore estimate: cannot write the overlay {overlay}: {e}", file=sys.stderr)
            return 2
    if args.json:
        print(json.dumps(result))
    else:
        x, y = est.com
        print(f"CoM: ({x:.2f}, {y:.2f}) px = ({est.com_m[0]:.4f}, {est.com_m[1]:.4f}) m")
        used = f"{len(est.used)} of {len(actions)} pushes used"
        print(f"method {args.method}, status {est.status}, {used}")
        if overlay is not None:
            print(f"overlay: {overlay}")
    return 0
