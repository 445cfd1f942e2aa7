"""The active estimator: the ask/tell session, its likelihood, push choice and stop rule.

:class:`ActiveSession` chooses each push, reads its outcome and keeps a posterior
over the CoM (``_grid``) scored by a push's likelihood (``_likelihood``, the motion
model's term in ``_motion_term``); the push choice (``_choice``), the stop rule
(``_stop``), the frames of a push (``_path`` reads them, ``_path_term`` scores them),
what a user sets (:class:`Likelihood`, :class:`StopRule` in ``_stop``,
:class:`PushChoice` in ``_choice``, the shared defaults in ``_options``), what it
records (``_records``: :class:`SessionState`, and the :class:`PosteriorDetails` an
estimate carries) and how it reads one push (``_reading``) each have a module.
:func:`estimate_active` is its blocking form; :func:`estimate_posterior` the same
posterior over recorded pushes, with its region from the bagged posterior (``_bagging``);
:func:`calibrate_model_weight` learns the model's power from recordings. May import
everything below it: the base modules, :mod:`comcore.geometry`, :mod:`comcore.vt`,
:mod:`comcore.motion` and :mod:`comcore.camera`.
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports
from .._types import PathPoint, PosteriorDetails
from ._choice import PushChoice
from ._likelihood import Likelihood
from ._options import RECORDED_SYSTEMATIC_ERROR, SESSION_SYSTEMATIC_ERROR
from ._posterior import RECORDED_BOOTSTRAP, estimate_posterior
from ._records import SessionState, credible_level
from ._session import ActiveSession
from ._stop import SenseCheck, StopRule

# The blocking loop and the power's calibration load on first use.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "estimate_active": "_blocking",
        "PowerCalibration": "_calibrate",
        "calibrate_model_weight": "_calibrate",
    },
)
if TYPE_CHECKING:
    from ._blocking import estimate_active
    from ._calibrate import PowerCalibration, calibrate_model_weight

__all__ = [
    "RECORDED_BOOTSTRAP",
    "RECORDED_SYSTEMATIC_ERROR",
    "SESSION_SYSTEMATIC_ERROR",
    "ActiveSession",
    "Likelihood",
    "PathPoint",
    "PosteriorDetails",
    "PowerCalibration",
    "PushChoice",
    "SenseCheck",
    "SessionState",
    "StopRule",
    "calibrate_model_weight",
    "credible_level",
    "estimate_active",
    "estimate_posterior",
]
