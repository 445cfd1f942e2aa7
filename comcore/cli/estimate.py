"""``comcore estimate``: the CoM of your own object from a mask image and a CSV of pushes.

The mask is an image of the object seen from above (a mask, or a photo of the object on a
plain table), read through :func:`comcore.mask_from_image`. The CSV has one row per push with
the columns ``sx, sy, ex, ey`` (the pusher's path in pixels, x = column, y = row down) and
``theta, tx, ty`` (the observed rotation in radians, counter-clockwise on screen, and the
displacement of the mask's area centroid in pixels): the conventions of
:mod:`comcore.conventions`. Every push must start from the pose of the mask. ``--resolution``
(metres per pixel) has no default: a camera's scale is the user's to measure. ``--example``
runs on the small recording shipped in ``comcore/data/examples/``.

Pushes that miss the object or start inside it are dropped with one warning naming their CSV
lines; ``--strict`` refuses them, and so is a recording where most would be dropped (with a
hint when swapping x and y makes them hit) or whose pushes fit the mask at another scale
(:func:`comcore.cli._mistakes.scale_mistake`). A recording far better explained with every
theta's sign flipped is reported ``inconsistent`` with that hint (:func:`sign_flip_nats`);
one far better explained in degrees is refused (``--theta-units``,
:func:`comcore.cli._mistakes.units_mistake`).

``--frames`` adds the frames a camera saw during the pushes (:mod:`comcore.cli._frames`), scored
by :func:`comcore.estimate_posterior` (``frames=``); it needs ``--mask``, ``--pushes``, the
``posterior`` method and a motion model. ``--bag`` takes a robot's ROS bag instead of the mask
and the CSV, through :func:`comcore.recordings.bag.recording_from_bag` (``comcore[ros]``): the
mask is drawn from ``--outline``, so ``--resolution`` is its pixel size (default 2.5 mm); the
pushes are numbered as the lines of the CSV the recording would make (the first is line 2); each
push's motion is taken over ``--travel`` metres after first contact (default 3 cm: at most the
cell's push length, since a push that travels less is skipped as ``short``); the CoM is also
given in the object's frame (the JSON's ``com_object_m``). The ROS messages' stamp is the bag's
time at the end of the last push kept (0 for a mask and a CSV, which carry no clock).

The default method, ``posterior``, scores the pushes with the motion model of
:class:`comcore.ActiveSession` (``--model limit-surface``, a round pusher of
``--pusher-radius`` metres); ``--model none`` is the Voting Theorem alone. The status is
``ok`` when the pushes are consistent and the region reached ``--target-radius`` (metres,
default 6 mm), ``wide`` when the region is wider (:class:`comcore.Status`). The exit code
says whether to use the answer (:data:`EPILOG`): 0 for an answer to use, :data:`EXIT_INCONSISTENT`
for ``inconsistent``. Every option, the frames' CSV and the bag: docs/how-to/recordings.md
and docs/how-to/bag.md.
"""

from __future__ import annotations

import dataclasses
import json
import sys
from importlib import resources
from pathlib import Path
from typing import NamedTuple

import numpy as np

import comcore
from comcore._validation import check_physical
from comcore.active._options import DEFAULT_MODEL, DEFAULT_PUSHER_RADIUS, DEFAULT_TARGET_RADIUS
from comcore.active._posterior import MAX_BOOTSTRAP, THETA_UNITS
from comcore.recordings._recording import DEFAULT_TRAVEL_M

from . import _options
from ._frames import FRAME_COLUMNS, dropped_frames, dropped_note, frame_error, read_frames
from ._inputs import (
    COLUMNS,
    RESOLUTION_RANGE,
    InputError,
    check_resolution,
    line_list,
    read_bag,
    read_mask,
    read_pushes,
    screen_pushes,
)
from ._mistakes import (
    SIGN_FLIP_NATS as SIGN_FLIP_NATS,  # re-exported (benchmarks/accuracy/estimate_methods.py)
)
from ._mistakes import (
    object_size_m,
    recording_mistakes,
    sign_mistake,
    units_mistake,
)
from ._mistakes import sign_flip_nats as sign_flip_nats  # re-exported, as above
from ._outputs import print_text, region_summary, status_meaning

