"""Whether a push's pusher ends inside the object as its reported motion moved it.

A rigid pusher cannot pass through a rigid object: whatever the CoM and the
friction, the object moves at least as far as the pusher pushes it, so the
pusher at the end of its path lies outside the object in the object's pose
after the push. Taken back into the object's frame (through the inverse of the
observed motion about the first mask's centroid,
:func:`comcore.conventions.apply_motion`), the pusher's disc at the push's end
must not lie inside the first mask. A push whose motion is too small for its
travel (a tracker that reports a turn in place while the pusher drove 12 px into
the object) contradicts this, and no (CoM, friction, model) hypothesis explains
it: the data are inconsistent
(:attr:`comcore.active._records.SessionState.consistent`), however well some CoM
explains the motions' other features.

What is checked is the disc's centre (``pusher_radius`` behind the path's end,
which is the pusher's leading point): its depth inside the first mask, read from
the mask's smoothed signed distance (:func:`comcore.geometry.outline_field`). The
disc itself may overlap the outline by up to its radius: the radius is set by the
user and a pusher is not an exact disc, while a centre inside the outline
contradicts every round pusher of at least half the radius set (a pusher of
radius ``r`` ends with its centre at least ``r`` outside; the centre computed
with the radius set lies within the difference of the radii of it, and the
signed distance moves by at most as much as its point). The depth is a
contradiction only beyond what the noise allows:

* the measured motion's error (``tracking_noise``: ``motion_noise`` and the
  registration's residual), whose translation moves the centre by as much and
  whose rotation by the centre's distance from the centroid times the rotation
  error;
* the pusher's error across its path (``Likelihood.pusher_error``): a pusher
  executed beside its planned path ends beside its planned end;
* the outline itself: the mask's pixel staircase, smoothed, lies within
  :data:`OUTLINE_SLACK_PX` of the object's outline.

The signed distance being 1-Lipschitz, the spread of the centre's offset bounds
that of its depth: the allowance is :data:`OVERLAP_SIGMAS` of the three errors
together, plus the outline's slack. A push whose rotation was not observed is
checked at every rotation (the least depth over a grid of turns, the grid's half
step in the allowance). Misses and failed pushes carry no evidence and are not
checked; nor is any push scored by the Voting Theorem alone (``model=None``),
whose evidence is each push's sense of rotation, not how far the object went: a
turn in place reported in the sense a CoM gives is data it explains.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..conventions import rotation_matrix
from ..geometry._disc_contacts import outline_field
from ._likelihood import tracking_noise

__all__ = [
    "OUTLINE_SLACK_PX",
    "OVERLAP_SIGMAS",
    "PusherOverlap",
    "overlap_and_allowance",
    "pusher_overlap",
]

#: Standard deviations of the centre's offset (tracking and pusher error together) that its
#: depth may reach before it is a contradiction (one-sided: about 3e-7 a push).
OVERLAP_SIGMAS = 5.0
#: Pixels the smoothed outline of a mask may lie inside the object's outline.
OUTLINE_SLACK_PX = 1.0
#: Turns tried for a push whose rotation was not observed (a full turn in equal steps).
UNOBSERVED_TURNS = 720


class PusherOverlap(NamedTuple):
    """A push whose pusher ends inside the object as its motion moved it."""

    depth_px: float
    """How deep the pusher's centre lies inside the moved object (pixels of the first mask)."""
    allowed_px: float
    """The most the noise allows (pixels)."""

    def message(self, position: int) -> str:
        """Why the push at ``position`` among the pushes is inconsistent, whatever the CoM."""
        return (
            f"pushes[{position}]: the pusher's centre ends {self.depth_px:.1f} px inside the "
            f"object as the reported motion moved it (the noise allows {self.allowed_px:.1f} "
            "px): no CoM explains an object that moved less than the pusher pushed it. A "
            "motion about another point than the object's centroid, in another frame or "
            "unit, or a pusher that stopped short of its path's end?"
        )


