"""The paper's two estimators: Alg. 1 (the heat map) and Alg. 2 (progressive halving).

:func:`estimate_heatmap` and :func:`rotation_heatmap` (Alg. 1),
:func:`estimate_progressive` and the Action Equality Score :func:`equality_score`
(Alg. 2), each as the paper specifies it (what each computed on the way in
:class:`HeatmapDetails` and :class:`ProgressiveDetails`), with the choices made where it is silent
written in the module. May import the base modules, :mod:`comcore.geometry` and
:mod:`comcore.vt`.
"""

from .._types import HeatmapDetails, ProgressiveDetails
from ._heatmap import estimate_heatmap, rotation_heatmap
from ._progressive import equality_score, estimate_progressive

__all__ = [
    "HeatmapDetails",
    "ProgressiveDetails",
    "equality_score",
    "estimate_heatmap",
    "estimate_progressive",
    "rotation_heatmap",
]