HELP = "estimate the CoM of your object from a mask image and a CSV of observed pushes"
#: Exit code when the answer is not to be used: status ``inconsistent``.
EXIT_INCONSISTENT = 3
#: The end of ``comcore estimate --help``: the statuses and the exit codes.
EPILOG = f"""\
status (in the text and the JSON's "status", with "status_meaning"):
  ok            the pushes are consistent and the region (the posterior's 90 % credible
                region, Alg. 2's final region) is within --target-radius
  wide          consistent, but the region is wider than --target-radius: usable, less
                sure; more pushes across the region narrow it
  inconsistent  no CoM explains the pushes (or theta's sign looks flipped): do not use it
  no_evidence, no_actions, flat_heatmap, unchecked: see docs/how-to/recordings.md

exit codes:
  0  an answer to use: ok, wide, or a documented fallback (no_evidence, no_actions, ...)
  1  the pushes do not fit the mask (nothing estimated)
  2  a bad file or option (or the overlay could not be written)
  {EXIT_INCONSISTENT}  status inconsistent: the answer is printed, but do not use it
"""

#: The methods of ``--method``, the default first.
METHODS = ("posterior", "alg2", "alg2-rotation", "alg1", "centroid")
#: Probability of the posterior's credible region (printed and in the JSON).
CREDIBLE = 0.9
#: ``--systematic-error`` (metres): estimate_posterior's floor for a recording's many pushes,
#: chosen with the bagged region on the MIT push dataset's train plates (calibrated by
#: benchmarks/realdata/real_pushes.py; docs/explanation/calibration.md).
SYSTEMATIC_ERROR = comcore.active.RECORDED_SYSTEMATIC_ERROR
#: ``--bootstrap``: resamplings of the pushes whose posteriors the region is read from.
BOOTSTRAP = comcore.active.RECORDED_BOOTSTRAP
#: The example shipped with the package (``--example``): files in comcore/data/examples/.
EXAMPLE = {"mask": "object.png", "pushes": "pushes.csv", "truth": "truth.json"}
#: ``status_meaning`` of ``--method centroid``: a baseline whose ``ok`` checks nothing.
CENTROID_MEANING = "the area centroid, a baseline that uses no push: nothing is checked"
#: What ``--resolution`` is and how to measure it (its help and the error without it).
RESOLUTION_HELP = (
    "the size of one image pixel on the table, in METRES per pixel (e.g. 0.0025 for 2.5 mm); "
    "measure it: photograph a ruler or an object of known length lying on the table, and "
    "divide its length in metres by its length in pixels"
)
#: ``--frame-id``'s default: the mask frame (metres, x along the columns, y down the rows).
MASK_FRAME_ID = "comcore_mask"
#: ``--frame-id``'s default with ``--bag`` and no ``--object-child-frame``: the object's frame.
OBJECT_FRAME_ID = "object"
#: The motion models of ``--model`` (the posterior's), the default first.
MODELS = ("limit-surface", "none")


def methods() -> tuple[str, ...]:
    """The methods of ``--method``, the default (``posterior``) first."""
    return METHODS


def example_files() -> dict[str, Path]:
    """Paths of the shipped example: ``{"mask": ..., "pushes": ..., "truth": ...}``."""
    folder = resources.files("comcore") / "data" / "examples"
    return {key: Path(str(folder / name)) for key, name in EXAMPLE.items()}


def add_arguments(parser) -> None:
    """Options of ``comcore estimate``."""
    add = parser.add_argument
    _add_input_arguments(parser)
    _add_bag_arguments(parser)
    _add_image_arguments(parser)
    _add_unit_arguments(parser)
    add(
        "--method",
        choices=METHODS,
        default=METHODS[0],
        help="estimator (default posterior). posterior: the active estimator's posterior over "
        "the recorded pushes, with a 90 %% credible region; it weighs every push, so a push "
        "observed turning the wrong way does not cut the true CoM away as it can in alg2 "
        "(docs/how-to/benchmark.md measures it). alg2: the paper's Alg. 2; "
        "alg2-rotation: Alg. 2 taking "
        "pushes by ascending |theta|; alg1: the heat map; centroid: the area centroid",
    )
    add(
        "--strict",
        action="store_true",
        help="refuse pushes that miss the object or start inside it (default: drop them "
        "with a warning)",
    )
    _add_model_arguments(parser)
    _add_status_arguments(parser)
    _add_output_arguments(parser)


