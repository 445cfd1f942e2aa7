"""comcore: find the centre of mass of an unknown flat object by pushing it.

The top level holds what a robot stack uses: the value types (:class:`Mask`,
:class:`Action`, :class:`Motion`, :class:`Estimate`, :class:`PushRecord`,
:class:`Status`), the
errors, the active session and its option groups, the posterior over recorded
pushes, the paper's estimators, the goal session, camera frames to masks and
motions, recordings, and the :class:`Predictor` protocol. Everything else is public
in the subpackage that holds it:

* :mod:`comcore.conventions`: frames, signs, units and tolerances (the one place).
* :mod:`comcore.checks`: the validators, for predictor and simulator authors.
* :mod:`comcore.geometry`: contacts, lines, outlines, rasters, push sampling.
* :mod:`comcore.vt`: Mason's Voting Theorem.
* :mod:`comcore.paper`: Alg. 1 and Alg. 2.
* :mod:`comcore.motion`: the predictor protocol and the limit-surface model.
* :mod:`comcore.camera`: image to mask, registration, pose tracking.
* :mod:`comcore.recordings`: recorded pushes (and ``comcore.recordings.mit_push``).
* :mod:`comcore.active`: the active session, its likelihood, choice and stop rule.
* :mod:`comcore.goal`: pushing to a goal pose.
* :mod:`comcore.ros`: estimates as ROS messages' fields (plain dicts, no ROS needed).
* :mod:`comcore.plot`, :mod:`comcore.cli`, :mod:`comcore.bench`: pictures, the
  command line and the benchmark (each loads its extras when imported).

``import comcore`` loads numpy and scipy only, and the core's modules: the goal session,
recordings, ROS messages and the validators' namespace load on first use.

Examples
--------
>>> import numpy as np, comcore
>>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4), resolution=0.0025)
>>> actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
>>> motions = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)]
>>> comcore.estimate_progressive(mask, actions, motions).com
(10.5, 10.5)
"""

from typing import TYPE_CHECKING

from . import active as active
from . import camera as camera
from . import conventions as conventions
from . import geometry as geometry
from . import motion as motion
from . import paper as paper
from . import vt as vt
from ._errors import ComcoreError, ImageError, PushFailedError, SessionError
from ._lazy import lazy_exports
from ._mask import Mask
from ._status import Status
from ._types import Action, Estimate, Motion, PushFrame, PushRecord
from .active import (
    ActiveSession,
    Likelihood,
    PushChoice,
    StopRule,
    credible_level,
    estimate_posterior,
)
from .camera import MotionMeasurement, measure_motion
from .conventions import apply_motion
from .geometry import mask_from_outline, sample_pushes
from .motion import HypothesisPredictor, LimitSurfaceModel, Predictor
from .paper import estimate_heatmap, estimate_progressive

# The application layers load on first use: ``import comcore`` loads the core alone.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "checks": "checks",
        "goal": "goal",
        "recordings": "recordings",
        "ros": "ros",
        "Goal": "goal",
        "GoalSession": "goal",
        "RecordedPush": "recordings",
        "Recording": "recordings",
        "SkippedPush": "recordings",
        "recording_from_poses": "recordings",
        "estimate_active": "active",
        "PowerCalibration": "active",
        "calibrate_model_weight": "active",
        "mask_from_image": "camera",
        "TableCalibration": "camera",
        "TableView": "camera",
        "calibrate_table": "camera",
    },
)
if TYPE_CHECKING:  # what the lazy names are, for type checkers and editors
    from . import checks as checks
    from . import goal as goal
    from . import recordings as recordings
    from . import ros as ros
    from .active import PowerCalibration, calibrate_model_weight, estimate_active
    from .camera import TableCalibration, TableView, calibrate_table, mask_from_image
    from .goal import Goal, GoalSession
    from .recordings import RecordedPush, Recording, SkippedPush, recording_from_poses

__version__ = "0.1.0"

__all__ = [
    "Action",
    "ActiveSession",
    "ComcoreError",
    "Estimate",
    "Goal",
    "GoalSession",
    "HypothesisPredictor",
    "ImageError",
    "Likelihood",
    "LimitSurfaceModel",
    "Mask",
    "Motion",
    "MotionMeasurement",
    "PowerCalibration",
    "Predictor",
    "PushChoice",
    "PushFailedError",
    "PushFrame",
    "PushRecord",
    "RecordedPush",
    "Recording",
    "SessionError",
    "SkippedPush",
    "Status",
    "StopRule",
    "TableCalibration",
    "TableView",
    "__version__",
    "apply_motion",
    "calibrate_model_weight",
    "calibrate_table",
    "credible_level",
    "estimate_active",
    "estimate_heatmap",
    "estimate_posterior",
    "estimate_progressive",
    "mask_from_image",
    "mask_from_outline",
    "measure_motion",
    "recording_from_poses",
    "sample_pushes",
]
