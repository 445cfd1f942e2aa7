"""The paper's few-shot motion model: an attentive neural process (needs ``comcore[anp]``).

``AnpPredictor()`` loads the weights shipped in ``predictors/anp/weights/anp.pt``;
``python -m predictors.anp.train`` regenerates them from simulated pushes
(:mod:`predictors.anp.data`). See ``docs/explanation/motion-models.md``.
"""

try:
    import torch  # noqa: F401
except ImportError as e:  # pragma: no cover - exercised in a subprocess test
    raise ImportError(
        "predictors.anp (AnpPredictor) needs PyTorch: pip install comcore[anp]"
    ) from e

from .model import AnpConfig, AnpModel
from .predictor import DEFAULT_WEIGHTS, AnpPredictor, load_weights, save_weights

__all__ = [
    "DEFAULT_WEIGHTS",
    "AnpConfig",
    "AnpModel",
    "AnpPredictor",
    "load_weights",
    "save_weights",
]