def _add_image_arguments(parser) -> None:
    """``--object``, ``--threshold``, ``--background`` and ``--roi``: reading the mask image."""
    add = parser.add_argument
    add(
        "--object",
        choices=("auto", "bright", "dark"),
        default="auto",
        help="the object is brighter or darker than its table in the image (default auto: "
        "the side that does not touch the image border)",
    )
    add(
        "--threshold",
        type=_options.threshold,
        default="auto",
        help="how the object is told from its table: auto (default: the table's light fitted "
        "and taken off, for uneven lighting), otsu (one grey level for the whole image), or a "
        "grey level (with --background: the least difference from it)",
    )
    add(
        "--background",
        metavar="IMAGE",
        help="an image of the empty table from the same camera: the object is what differs "
        "from it (a textured table, fixed clutter and shadows then do not matter)",
    )
    add(
        "--roi",
        type=_options.box,
        metavar="X0,Y0,X1,Y1",
        help="look only inside this box of the image, in pixels (columns X0..X1-1, rows "
        "Y0..Y1-1); pixel coordinates do not change",
    )


def _add_output_arguments(parser) -> None:
    """``--json``, ``--frame-id``, ``--overlay`` and ``--no-overlay``."""
    add = parser.add_argument
    add("--json", action="store_true", help="print one JSON object instead of text")
    add(
        "--frame-id",
        help='the tf frame named in the JSON\'s ROS messages ("ros": InertiaStamped and '
        "PoseWithCovarianceStamped fields, comcore.ros.ros_messages). With --mask: the CoM in "
        f"the mask frame's metres (x along the columns, y down the rows), default {MASK_FRAME_ID}. "
        "With --bag: in the object's frame (the outline's, the object topic's), default "
        f"--object-child-frame or {OBJECT_FRAME_ID}",
    )
    picture = parser.add_mutually_exclusive_group()
    picture.add_argument(
        "--overlay",
        metavar="PNG",
        help="where to write the picture of the mask, pushes, region and estimate "
        "(default: MASK_STEM-overlay.png in the current folder; example-overlay.png with "
        "--example)",
    )
    picture.add_argument("--no-overlay", action="store_true", help="write no picture")


#: The options of a bag input, each with its help; all but the child frames are required.
BAG_OPTIONS = {
    "--object-topic": "the topic of the object's pose (PoseStamped, TransformStamped, /tf, "
    "Odometry), in one frame with the pusher's, z up, metres",
    "--pusher-topic": "the topic of the pusher tip's centre (its orientation is not used)",
    "--object-child-frame": "the object's child frame, for a /tf topic that carries several",
    "--pusher-child-frame": "the tip's child frame, for a /tf topic that carries several",
    "--outline": "the object's outline in its own frame (the object topic's): a CSV of x,y "
    "vertices in metres, or a mesh (.stl, .obj, ...: its footprint, needs comcore[sim])",
}


def _add_input_arguments(parser) -> None:
    """``--mask``, ``--pushes``, ``--frames`` and ``--example``."""
    files = parser.add_argument_group("input (--mask and --pushes, --bag, or --example)")
    files.add_argument(
        "--mask", help="image of the object seen from above: a mask or a photo on a plain table"
    )
    files.add_argument("--pushes", help="CSV with the columns " + ", ".join(COLUMNS))
    files.add_argument(
        "--frames",
        metavar="CSV",
        help="the frames a camera saw during the pushes: a CSV with the columns "
        + ", ".join(FRAME_COLUMNS)
        + "; push: 1 for the first data row of --pushes (its line 2 after the header), 2 for "
        "the next row, ... (the rows of one "
        "push in the order taken; a push may have none); px, py: the pusher's leading point "
        "then (pixels); theta, tx, ty: the object's motion since the push began, as in "
        "--pushes (theta in --theta-units). Needs --mask and --pushes, --method posterior and "
        "--model limit-surface",
    )
    files.add_argument(
        "--example",
        action="store_true",
        help="use the example shipped with comcore (an object image and 40 simulated pushes)",
    )


def _add_bag_arguments(parser) -> None:
    """``--bag`` and its topics, child frames and outline."""
    bag = parser.add_argument_group(
        "a ROS bag instead (--bag, --object-topic, --pusher-topic, --outline; needs comcore[ros])"
    )
    bag.add_argument(
        "--bag",
        metavar="BAG",
        help="a ROS 1 .bag or a rosbag2 folder (sqlite3 or MCAP) holding the object's and the "
        "pusher's poses: the mask is drawn from --outline and the pushes are cut from the poses",
    )
    for option, text in BAG_OPTIONS.items():
        bag.add_argument(option, metavar="FILE" if option == "--outline" else "NAME", help=text)
    bag.add_argument(
        "--travel",
        type=float,
        metavar="METRES",
        help="the pusher's travel after first contact over which each push's motion is taken "
        f"(default {DEFAULT_TRAVEL_M:g} m): your cell's push length or less; a push that "
        "travels less is skipped as short",
    )


