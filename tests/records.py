"""The executed pushes of an active estimate as arrays (tests read them often)."""

from __future__ import annotations

import numpy as np


def executed(est) -> list:
    """The records of the pushes that were executed (evidence or miss), in order."""
    return [p for p in est.pushes if p.outcome != "failed"]


def actions_of(est) -> np.ndarray:
    """Executed pushes in the first mask's frame, as scored, shape (k, 4)."""
    return np.array([p.action for p in executed(est)], dtype=float).reshape(-1, 4)


def motions_of(est) -> np.ndarray:
    """Their motions in the first mask's frame, shape (k, 3)."""
    return np.array([p.motion for p in executed(est)], dtype=float).reshape(-1, 3)


def outcomes_of(est) -> tuple:
    """``"evidence"`` or ``"miss"`` per executed push."""
    return tuple(p.outcome for p in executed(est))
