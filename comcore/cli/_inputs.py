"""The files of ``comcore estimate``: the mask image and the CSV of pushes, or a ROS bag.

Every problem is an :class:`InputError` naming the option and, for the CSV, the
file's line numbers (the header is line 1), never a 0-based index.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import comcore
from comcore.geometry._disc_contacts import pusher_contacts
from comcore.recordings._recording import DEFAULT_TRAVEL_M

__all__ = [
    "COLUMNS",
    "RESOLUTION_RANGE",
    "InputError",
    "Pushes",
    "check_resolution",
    "line_list",
    "read_bag",
    "read_mask",
    "read_pushes",
    "screen_pushes",
]

#: Columns of the pushes CSV: the pusher's path (pixels) and the observed motion.
COLUMNS = ("sx", "sy", "ex", "ey", "theta", "tx", "ty")
#: Plausible camera resolutions (metres per pixel): 10 micrometres to 5 cm a pixel, as
#: everywhere in comcore (``comcore.conventions.PLAUSIBLE["resolution"]``).
RESOLUTION_RANGE = (
    comcore.conventions.PLAUSIBLE["resolution"].low,
    comcore.conventions.PLAUSIBLE["resolution"].high,
)


class InputError(ValueError):
    """A problem with the user's files or options, reported as one line on stderr."""


@dataclass(frozen=True)
class Pushes:
    """The pushes of a CSV: actions (n, 4), motions (n, 3) and each row's line number."""

    actions: np.ndarray
    motions: np.ndarray
    lines: np.ndarray

    def subset(self, keep: np.ndarray) -> Pushes:
        """The pushes where ``keep`` (bool, shape (n,)) is true."""
        return Pushes(self.actions[keep], self.motions[keep], self.lines[keep])

    def theta_from_degrees(self) -> Pushes:
        """The pushes with theta, given in degrees, in radians."""
        return Pushes(self.actions, self.motions * [math.pi / 180, 1.0, 1.0], self.lines)


def check_resolution(value: float) -> float:
    """``value`` (metres per pixel) if it lies in :data:`RESOLUTION_RANGE`, else InputError.

    The message guesses the unit it was typed in (:func:`comcore.checks.check_plausible`).

    Examples
    --------
    >>> check_resolution(0.0025)
    0.0025
    >>> try:
    ...     check_resolution(2.5)  # millimetres typed for metres
    ... except InputError as e:
    ...     print(e)
    --resolution 2.5 m per pixel is implausible (expected 1e-05 to 0.05 m per pixel): did you mean millimetres, 0.0025?
    """  # noqa: E501
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"--resolution must be a positive number of metres per pixel, got {value}")
    try:
        return comcore.checks.check_plausible(value, "--resolution", "resolution")
    except ValueError as e:
        raise InputError(str(e)) from None


def _read_image(path: Path, option: str = "--mask") -> np.ndarray:
    """The image file as an array: grey (H, W) or RGB(A) (H, W, 3|4), in its own units."""
    try:
        import cv2
    except ImportError:
        cv2 = None
    if cv2 is not None:
        image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
        if image is None:
            raise InputError(f"{option}: cannot read {path} as an image")
        if image.ndim == 3:  # OpenCV's BGR(A) to RGB(A)
            image = image[..., [2, 1, 0, *range(3, image.shape[2])]]
        return image
    try:
        from matplotlib import image as mpimg
    except ImportError as e:
        raise InputError(f"{option}: reading images needs pip install comcore[sim]") from e
    try:
        return np.asarray(mpimg.imread(path))
    except Exception as e:  # matplotlib/Pillow raise several types on a bad file
        raise InputError(f"{option}: cannot read {path} as an image") from e


#: mask_from_image's keywords as its messages name them, and the options of the command.
_OPTION_NAMES = {
    "threshold='auto'": "--threshold auto",
    "threshold=": "--threshold",
    "background=": "--background",
    "roi=": "--roi",
}