def pusher_overlap(mask, scoring, record, gyration_px: float) -> PusherOverlap | None:
    """The push's :class:`PusherOverlap` where it exceeds what the noise allows, else None.

    Parameters
    ----------
    mask : Mask
        The first mask (the object's frame).
    scoring : comcore.active._likelihood.Scoring
        The likelihood in pixels (its tracking noise, pusher error and radius).
    record : PushRecord
        The push (its ``action`` and ``motion`` in the first mask's frame, its
        ``rotation_observed`` and ``residual_px``); only pushes with evidence scored with
        a motion model (``scoring.models``) are checked.
    gyration_px : float
        The first mask's radius of gyration (pixels), for the registration's rotation noise.

    Examples
    --------
    A square pushed 12 px past its edge that, as reported, only turned in place:
    the pusher ends deep inside it.

    >>> import numpy as np, comcore
    >>> from comcore.active._likelihood import Scoring, gyration_px
    >>> mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 8))
    >>> model = comcore.LimitSurfaceModel(pusher_radius=0.004)
    >>> scoring = Scoring.build(comcore.Likelihood(), mask, (model,), pusher_radius=0.004)
    >>> push = comcore.PushRecord(action=(22.0, 42.3, 22.0, 25.5), motion=(0.1, 0.0, 0.0),
    ...                           outcome="evidence")
    >>> round(pusher_overlap(mask, scoring, push, gyration_px(mask)).depth_px, 1)
    10.4
    >>> moved = push.__class__(action=push.action, motion=(0.0, 0.0, -13.0), outcome="evidence")
    >>> pusher_overlap(mask, scoring, moved, gyration_px(mask)) is None
    True
    """
    if record.outcome != "evidence" or record.motion is None or not scoring.models:
        return None
    depth, allowed = overlap_and_allowance(mask, scoring, record, gyration_px)
    return PusherOverlap(depth, allowed) if depth > allowed else None


def overlap_and_allowance(mask, scoring, record, gyration_px: float) -> tuple[float, float]:
    """``(depth, allowed)`` (pixels) of a push with a motion: :func:`pusher_overlap`'s figures.

    ``depth`` is negative where the pusher's centre ends outside the object.
    """
    radius = scoring.pusher_radius / scoring.resolution
    x0, y0, x1, y1 = (float(v) for v in record.action)
    unit = np.array([x1 - x0, y1 - y0]) / math.hypot(x1 - x0, y1 - y0)
    centre = np.array([x1, y1]) - radius * unit  # the disc's centre at the push's end
    theta, tx, ty = (float(v) for v in record.motion)
    turns, step = np.array([theta]), 0.0
    if not record.rotation_observed:
        step = 2 * math.pi / UNOBSERVED_TURNS
        turns = theta + step * np.arange(UNOBSERVED_TURNS)
    origin = np.asarray(mask.centroid, dtype=float)
    # the inverse of apply_motion: p = R(-theta) (c - C - t) + C, for every turn tried
    offset = centre - origin - (tx, ty)
    back = np.stack([offset @ rotation_matrix(t) for t in turns]) + origin
    # exact within the field's padding around the image; beyond it, positive (outside)
    distance = outline_field(mask).sample(back[:, 0], back[:, 1])[0]
    best = int(np.argmax(distance))
    track_theta, track_px = tracking_noise(scoring.tracking, record.residual_px, gyration_px)
    lever = float(np.hypot(*(back[best] - origin)))
    if not record.rotation_observed:
        track_theta = 0.0  # every turn was tried: the grid's half step is the rotation's error
    spread = math.sqrt(track_px**2 + (track_theta * lever) ** 2 + scoring.pusher_px**2)
    allowed = OVERLAP_SIGMAS * spread + OUTLINE_SLACK_PX + lever * step / 2
    return -float(distance[best]), allowed
