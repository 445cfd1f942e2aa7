"""Motion models: the :class:`Predictor` protocol and the limit-surface model.

A motion model plugs into every estimator through :class:`Predictor`: one
method, ``predict_hypotheses`` (the motions of pushes for many CoM hypotheses at
once), with the paper's few-shot ``predict`` built on it; what a model returns is
checked where it enters (:func:`check_model_output`).
:class:`LimitSurfaceModel` is the analytic quasi-static model comcore ships: its
physics (``_physics``), the pressure consistent with a CoM (``_pressure``) and the
lattice of pushes it tabulates (``_lattice``). May import the base modules and
:mod:`comcore.geometry`.
"""

from ._limit_surface import LimitSurfaceModel
from ._predictor import (
    MAX_PUSH_THETA,
    MAX_TRANSLATION_PER_PUSH_LENGTH,
    MAX_TURN_PER_LENGTH,
    Predictor,
    check_model_output,
    check_plausible_motions,
    check_predictor,
    predict_motions,
    turn_bounds,
)

__all__ = [
    "MAX_PUSH_THETA",
    "MAX_TRANSLATION_PER_PUSH_LENGTH",
    "MAX_TURN_PER_LENGTH",
    "LimitSurfaceModel",
    "Predictor",
    "check_model_output",
    "check_plausible_motions",
    "check_predictor",
    "predict_motions",
    "turn_bounds",
]