def read_mask(
    path, resolution: float, side: str = "auto", *, threshold=None, background=None, roi=None
) -> comcore.Mask:
    """The object mask of an image file, through :func:`comcore.mask_from_image`.

    ``side``: whether the object is ``"bright"`` or ``"dark"`` on its table, or
    ``"auto"``; ``threshold``, ``background`` (the path of an image of the
    empty table) and ``roi`` are passed on. What is wrong with an image
    (constant, no object, several objects, touching the border, ...) is said
    about the image, as :class:`comcore.ImageError` words it, with the
    command's option names.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"--mask: no such file: {path}")
    image = _read_image(path)
    reference = None
    if background is not None:
        background = Path(background)
        if not background.is_file():
            raise InputError(f"--background: no such file: {background}")
        reference = _read_image(background, "--background")
    try:
        return comcore.mask_from_image(
            image,
            object=side,
            threshold=threshold,
            background=reference,
            roi=roi,
            resolution=resolution,
        )
    except (TypeError, ValueError) as e:  # comcore.ImageError is a ValueError
        message = str(e)
        for keyword, option in _OPTION_NAMES.items():
            message = message.replace(keyword, option)
        raise InputError(f"--mask: {path}: {message}") from e


def read_pushes(path) -> Pushes:
    """The pushes of a CSV with the columns :data:`COLUMNS`, with their line numbers."""
    path = Path(path)
    rows, lines = [], []
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
            for row in reader:
                rows.append({k.strip(): v for k, v in row.items() if k})
                lines.append(reader.line_num)
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise InputError(f"--pushes: cannot read {path}: {e}") from e
    if not rows:
        raise InputError(f"--pushes: {path} holds no push")
    values = np.empty((len(rows), len(COLUMNS)))
    for i, (row, line) in enumerate(zip(rows, lines)):
        for j, column in enumerate(COLUMNS):
            text = (row.get(column) or "").strip()
            try:
                values[i, j] = float(text)
            except ValueError:
                raise InputError(
                    f"--pushes: {path} line {line}, column {column}: {text!r} is not a number"
                ) from None
            if not math.isfinite(values[i, j]):
                raise InputError(
                    f"--pushes: {path} line {line}, column {column}: {text!r} is not finite"
                )
        if values[i, 0] == values[i, 2] and values[i, 1] == values[i, 3]:
            raise InputError(f"--pushes: {path} line {line}: the push has zero length")
    return Pushes(values[:, :4], values[:, 4:], np.asarray(lines, int))


def read_bag(
    path,
    object_topic: str,
    pusher_topic: str,
    outline,
    pusher_radius: float,
    resolution: float,
    *,
    object_child_frame: str | None = None,
    pusher_child_frame: str | None = None,
    travel: float = DEFAULT_TRAVEL_M,
) -> tuple[comcore.Mask, Pushes, comcore.Recording]:
    """The mask and pushes of a bag (:func:`comcore.recordings.bag.recording_from_bag`).

    ``outline`` is the path of the outline's file (``--outline``); ``travel``
    (metres) the window of pusher travel each push's motion is taken over. The pushes
    are numbered as the rows of the pushes CSV the recording would make (the
    first is line 2), so that the messages and the JSON read alike for both
    inputs. What is wrong (the bag, a topic, the outline, rosbags missing) is
    an InputError naming the option.
    """
    try:
        poly = comcore.recordings.read_outline(outline)
    except (ValueError, ImportError) as e:
        raise InputError(f"--outline: {e}") from e
    try:
        import comcore.recordings.bag as bag

        rec = bag.recording_from_bag(
            path,
            object_topic,
            pusher_topic,
            poly,
            pusher_radius,
            resolution=resolution,
            travel=travel,
            object_child_frame=object_child_frame,
            pusher_child_frame=pusher_child_frame,
        )
    except (ValueError, ImportError) as e:
        raise InputError(f"--bag: {e}") from e
    if not rec.pushes:
        raise InputError(f"--bag: no push could be used: {rec.report()}")
    lines = np.arange(2, len(rec.pushes) + 2)
    return rec.mask, Pushes(rec.actions, rec.motions, lines), rec


def line_list(lines) -> str:
    """Line numbers for a message: the first ten, then how many more.

    Examples
    --------
    >>> line_list([4, 6, 7])
    '4, 6, 7'
    >>> line_list(range(2, 14))
    '2, 3, 4, 5, 6, 7, 8, 9, 10, 11 and 2 more'
    """
    lines = list(lines)
    shown = ", ".join(str(int(v)) for v in lines[:10])
    return shown + (f" and {len(lines) - 10} more" if len(lines) > 10 else "")


def screen_pushes(
    mask: comcore.Mask, pushes: Pushes, *, strict: bool, pusher_radius: float = 0.0
) -> tuple[Pushes, dict]:
    """The pushes that hit the object, and ``{line: reason}`` for those dropped.

    A push misses or starts inside the object; either gives no contact to
    reason about. The contact is the estimator's: a round pusher's disc of
    ``pusher_radius`` metres (the posterior's, :func:`comcore.geometry.disc_contacts`:
    a graze past a corner the disc touches is kept), or with 0 the leading
    point's path on the pixels (Alg. 1 and Alg. 2: a graze counts as a
    miss). ``strict``: raise InputError naming them instead.
    """
    found = pusher_contacts(mask, pushes.actions, pusher_radius)
    bad = found.starts_inside | ~found.hit
    reasons = {
        int(line): ("starts inside the object" if inside else "misses the object")
        for line, inside, b in zip(pushes.lines, found.starts_inside, bad)
        if b
    }
    if not reasons:
        return pushes, {}
    where = line_list(reasons)
    if strict:
        raise InputError(
            f"--strict: {len(reasons)} push(es) miss the object or start inside it: "
            f"CSV line(s) {where}"
        )
    if len(reasons) == len(pushes.lines):
        raise InputError(
            f"--pushes: no push hits the object (every push misses it or starts inside it: "
            f"CSV line(s) {where}); are the mask and the pushes in the same pixel frame?"
        )
    return pushes.subset(~bad), reasons