def _add_status_arguments(parser) -> None:
    """``--target-radius``: the region's radius for status ``ok`` (:data:`EPILOG`)."""
    parser.add_argument(
        "--target-radius",
        type=float,
        default=DEFAULT_TARGET_RADIUS,
        help="radius in METRES the region must reach for status ok (default "
        f"{DEFAULT_TARGET_RADIUS:g} m, as an active session's); consistent but wider is wide",
    )


def _add_unit_arguments(parser) -> None:
    """``--resolution`` and ``--theta-units``: the units of the mask and the CSV."""
    lo, hi = RESOLUTION_RANGE
    parser.add_argument(
        "--resolution",
        type=float,
        metavar="METRES_PER_PIXEL",
        help=f"required (unless --example or --bag): {RESOLUTION_HELP}; values outside "
        f"[{lo:g}, {hi:g}] are refused. With --bag: the pixel size of the mask drawn from "
        f"--outline (default {comcore.conventions.DEFAULT_RESOLUTION:g})",
    )
    parser.add_argument(
        "--theta-units",
        choices=THETA_UNITS,
        default=THETA_UNITS[0],
        help="unit of the theta column (default auto: radians, and a recording that every theta "
        "times pi/180 explains far better is refused as being in degrees, whatever the method; "
        "rad: radians, such a recording is estimated with a warning and status inconsistent; "
        "deg: degrees, converted, not checked)",
    )


def _add_model_arguments(parser) -> None:
    """``--model`` and ``--pusher-radius``: the posterior's motion model."""
    parser.add_argument(
        "--model",
        choices=MODELS,
        default=MODELS[0],
        help="the posterior's motion model (default limit-surface: comcore.LimitSurfaceModel, "
        "the active session's; it tells a recording with theta's sign flipped from a right "
        "one, and takes a few seconds for 40 pushes). none: the Voting Theorem alone, about "
        "20 times faster (docs/how-to/benchmark.md)",
    )
    parser.add_argument(
        "--pusher-radius",
        type=float,
        default=DEFAULT_PUSHER_RADIUS,
        help="radius of the round pusher in METRES, for --model limit-surface (default "
        f"{DEFAULT_PUSHER_RADIUS:g} m); over "
        f"{comcore.conventions.PLAUSIBLE['pusher_radius'].high:g} m is refused",
    )
    parser.add_argument(
        "--systematic-error",
        type=float,
        default=SYSTEMATIC_ERROR,
        help="std (METRES) of an error on the CoM that more pushes do not average away: the "
        "credible region is the posterior blurred by it (comcore.Likelihood("
        f"systematic_error=...); default {SYSTEMATIC_ERROR:g} m, chosen on real "
        "pushes, docs/explanation/calibration.md; 0: none)",
    )
    parser.add_argument(
        "--bootstrap",
        type=int,
        default=BOOTSTRAP,
        help="resamplings of the pushes whose posteriors, averaged, give the credible region "
        f"(the bagged posterior: wider where the pushes disagree; default {BOOTSTRAP}; 0: the "
        "posterior's own region)",
    )


def overlay_path(args) -> Path | None:
    """Where the overlay goes: ``--overlay``, else ``<mask stem>-overlay.png`` here.

    ``None`` with ``--no-overlay``; ``example-overlay.png`` with ``--example``.
    Never beside the mask by default: the mask's folder may be the user's data,
    or the installed package's (``--example``), which a run should not write into.

    Examples
    --------
    >>> import argparse
    >>> str(overlay_path(argparse.Namespace(mask="data/cup.png", overlay=None, no_overlay=False)))
    'cup-overlay.png'
    >>> overlay_path(argparse.Namespace(mask="cup.png", overlay=None, no_overlay=True)) is None
    True
    """
    if getattr(args, "no_overlay", False):
        return None
    if getattr(args, "overlay", None):
        return Path(args.overlay)
    if getattr(args, "example", False):
        return Path("example-overlay.png")
    return Path(f"{Path(getattr(args, 'bag', None) or args.mask).stem}-overlay.png")


