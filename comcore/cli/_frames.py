"""The frames CSV of ``comcore estimate --frames``: what a camera saw during each push.

One row per frame, with the columns :data:`FRAME_COLUMNS`: ``push`` numbers the
push the frame was taken during, 1 for the first data row of the pushes CSV, 2
for the second, and so on (push 1 is the pushes CSV's line 2 when its header is
line 1 and no line is blank: every message gives both); ``px, py`` is where the
pusher's leading point was then (pixels of the mask, x = column, y = row down);
``theta, tx, ty`` the object's motion since the push began, in the conventions
of the pushes CSV (theta counter-clockwise on screen, in ``--theta-units``; tx,
ty the displacement of the mask's area centroid in pixels). The rows of one push
are in the order they were taken; a push may have none. Each becomes a
:class:`comcore.PushFrame` whose view is a :class:`comcore.Motion`, for
:func:`comcore.estimate_posterior`'s ``frames``.

Every problem is an :class:`~comcore.cli._inputs.InputError` naming the file and
its line numbers (the header is line 1), as for the pushes CSV.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from pathlib import Path

import comcore

from ._inputs import InputError, line_list

__all__ = [
    "FRAME_COLUMNS",
    "Frames",
    "dropped_frames",
    "dropped_note",
    "frame_error",
    "read_frames",
]

#: Columns of the frames CSV: the push (1-based), the pusher then (pixels), the motion since.
FRAME_COLUMNS = ("push", "px", "py", "theta", "tx", "ty")


@dataclass(frozen=True)
class Frames:
    """The frames of a CSV, per push of the pushes CSV (its row order).

    ``rows[k]``: the frames of push ``k + 1``, each ``(line, PushFrame)`` with
    its line in the frames CSV, in the file's order.
    """

    path: Path
    rows: tuple

    @property
    def n_frames(self) -> int:
        """How many frames the CSV holds."""
        return sum(len(r) for r in self.rows)

    def theta_from_degrees(self) -> Frames:
        """The frames with theta, given in degrees, in radians."""

        def in_radians(frame):
            view = frame.view
            return frame._replace(view=comcore.Motion(math.radians(view.theta), *view[1:]))

        rows = tuple(tuple((line, in_radians(f)) for line, f in push) for push in self.rows)
        return Frames(self.path, rows)

    def of(self, kept) -> list:
        """The frames of the pushes ``kept`` (0-based rows of the pushes CSV), per push.

        :func:`comcore.estimate_posterior`'s ``frames``: one list per push, None
        where a push has none.
        """
        return [[f for _, f in self.rows[k]] or None for k in kept]


def read_frames(path, pushes_lines) -> Frames:
    """The frames of a CSV with the columns :data:`FRAME_COLUMNS`.

    ``pushes_lines``: the pushes CSV's line of each of its rows, in order (push
    ``k`` is row ``k``, 1-based); the messages name both.
    """
    path = Path(path)
    n = len(pushes_lines)
    rows, lines = [], []
    try:
        with path.open(newline="", encoding="utf-8-sig") as f:
            reader = csv.reader(f)
            header = [h.strip() for h in next(reader, [])]
            _check_header(path, header)
            for row in reader:
                if not any(cell.strip() for cell in row):
                    continue  # a blank line, as the pushes CSV skips them
                if len(row) != len(header):
                    raise InputError(
                        f"--frames: {path} line {reader.line_num}: {len(row)} values, the "
                        f"header has {len(header)} ({', '.join(FRAME_COLUMNS)})"
                    )
                rows.append(dict(zip(header, (cell.strip() for cell in row))))
                lines.append(reader.line_num)
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise InputError(f"--frames: cannot read {path}: {e}") from e
    per_push: list = [[] for _ in range(n)]
    for row, line in zip(rows, lines):
        values = {}
        for column in FRAME_COLUMNS:
            text = row[column]
            try:
                value = float(text)
            except ValueError:
                raise InputError(
                    f"--frames: {path} line {line}, column {column}: {text!r} is not a number"
                ) from None
            if not math.isfinite(value):
                raise InputError(
                    f"--frames: {path} line {line}, column {column}: {text!r} is not finite"
                )
            values[column] = value
        push = values["push"]
        if not push.is_integer() or not 1 <= push <= n:
            raise InputError(
                f"--frames: {path} line {line}, column push: {row['push']!r} is not a push of "
                f"the pushes CSV: its {n} pushes are numbered 1 to {n} in the order of its rows "
                f"(push 1 is its first data row, line {int(pushes_lines[0])})"
            )
        frame = comcore.PushFrame(
            (values["px"], values["py"]),
            comcore.Motion(values["theta"], values["tx"], values["ty"]),
        )
        per_push[int(push) - 1].append((line, frame))
    return Frames(path, tuple(tuple(p) for p in per_push))


def _check_header(path: Path, header: list) -> None:
    """The header holds each of :data:`FRAME_COLUMNS` once and nothing else, or InputError."""
    expected = ", ".join(FRAME_COLUMNS)
    got = ", ".join(h or "(unnamed)" for h in header) or "no header"
    missing = [c for c in FRAME_COLUMNS if c not in header]
    if missing:
        raise InputError(
            f"--frames: {path} lacks column(s) {', '.join(missing)}; expected {expected}, got {got}"
        )
    extra = [h or "(unnamed)" for h in header if h not in FRAME_COLUMNS]
    twice = sorted({h for h in header if header.count(h) > 1})
    if extra or twice:
        what = (
            f"column(s) {', '.join(extra)} that are not frame columns"
            if extra
            else f"column(s) {', '.join(twice)} twice"
        )
        raise InputError(f"--frames: {path} has {what}; expected {expected}, got {got}")


#: ``frames[k]: `` at the start of estimate_posterior's messages about push k's frames, and
#: ``frames[j]`` (with ``.pusher`` or ``.view``) for frame j of it.
_PUSH_PREFIX = re.compile(r"^frames\[(\d+)\]: ")
_FRAME = re.compile(r"frames\[(\d+)\](\.pusher|\.view)?")


def frame_error(message: str, frames: Frames, kept, pushes_lines) -> InputError | None:
    """:func:`comcore.estimate_posterior`'s error about the frames, named by CSV lines.

    ``kept``: the pushes CSV row (0-based) of each push given to it. None when
    ``message`` is not about a push's frames.

    Examples
    --------
    >>> frames = Frames(Path("f.csv"), ((), ((5, None), (6, None))))
    >>> print(frame_error("frames[0]: frames[1].pusher is 3.0 px behind", frames, [1], [2, 3]))
    --frames: f.csv push 2 (pushes CSV line 3): line 6's pusher is 3.0 px behind
    """
    head = _PUSH_PREFIX.match(message)
    if head is None or int(head.group(1)) >= len(kept):
        return None
    k = kept[int(head.group(1))]
    rows = frames.rows[k]

    def line(match) -> str:
        j = int(match.group(1))
        if j >= len(rows):
            return match.group(0)
        part = {".pusher": "'s pusher", ".view": "'s motion"}.get(match.group(2) or "", "")
        return f"line {rows[j][0]}{part}"

    rest = _FRAME.sub(line, message[head.end() :])
    return InputError(
        f"--frames: {frames.path} push {k + 1} (pushes CSV line {int(pushes_lines[k])}): {rest}"
    )


def dropped_frames(est, frames: Frames, kept, pushes_lines, dropped: dict) -> list:
    """The JSON's ``dropped_frames``: per push with frames not scored, which and why.

    One ``{"push", "line", "frames": [{"line", "reason"}, ...]}`` per push (its
    number, its pushes CSV line, and its frames CSV lines) in push order: the
    reasons of ``PushRecord.dropped_frames`` (:mod:`comcore.active._path`:
    ``before_contact``, ``at_end``, ``thinned``, ``jump``), ``push_dropped: ...``
    for the frames of a push dropped with it (``dropped``: ``{line: reason}``
    of :func:`comcore.cli._inputs.screen_pushes`) and ``push_miss`` for those
    of a push that moved the object less than the noise (no evidence, no path).
    ``kept``: the pushes CSV row (0-based) of each push the estimate was given.
    """
    why: dict = {}  # push row (0-based) -> [(frame index, reason)]
    records = {r.index: r for r in est.pushes if r.index is not None}
    at = {k: i for i, k in enumerate(kept)}
    for k, rows in enumerate(frames.rows):
        if not rows:
            continue
        line = int(pushes_lines[k])
        if k not in at:
            why[k] = [
                (j, f"push_dropped: {dropped.get(line, 'not estimated')}") for j in range(len(rows))
            ]
            continue
        record = records.get(at[k])
        if record is None or record.outcome != "evidence":
            reason = "push_miss: the object moved less than the noise" if record else "push_unused"
            why[k] = [(j, reason) for j in range(len(rows))]
        elif record.dropped_frames:
            why[k] = list(record.dropped_frames)
    return [
        {
            "push": k + 1,
            "line": int(pushes_lines[k]),
            "frames": [{"line": frames.rows[k][j][0], "reason": r} for j, r in why[k]],
        }
        for k in sorted(why)
    ]


def dropped_note(frames: Frames, dropped_rows) -> str:
    """The warning's words about the frames of the pushes dropped by screening, or ""."""
    lines = [line for k in dropped_rows for line, _ in frames.rows[k]]
    if not lines:
        return ""
    where = line_list(lines)
    return f"; their {len(lines)} frame(s) are dropped with them: --frames line(s) {where}"
