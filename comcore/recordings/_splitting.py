"""One long log of an object's and a pusher's poses cut into pushes.

:func:`recording_from_poses` takes one pair of pose streams per push; a robot's
log (a ROS bag, a motion-capture take) holds many pushes in one pair.
:func:`split_pushes` cuts it where the pusher is away from the object.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_positive
from ..geometry._outline import check_outline
from ._pose_streams import pusher_gaps, stream
from ._recording import DEFAULT_CONTACT_TOLERANCE_M

__all__ = ["DEFAULT_SEPARATION_M", "split_pushes"]

#: Default gap (metres) between the pusher's disc and the outline past which a push has ended.
DEFAULT_SEPARATION_M = 0.005


def split_pushes(
    outline,
    object_poses,
    pusher_poses,
    pusher_radius: float,
    *,
    separation: float = DEFAULT_SEPARATION_M,
    contact_tolerance: float = DEFAULT_CONTACT_TOLERANCE_M,
) -> list[tuple[np.ndarray, np.ndarray]]:
    """Cut one log of object and pusher poses into the pairs :func:`recording_from_poses` takes.

    The gap between the pusher's disc and the outline is taken at each pusher
    sample (the object's pose interpolated linearly at the pusher's times,
    as :func:`recording_from_poses` does). A push is a contact (a gap of at
    most ``contact_tolerance``) between two times the pusher is away (a gap
    of more than ``separation``): it runs from the first sample the pusher is
    away after the previous push (or the log's start) to the first sample it
    is away after this one (or the log's end), so each piece holds the
    pusher's approach, its first contact and the push. The gap may wander
    between the two thresholds without starting or ending a push. Pusher
    samples outside the object's time span are not used.

    Parameters
    ----------
    outline : array_like, shape (k, 2)
        The object's outline in its own frame, metres.
    object_poses, pusher_poses : array_like, shape (n, 4)
        The two streams, rows ``(t, x, y, yaw)`` (seconds, metres, radians), in
        one world frame; each is sorted by time and its yaw unwrapped.
    pusher_radius : float
        Radius of the round pusher's tip, metres (>= 0).
    separation : float, optional
        Gap (metres) past which the pusher has left the object (default 5 mm);
        at least ``contact_tolerance``.
    contact_tolerance : float, optional
        Gap (metres) that counts as contact (default 2 mm, as
        :func:`recording_from_poses`'s).

    Returns
    -------
    list of (ndarray, ndarray)
        Per push, in time order, ``(object_poses, pusher_poses)``: the rows of
        each stream over the push's span (the object's with one sample more at
        either end, where there is one, so its poses cover the pusher's).
        Empty when the pusher never touches the object.

    Raises
    ------
    TypeError, ValueError
        On invalid arguments (each named), as :func:`recording_from_poses`.

    Examples
    --------
    A pusher that comes up to a 6 cm square plate twice (the plate does not
    move here), going 2 cm away between the touches:

    >>> import numpy as np
    >>> from comcore.recordings import split_pushes
    >>> square = [(-0.03, -0.03), (0.03, -0.03), (0.03, 0.03), (-0.03, 0.03)]
    >>> t = np.linspace(0.0, 4.0, 401)
    >>> gap = 0.02 * np.abs(np.cos(np.pi * t / 2))  # away, touching at t = 1 and t = 3
    >>> pusher = np.column_stack([t, 0 * t, -0.03 - 0.004 - gap, 0 * t])
    >>> plate = np.column_stack([t, 0 * t, 0 * t, 0 * t])
    >>> pieces = split_pushes(square, plate, pusher, 0.004)
    >>> [(float(p[0, 0]), float(p[-1, 0])) for _, p in pieces]
    [(0.0, 1.17), (1.17, 3.17)]
    """
    poly = check_outline(outline)
    radius = check_positive(pusher_radius, "pusher_radius", allow_zero=True)
    tolerance = check_positive(contact_tolerance, "contact_tolerance", allow_zero=True)
    separation = check_positive(separation, "separation")
    if separation < tolerance:
        raise ValueError(
            f"separation ({separation:g} m) must be at least contact_tolerance ({tolerance:g} m)"
        )
    obj = stream(object_poses, "object_poses")
    pusher, gap = pusher_gaps(poly, obj, stream(pusher_poses, "pusher_poses"), radius)
    if len(pusher) == 0:
        return []
    touching = _hysteresis(gap <= tolerance, gap > separation)
    starts = np.flatnonzero(np.diff(touching.astype(int), prepend=0) == 1)
    pieces = []
    begin = 0
    for start in starts:
        ends = np.flatnonzero(~touching[start:])
        end = start + int(ends[0]) if len(ends) else len(pusher) - 1
        pieces.append(_piece(obj, pusher[begin : end + 1]))
        begin = end
    return pieces


def _hysteresis(on: np.ndarray, off: np.ndarray) -> np.ndarray:
    """Per sample, whether the last of ``on`` / ``off`` seen (so far) was ``on``."""
    code = np.where(on, 1, np.where(off, 0, -1))
    known = np.where(code >= 0, np.arange(len(code)), -1)
    last = np.maximum.accumulate(known)
    return np.where(last >= 0, code[np.maximum(last, 0)], 0) == 1


def _piece(obj: np.ndarray, pusher: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The object's rows covering the pusher's span (one more each side), and the pusher's."""
    lo = max(int(np.searchsorted(obj[:, 0], pusher[0, 0], side="right")) - 1, 0)
    hi = min(int(np.searchsorted(obj[:, 0], pusher[-1, 0], side="left")) + 1, len(obj))
    return obj[lo:hi].copy(), pusher.copy()
