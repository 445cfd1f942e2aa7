"""Pushing an object to a goal pose while learning its CoM.

:class:`GoalSession` is the ask/tell loop to a :class:`Goal` (``_session``): each push
is chosen over the posterior's particles (:class:`CoMHypotheses`, ``_types``) by the
planner (``_planner``) from what a push is worth (``_costs``: the pose cost, the
model's error, the lookahead), among pushes along a direction
(:func:`translation_push`, ``_translation``), from the session's prior
(``_prior``). May import everything below it, :mod:`comcore.active` included.
"""

from ._session import GoalSession
from ._translation import TranslationPush, translation_push
from ._types import CoMHypotheses, Goal, MetricPose

__all__ = [
    "CoMHypotheses",
    "Goal",
    "GoalSession",
    "MetricPose",
    "TranslationPush",
    "translation_push",
]