def estimate(
    mask: comcore.Mask,
    actions,
    motions,
    method: str,
    *,
    model: str = MODELS[0],
    pusher_radius: float = DEFAULT_PUSHER_RADIUS,
    systematic_error: float = SYSTEMATIC_ERROR,
    bootstrap: int = BOOTSTRAP,
    target_radius: float = DEFAULT_TARGET_RADIUS,
    frames=None,
) -> comcore.Estimate:
    """Run one of :func:`methods` on the observed pushes.

    ``model`` (one of :data:`MODELS`), ``systematic_error`` (metres) and
    ``bootstrap`` are the posterior's; the other methods take no model.
    ``pusher_radius`` (metres, the recording's) is the posterior's and Alg. 2's;
    ``target_radius`` (metres) too: the region's radius for ``"ok"``. ``frames``: per push, the
    :class:`comcore.PushFrame` s taken during it (or None), for the posterior
    with a motion model only (:func:`comcore.estimate_posterior`'s ``frames``).
    """
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}, got {model!r}")
    if frames is not None and (method != "posterior" or model == "none"):
        raise ValueError("frames are scored by the posterior's motion model alone")
    if method == "posterior":
        chosen = None if model == "none" else DEFAULT_MODEL
        return comcore.estimate_posterior(
            mask,
            actions,
            motions,
            credible=CREDIBLE,
            model=chosen,
            pusher_radius=pusher_radius,
            likelihood=comcore.Likelihood(systematic_error=systematic_error),
            bootstrap=bootstrap,
            target_radius=target_radius,
            theta_units="rad",  # the command checks theta's unit itself
            frames=frames,
        )
    if method == "alg1":
        return comcore.estimate_heatmap(mask, actions, motions)
    if method in ("alg2", "alg2-rotation"):
        selection = "rotation" if method == "alg2-rotation" else "equality"
        return comcore.estimate_progressive(
            mask, actions, motions, selection=selection, target_radius=target_radius,
            pusher_radius=pusher_radius,
        )
    if method == "centroid":
        return comcore.Estimate(  # a baseline that uses no push: nothing is checked
            com=mask.centroid,
            com_m=mask.centroid_m,
            region=mask.data,
            status=comcore.Status.UNCHECKED,
        )
    raise ValueError(f"method must be one of {methods()}, got {method!r}")


def overlay_numbers(est: comcore.Estimate, lines) -> list[int]:
    """The CSV line of each push the overlay numbers, in its order: the text's numbering.

    :func:`comcore.plot.plot_estimate` numbers the pushes an estimate rests on:
    the posterior's records (each with its index among the pushes given), the
    other estimators' ``used``.

    Examples
    --------
    >>> import numpy as np
    >>> est = comcore.Estimate((1.0, 1.0), (0.0, 0.0), np.ones((3, 3), bool), used=(2, 0))
    >>> overlay_numbers(est, [2, 4, 5])
    [5, 2]
    """
    lines = [int(v) for v in lines]
    if est.pushes:
        return [lines[p.index] for p in est.pushes if p.outcome != "failed"]
    return [lines[i] for i in est.used]


def _write_overlay(path: Path, mask, pushes, est, method: str) -> bool:
    """Draw with :func:`comcore.plot.plot_estimate`; ``True`` if a file was replaced."""
    try:
        import comcore.plot
    except ImportError as e:
        raise ModuleNotFoundError(str(e), name="matplotlib") from e
    replaced = path.exists()
    x, y = est.com
    title = (
        f"comcore estimate --method {method}: CoM ({x:.1f}, {y:.1f}) px, status "
        f"{est.status}\npushes numbered by their CSV line"
    )
    ax = comcore.plot.plot_estimate(
        mask,
        est,
        actions=pushes.actions,
        title=title,
        credible=CREDIBLE,
        numbers=overlay_numbers(est, pushes.lines),
    )
    ax.figure.savefig(path)
    return replaced


def _frames_options(args) -> None:
    """With ``--frames``: the pushes CSV and the posterior with its motion model."""
    if args.frames is None:
        return
    if args.bag or args.example:
        other = "--bag" if args.bag else "--example"
        why = (
            "its pushes are cut from its poses, not rows of a pushes CSV"
            if args.bag
            else "the example has no frames"
        )
        raise InputError(f"--frames goes with --mask and --pushes, not {other} ({why})")
    if not args.pushes:
        raise InputError("--frames needs --pushes: its push column numbers the pushes CSV's rows")
    if args.method != "posterior":
        raise InputError(
            f"--frames needs --method posterior (the default): {args.method} scores no path"
        )
    if args.model == "none":
        raise InputError(
            "--frames needs --model limit-surface (the default): the Voting Theorem alone reads "
            "each push's sense, not the path its frames show"
        )


