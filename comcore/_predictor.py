"""The :class:`Predictor` protocol: how motion models plug into comcore."""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from ._mask import Mask
from ._validation import check_actions, check_motions

__all__ = ["HypothesisPredictor", "Predictor", "check_predictor", "predict_motions"]


@runtime_checkable
class Predictor(Protocol):
    """Anything that predicts the motion of pushes on an object.

    One method: ``predict(mask, actions, priors=())`` returns one motion
    ``(theta, tx, ty)`` per action, as an array of shape (n, 3) or a sequence
    of :class:`comcore.Motion`. ``priors`` are ``(Action, Motion)`` pairs
    already observed on the same mask (a few-shot predictor conditions on
    them; others may ignore them). Conventions: :mod:`comcore._conventions`.

    Examples
    --------
    A toy predictor that believes the CoM is the mask's centroid and turns the
    object by 0.01 rad per pixel of lever arm:

    >>> import numpy as np
    >>> import comcore
    >>> class LeverArm:
    ...     def predict(self, mask, actions, priors=()):
    ...         acts = comcore.check_actions(actions)
    ...         lever = comcore.signed_line_distance([mask.centroid], acts)[0]
    ...         theta = 0.01 * lever  # CoM on the push's CCW side: CCW
    ...         return np.column_stack([theta, acts[:, 2] - acts[:, 0], acts[:, 3] - acts[:, 1]])
    >>> isinstance(LeverArm(), comcore.Predictor)
    True
    >>> m = comcore.Mask(np.pad(np.ones((10, 10), bool), 3))
    >>> comcore.predict_motions(LeverArm(), m, [(0, 5, 6, 5)]).round(3)
    array([[-0.025,  6.   ,  0.   ]])
    """

    def predict(self, mask: Mask, actions, priors=()):  # pragma: no cover - protocol
        """Return motions ``(theta, tx, ty)`` for each action, shape (n, 3)."""
        ...


@runtime_checkable
class HypothesisPredictor(Protocol):
    """A motion model that predicts for given CoM hypotheses and contact friction.

    Optional extension of :class:`Predictor` used by estimators that keep a
    belief over the CoM (``comcore.estimate_active``): one method,
    ``predict_hypotheses(mask, actions, coms, mu)`` returning an array of shape
    ``(n_coms, n_actions, 3)``: the motion ``(theta, tx, ty)`` of each action if
    the CoM were at each of ``coms`` (pixels, shape (n_coms, 2)) and the
    contact friction were ``mu`` (a float).

    Examples
    --------
    >>> import numpy as np
    >>> import comcore
    >>> class Lever:
    ...     def predict_hypotheses(self, mask, actions, coms, mu):
    ...         lever = comcore.signed_line_distance(coms, actions)  # (n_coms, n_actions)
    ...         return np.stack([0.01 * lever, 0 * lever, 0 * lever], axis=-1)
    >>> isinstance(Lever(), comcore.HypothesisPredictor)
    True
    """

    def predict_hypotheses(self, mask: Mask, actions, coms, mu: float):  # pragma: no cover
        """Return motions of shape (n_coms, n_actions, 3)."""
        ...


def check_predictor(predictor, name: str = "predictor") -> Predictor:
    """Raise TypeError unless ``predictor`` implements :class:`Predictor`."""
    if not isinstance(predictor, Predictor) or not callable(getattr(predictor, "predict", None)):
        raise TypeError(
            f"{name} must implement comcore.Predictor (a predict(mask, actions, priors=()) "
            f"method), got {type(predictor).__name__}"
        )
    return predictor


def predict_motions(predictor, mask: Mask, actions, priors=()) -> np.ndarray:
    """Call a predictor and validate what it returns: shape (n, 3), finite."""
    predictor = check_predictor(predictor)
    acts = check_actions(actions)
    out = predictor.predict(mask, acts, priors)
    try:
        return check_motions(
            out, n=acts.shape[0], name=f"{type(predictor).__name__}.predict output"
        )
    except (TypeError, ValueError) as e:
        raise ValueError(f"predictor returned invalid motions: {e}") from e
