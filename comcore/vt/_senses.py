"""The Voting Theorem's check of recorded pushes: the senses each hypothesis leaves unexplained.

:class:`SenseTally` counts, per (CoM, friction) hypothesis, the pushes whose observed
rotation sense it cannot explain; the stop rule compares the fewest with what chance allows
(:func:`comcore.active._stop.sense_check`). It is the one check a recording with the Voting Theorem
alone can make (a sign-flipped or x/y-swapped recording fails it).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["UNEXPLAINED_STDS", "SenseTally"]

#: Standard deviation of a logistic of unit scale (its scale is std * sqrt(3) / pi).
_LOGISTIC_STD = math.pi / math.sqrt(3.0)
#: A hypothesis leaves a push's observed sense unexplained when it lies more than this many
#: standard deviations of the force line's blur on the wrong side of the line (the logistic
#: edge then gives the observed sense 2.6 % before ``flip_prob``).
UNEXPLAINED_STDS = 2.0


class SenseTally:
    """How many pushes' observed senses each (CoM, friction) hypothesis leaves unexplained.

    The Voting Theorem's check of recorded pushes, with or without a motion
    model: a push is unexplained by a hypothesis that lies more than
    :data:`UNEXPLAINED_STDS` standard deviations of the force line's blur on
    the wrong side of its force line. Under the hypothesis that made the
    pushes, push ``i`` is unexplained with probability at most
    ``allowed[i]``: its sense's flip probability (``flip_prob``, more for a
    rotation within the tracking noise of zero: :func:`sense_flip_prob`)
    plus the edge's 2.6 %. The stop rule compares the fewest unexplained
    pushes with those probabilities (:func:`comcore.active._stop.sense_check`).

    Examples
    --------
    Two pushes whose senses put the CoM on opposite sides of one line: every
    hypothesis leaves one of them unexplained.

    >>> tally = SenseTally((3, 1))
    >>> distances = np.array([[-9.0], [0.0], [9.0]])  # three CoMs, one friction value
    >>> tally.add(distances, +1, 0.05, 1.0)
    >>> tally.add(distances, -1, 0.05, 1.0)
    >>> tally.counts[:, 0].tolist(), tally.fewest, len(tally.allowed)
    ([1, 0, 1], 0, 2)
    """

    def __init__(self, shape: tuple[int, int]):
        self.counts = np.zeros(shape, dtype=np.int64)
        self.allowed: list[float] = []

    def add(self, distances, sense: int, flip_prob: float, scale: float) -> None:
        """Count one push of observed ``sense`` (0: none, not counted) at ``distances`` (p, m).

        ``flip_prob`` is the probability its sense is wrong, ``scale`` the
        force line's logistic scale (pixels).
        """
        if sense == 0:
            return
        margin = UNEXPLAINED_STDS * _LOGISTIC_STD * scale
        self.counts += np.asarray(sense * distances < -margin)
        edge = 1.0 / (1.0 + math.exp(UNEXPLAINED_STDS * _LOGISTIC_STD))
        self.allowed.append(flip_prob + (1.0 - 2.0 * flip_prob) * edge)

    @property
    def fewest(self) -> int:
        """The fewest pushes any hypothesis leaves unexplained (0 before any)."""
        return int(self.counts.min()) if self.counts.size else 0

    def at_pixel(self, index: int) -> int:
        """The fewest pushes a CoM at grid pixel ``index`` leaves unexplained, any friction."""
        return int(self.counts[index].min())