def _bag_options(args) -> None:
    """With ``--bag``: its options given and nothing of the other inputs; without it, none."""
    given = [o for o in BAG_OPTIONS if getattr(args, o[2:].replace("-", "_")) is not None]
    if not args.bag:
        if given:
            raise InputError(f"{', '.join(given)} need --bag (they say what to read in the bag)")
        if getattr(args, "travel", None) is not None:
            raise InputError(
                "--travel needs --bag: a pushes CSV gives each push's path and motion itself"
            )
        return
    image = {"--mask": args.mask, "--pushes": args.pushes, "--example": args.example}
    image.update({"--background": args.background, "--roi": args.roi})
    others = [option for option, value in image.items() if value]
    if others:
        raise InputError(
            f"--bag replaces --mask and --pushes (and the image's options); give one or the "
            f"other, not --bag with {', '.join(others)}"
        )
    if args.theta_units == "deg":
        raise InputError("--theta-units deg: the rotations read from --bag are radians")
    missing = [o for o in ("--object-topic", "--pusher-topic", "--outline") if o not in given]
    if missing:
        raise InputError(f"{' and '.join(missing)} required with --bag")


def _read(args, resolution: float, pusher_radius: float):
    """The mask, the pushes and the bag's Recording (None for the mask image and the CSV)."""
    if args.bag:
        mask, recorded, rec = read_bag(
            args.bag,
            args.object_topic,
            args.pusher_topic,
            args.outline,
            pusher_radius,
            resolution,
            object_child_frame=args.object_child_frame,
            pusher_child_frame=args.pusher_child_frame,
            travel=_travel(args),
        )
        print(f"comcore estimate: --bag: {rec.report()}".replace("\n", "\n  "), file=sys.stderr)
        return mask, recorded, rec
    mask_path, pushes_path = _inputs(args)
    mask = read_mask(
        mask_path,
        resolution,
        args.object,
        threshold=args.threshold,
        background=args.background,
        roi=args.roi,
    )
    return mask, read_pushes(pushes_path), None


def _inputs(args):
    if args.example:
        if args.mask or args.pushes:
            raise InputError("--example replaces --mask and --pushes; give one or the other")
        files = example_files()
        return files["mask"], files["pushes"]
    if args.resolution is None:
        raise InputError(f"--resolution required (or --example, or --bag): {RESOLUTION_HELP}")
    if not (args.mask and args.pushes):
        missing = [o for o, v in (("--mask", args.mask), ("--pushes", args.pushes)) if not v]
        raise InputError(f"{' and '.join(missing)} required (or --example, or --bag)")
    return Path(args.mask), Path(args.pushes)


def _result(args, mask, recorded, pushes, dropped, est, *, mistake=None, frame=None) -> dict:
    """The JSON object of a run (without the overlay); ``frame``: a bag's Recording.

    The ROS messages are stamped with the bag's time at the end of its last push
    kept (:attr:`comcore.Recording.stamp`), 0 without a bag.
    """
    stamp = None if frame is None else frame.stamp
    status = comcore.Status.INCONSISTENT if mistake else est.status
    return {
        "com_px": list(est.com),
        "com_m": list(est.com_m),
        "method": args.method,
        "model": args.model if args.method == "posterior" else None,
        "status": status,
        "status_meaning": CENTROID_MEANING
        if args.method == "centroid"
        else status_meaning(status, args.target_radius),
        "estimator_status": est.status,
        "target_radius_m": args.target_radius,
        "mistake": mistake,
        "used_lines": [int(pushes.lines[i]) for i in est.used if 0 <= i < len(pushes.lines)],
        "dropped_lines": {str(k): v for k, v in dropped.items()},
        "n_pushes": len(recorded.lines),
        "n_frames": 0,  # --frames: the frames read
        "dropped_frames": [],  # --frames: per push, the frames not scored and why
        "resolution": mask.resolution,
        "object_size_m": object_size_m(mask),
        "region": region_summary(est, mask.resolution, CREDIBLE),
        "covariance_px2": None if est.covariance is None else np.asarray(est.covariance).tolist(),
        "overlay": None,
        "overlay_replaced": False,
        "ros": comcore.ros.ros_messages(
            dataclasses.replace(est, status=status),
            frame_id=args.frame_id,
            resolution=None if frame is not None else mask.resolution,
            frame=frame,
            stamp=0.0 if stamp is None else stamp,
        ),
    }


