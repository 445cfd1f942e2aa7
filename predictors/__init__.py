"""Motion predictors that plug into comcore through :class:`comcore.Predictor`.

* :class:`OraclePredictor` runs the simulator on the true object (needs ``comcore[sim]``).
* :class:`EllipsoidPredictor` is the analytic ellipsoidal limit-surface model (numpy/scipy).
* :class:`AnpPredictor` is the paper's few-shot attentive neural process (needs ``comcore[anp]``).

Names are imported lazily, so ``import predictors`` pulls in neither torch nor pymunk.
"""

from __future__ import annotations

import importlib

__all__ = ["AnpPredictor", "EllipsoidFit", "EllipsoidPredictor", "OraclePredictor"]

_LAZY = {
    "OraclePredictor": "predictors.oracle",
    "EllipsoidPredictor": "predictors.ellipsoid",
    "EllipsoidFit": "predictors.ellipsoid",
    "AnpPredictor": "predictors.anp",
}


def __getattr__(name: str):
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'predictors' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
