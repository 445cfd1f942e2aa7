"""Motion models: the :class:`Predictor` protocol and the limit-surface model.

A predictor maps a mask, pushes and CoM priors to the object's motions; it plugs
into every estimator through :class:`Predictor` (one method) or, for the active
session, :class:`HypothesisPredictor` (motions for many CoM hypotheses at once).
:class:`LimitSurfaceModel` is the analytic quasi-static model comcore ships: its
physics (``_physics``), the pressure consistent with a CoM (``_pressure``) and the
lattice of pushes it tabulates (``_lattice``). May import the base modules and
:mod:`comcore.geometry`.
"""

from ._limit_surface import LimitSurfaceModel
from ._predictor import (
    MAX_PUSH_THETA,
    MAX_TRANSLATION_PER_PUSH_LENGTH,
    HypothesisPredictor,
    Predictor,
    check_plausible_motions,
    check_predictor,
    predict_motions,
)

__all__ = [
    "MAX_PUSH_THETA",
    "MAX_TRANSLATION_PER_PUSH_LENGTH",
    "HypothesisPredictor",
    "LimitSurfaceModel",
    "Predictor",
    "check_plausible_motions",
    "check_predictor",
    "predict_motions",
]