def _overlay(args, mask, pushes, est, result: dict) -> int:
    """Write the overlay if asked for (by default it is); fills ``result``; the exit status."""
    overlay = overlay_path(args)
    if overlay is None:
        return 0
    try:
        result["overlay_replaced"] = _write_overlay(overlay, mask, pushes, est, args.method)
    except ModuleNotFoundError as e:
        why = "the overlay needs matplotlib: pip install comcore[plot]"
        if args.overlay:  # asked for by name: an error
            print(f"comcore estimate: cannot write the overlay {overlay}: {why}", file=sys.stderr)
            return 2
        print(
            f"comcore estimate: no overlay written ({why}; --no-overlay skips it) ({e})",
            file=sys.stderr,
        )
        return 0
    except (OSError, ValueError) as e:
        print(f"comcore estimate: cannot write the overlay {overlay}: {e}", file=sys.stderr)
        return 2
    result["overlay"] = str(overlay)
    if result["overlay_replaced"] and args.json:
        print(f"comcore estimate: overwrote the existing file {overlay}", file=sys.stderr)
    return 0


def _target(value) -> float:
    """``--target-radius`` (metres), checked."""
    try:
        return check_physical(value, "--target-radius", "target_radius")
    except ValueError as e:
        raise InputError(str(e)) from None


def _travel(args) -> float:
    """``--travel`` (metres), checked; its default without it."""
    travel = getattr(args, "travel", None)
    if travel is None:
        return DEFAULT_TRAVEL_M
    try:
        return check_physical(travel, "--travel", "push_length")
    except ValueError as e:
        raise InputError(str(e)) from None


def _metres(value, flag: str, kind: str) -> float:
    """A length option in metres (`--pusher-radius`, `--systematic-error`), checked."""
    try:
        return check_physical(value, flag, kind, allow_zero=True)
    except ValueError as e:
        raise InputError(str(e)) from None


def _resolution(args) -> float:
    """``--resolution``, checked; without it the example's own, or the mask's default (--bag)."""
    if args.resolution is None and args.bag:
        return comcore.conventions.DEFAULT_RESOLUTION
    if args.resolution is None:  # _inputs allows it only with --example
        return float(json.loads(example_files()["truth"].read_text())["resolution"])
    return check_resolution(args.resolution)


def _numbers(args) -> tuple[float, float, float]:
    """The resolution, pusher radius and systematic error in metres; the other options checked.

    Sets ``args.target_radius`` (metres) and ``args.frame_id`` (its default) in place.
    """
    resolution = _resolution(args)
    pusher_radius = _metres(args.pusher_radius, "--pusher-radius", "pusher_radius")
    systematic_error = _metres(args.systematic_error, "--systematic-error", "length_noise")
    args.target_radius = _target(args.target_radius)
    if args.frame_id is None:
        args.frame_id = (args.object_child_frame or OBJECT_FRAME_ID) if args.bag else MASK_FRAME_ID
    if not args.frame_id.strip():
        raise InputError("--frame-id must name a tf frame, got an empty string")
    if not 0 <= args.bootstrap <= MAX_BOOTSTRAP:
        raise InputError(
            f"--bootstrap must be 0 to {MAX_BOOTSTRAP} resamplings, got {args.bootstrap}"
        )
    return resolution, pusher_radius, systematic_error


class _Inputs(NamedTuple):
    """What a run read and checked, before estimating."""

    mask: comcore.Mask
    """The object's mask."""
    recorded: object
    """Every push read (``Pushes``), dropped ones included."""
    pushes: object
    """The pushes kept (``Pushes``)."""
    dropped: dict
    """``{CSV line: why}`` of the pushes dropped."""
    frames: object
    """The frames read (``--frames``), or None."""
    from_bag: comcore.Recording | None
    """The bag's Recording (``--bag``), or None."""
    pusher_radius: float
    """``--pusher-radius``, metres."""
    systematic_error: float
    """``--systematic-error``, metres."""

    @property
    def kept(self) -> list[int]:
        """The rows of ``recorded`` that were kept."""
        return [k for k, line in enumerate(self.recorded.lines) if int(line) not in self.dropped]


def _prepare(args) -> _Inputs:
    """Check the options, read the inputs and screen the pushes (InputError on a mistake)."""
    _frames_options(args)
    _bag_options(args)
    if not args.bag:
        _inputs(args)  # the mask and CSV options, checked before the numbers
    resolution, pusher_radius, systematic_error = _numbers(args)
    mask, recorded, from_bag = _read(args, resolution, pusher_radius)
    frames = None if args.frames is None else read_frames(args.frames, recorded.lines)
    if args.theta_units == "deg":
        recorded = recorded.theta_from_degrees()
        frames = None if frames is None else frames.theta_from_degrees()
    contact_radius = pusher_radius if args.method == "posterior" else 0.0  # Alg. 1, 2: points
    pushes, dropped = screen_pushes(
        mask, recorded, strict=args.strict, pusher_radius=contact_radius
    )
    recording_mistakes(mask, recorded, dropped, degrees=args.theta_units == "deg")
    return _Inputs(
        mask, recorded, pushes, dropped, frames, from_bag, pusher_radius, systematic_error
    )


