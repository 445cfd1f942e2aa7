"""comcore: find the centre of mass of an unknown flat object by pushing it.

The core is pure numpy/scipy: value types (:class:`Mask`, :class:`Action`,
:class:`Motion`, :class:`Estimate`), contact geometry, Mason's Voting Theorem
(:mod:`comcore.vt`), the paper's two estimators and the :class:`Predictor`
protocol through which motion models plug in. Conventions (pixel frame, sign of
theta, units) are defined once, in :mod:`comcore._conventions`.

Examples
--------
>>> import numpy as np, comcore
>>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4), resolution=0.0025)
>>> actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
>>> motions = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)]
>>> comcore.estimate_progressive(mask, actions, motions).com
(10.5, 10.5)
"""

from . import vt
from ._active import estimate_active
from ._bagging import RECORDED_BOOTSTRAP
from ._calibrate import PowerCalibration, calibrate_model_weight
from ._conventions import (
    ANGLE_EPS,
    DEFAULT_RESOLUTION,
    LENGTH_EPS,
    PLAUSIBLE,
    apply_motion,
    ccw_cross,
    check_plausible,
    pixel_centres,
    quarter_turn_ccw,
    rotate_vectors,
    rotation_matrix,
    rotation_sign,
)
from ._disc_contacts import disc_contacts
from ._errors import ComcoreError, ImageError, PushFailedError, SessionError
from ._flat_options import option_groups
from ._geometry import Contacts, contacts, signed_line_distance, split_by_line
from ._goal_session import GoalSession
from ._goal_translation import TranslationPush, translation_push
from ._goal_types import CoMHypotheses, Goal
from ._heatmap import estimate_heatmap, rotation_heatmap
from ._image import mask_from_image
from ._limit_surface_model import LimitSurfaceModel
from ._mask import Mask
from ._options import (
    RECORDED_SYSTEMATIC_ERROR,
    SESSION_SYSTEMATIC_ERROR,
    Likelihood,
    PushChoice,
    StopRule,
)
from ._outline import mask_from_outline
from ._outline_field import OutlineField, outline_field
from ._posterior import estimate_posterior
from ._predictor import (
    HypothesisPredictor,
    Predictor,
    check_plausible_motions,
    check_predictor,
    predict_motions,
)
from ._progressive import equality_score, estimate_progressive
from ._raster import rasterise_polygon
from ._recording import RecordedPush, Recording, SkippedPush, recording_from_poses
from ._records import credible_level
from ._regions import largest_component
from ._registration import MotionMeasurement, measure_motion
from ._sampling import sample_pushes
from ._session import ActiveSession
from ._types import Action, Estimate, Motion, PushRecord
from ._validation import (
    check_actions,
    check_mask,
    check_motions,
    check_mu,
    check_point,
    check_points,
    check_positive,
    check_priors,
    check_probability,
    check_rng,
)

__version__ = "0.1.0"

__all__ = [
    "ANGLE_EPS",
    "DEFAULT_RESOLUTION",
    "LENGTH_EPS",
    "PLAUSIBLE",
    "RECORDED_BOOTSTRAP",
    "RECORDED_SYSTEMATIC_ERROR",
    "SESSION_SYSTEMATIC_ERROR",
    "Action",
    "ActiveSession",
    "CoMHypotheses",
    "ComcoreError",
    "Contacts",
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
    "OutlineField",
    "PowerCalibration",
    "Predictor",
    "PushChoice",
    "PushFailedError",
    "PushRecord",
    "RecordedPush",
    "Recording",
    "SessionError",
    "SkippedPush",
    "StopRule",
    "TranslationPush",
    "__version__",
    "apply_motion",
    "calibrate_model_weight",
    "ccw_cross",
    "check_actions",
    "check_mask",
    "check_motions",
    "check_mu",
    "check_plausible",
    "check_plausible_motions",
    "check_point",
    "check_points",
    "check_positive",
    "check_predictor",
    "check_priors",
    "check_probability",
    "check_rng",
    "contacts",
    "credible_level",
    "disc_contacts",
    "equality_score",
    "estimate_active",
    "estimate_heatmap",
    "estimate_posterior",
    "estimate_progressive",
    "largest_component",
    "mask_from_image",
    "mask_from_outline",
    "measure_motion",
    "option_groups",
    "outline_field",
    "pixel_centres",
    "predict_motions",
    "quarter_turn_ccw",
    "rasterise_polygon",
    "recording_from_poses",
    "rotate_vectors",
    "rotation_heatmap",
    "rotation_matrix",
    "rotation_sign",
    "sample_pushes",
    "signed_line_distance",
    "split_by_line",
    "translation_push",
    "vt",
]