def _warn_dropped(read: _Inputs) -> None:
    """One warning naming the pushes dropped (and their frames), if any."""
    if not read.dropped:
        return
    lines = read.recorded.lines
    rows = [k for k, line in enumerate(lines) if int(line) in read.dropped]
    note = "" if read.frames is None else dropped_note(read.frames, rows)
    print(
        f"comcore estimate: warning: dropped {len(read.dropped)} of {len(lines)} pushes "
        f"that miss the object or start inside it: CSV line(s) {line_list(list(read.dropped))} "
        "(--strict refuses them)" + note,
        file=sys.stderr,
    )


def _estimate(args, read: _Inputs) -> tuple[comcore.Estimate, str | None]:
    """The estimate and the mistake the recording shows (None if none)."""
    mask, pushes, frames = read.mask, read.pushes, read.frames
    units = units_mistake(mask, pushes, args.theta_units, read.pusher_radius)
    est = estimate(
        mask,
        pushes.actions,
        pushes.motions,
        args.method,
        model=args.model,
        systematic_error=read.systematic_error,
        bootstrap=args.bootstrap,
        pusher_radius=read.pusher_radius,
        target_radius=args.target_radius,
        frames=None if frames is None else frames.of(read.kept),
    )
    mistake = "; ".join(m for m in (units, sign_mistake(mask, pushes)) if m) or None
    return est, mistake


def run(args) -> int:
    """Run ``comcore estimate``; its exit code (:data:`EPILOG`).

    0 for an answer to use, 1 if estimation fails, 2 on a bad file or option,
    :data:`EXIT_INCONSISTENT` when the status is ``inconsistent``.
    """
    try:
        read = _prepare(args)
    except InputError as e:
        print(f"comcore estimate: {e}", file=sys.stderr)
        return 2
    _warn_dropped(read)
    try:
        est, mistake = _estimate(args, read)
    except InputError as e:
        print(f"comcore estimate: {e}", file=sys.stderr)
        return 2
    except (TypeError, ValueError) as e:
        frames, lines = read.frames, read.recorded.lines
        error = None if frames is None else frame_error(str(e), frames, read.kept, lines)
        if error is not None:  # a frame that does not fit its push: the frames CSV's mistake
            print(f"comcore estimate: {error}", file=sys.stderr)
            return 2
        print(f"comcore estimate: the pushes do not fit the mask: {e}", file=sys.stderr)
        return 1
    if mistake:
        print(f"comcore estimate: warning: status inconsistent: {mistake}", file=sys.stderr)
    elif not est.ok and est.status != comcore.Status.WIDE:  # wide: usable, explained in the output
        meaning = (
            CENTROID_MEANING
            if args.method == "centroid"
            else status_meaning(est.status, args.target_radius)
        )
        print(f"comcore estimate: warning: status {est.status}: {meaning}", file=sys.stderr)
    return _report(args, read, est, mistake)


def _report(args, read: _Inputs, est, mistake) -> int:
    """Print the result (text or JSON) and write the overlay; the exit code."""
    mask, recorded, frames, from_bag = read.mask, read.recorded, read.frames, read.from_bag
    result = _result(
        args, mask, recorded, read.pushes, read.dropped, est, mistake=mistake, frame=from_bag
    )
    if frames is not None:
        result["n_frames"] = frames.n_frames
        result["dropped_frames"] = dropped_frames(
            est, frames, read.kept, recorded.lines, read.dropped
        )
    if from_bag is not None:  # the CoM in the outline's frame, the frame of the object topic
        result["com_object_m"] = from_bag.object_from_pixels(np.array(est.com))[0].tolist()
    shown = dataclasses.replace(est, status=comcore.Status.INCONSISTENT) if mistake else est
    code = _overlay(args, mask, read.pushes, shown, result)
    if code:
        return code
    if args.json:
        print(json.dumps(result))
    else:
        print_text(result, est)
    return EXIT_INCONSISTENT if result["status"] == comcore.Status.INCONSISTENT else 0
