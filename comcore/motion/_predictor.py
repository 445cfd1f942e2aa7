"""The :class:`Predictor` protocol: how motion models plug into comcore."""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from .._mask import Mask
from .._validation import check_actions, check_motions

__all__ = [
    "HypothesisPredictor",
    "Predictor",
    "check_plausible_motions",
    "check_predictor",
    "predict_motions",
]

#: The largest rotation (radians) a predicted push may cause: half a turn. A push turns
#: an object far less; beyond it the predictor is broken, not the object.
MAX_PUSH_THETA = np.pi
#: The largest displacement of the object's centroid a predicted push may cause, as a
#: multiple of the push's length (the pusher's whole path, approach included).
MAX_TRANSLATION_PER_PUSH_LENGTH = 10.0


def check_plausible_motions(motions, actions, who: str) -> np.ndarray:
    """Refuse predicted motions that no push can cause; return them as an array.

    A push cannot turn an object by more than half a turn (``|theta| <= pi``)
    or carry its centroid more than ten times the push's length. A predictor
    that says otherwise is broken (a corrupt weights file, a unit mistake), and
    its numbers (``4e34``) would otherwise flow into an estimator as evidence.
    comcore's own predictors and :func:`predict_motions` call this.

    Parameters
    ----------
    motions : array_like, shape (..., n, 3)
        Predicted ``(theta, tx, ty)`` (radians, pixels) of each action, for
        any number of leading axes (CoM hypotheses, say).
    actions : array_like, shape (n, 4)
        The pushes they were predicted for (pixels).
    who : str
        The predictor, for the message (``"AnpPredictor"``).

    Returns
    -------
    numpy.ndarray, shape (..., n, 3)

    Raises
    ------
    ValueError
        Naming ``who``, the push, the impossible number and the bound.

    Examples
    --------
    >>> import numpy as np
    >>> check_plausible_motions([[0.1, 5.0, 0.0]], [(0, 0, 20, 0)], "Mine").tolist()
    [[0.1, 5.0, 0.0]]
    >>> check_plausible_motions([[4e34, 5.0, 0.0]], [(0, 0, 20, 0)], "Mine")
    Traceback (most recent call last):
    ...
    ValueError: Mine predicted a motion no push can cause: push 0 (20 px long) turns the object by 4e+34 rad, more than half a turn (pi); the predictor is broken (corrupt weights, a unit mistake?), not the object
    """  # noqa: E501
    out = np.asarray(motions, dtype=float)
    acts = np.asarray(actions, dtype=float).reshape(-1, 4)
    if out.ndim < 2 or out.shape[-1] != 3 or out.shape[-2] != len(acts):
        raise ValueError(
            f"{who} predicted motions of shape {out.shape}, expected (..., {len(acts)}, 3)"
        )
    length = np.hypot(acts[:, 2] - acts[:, 0], acts[:, 3] - acts[:, 1])
    theta = np.abs(out[..., 0])
    shift = np.hypot(out[..., 1], out[..., 2])
    turned = ~(theta <= MAX_PUSH_THETA)  # NaN is refused too
    carried = ~(shift <= MAX_TRANSLATION_PER_PUSH_LENGTH * length)
    if not (turned.any() or carried.any()):
        return out
    broken = " the predictor is broken (corrupt weights, a unit mistake?), not the object"
    if turned.any():
        where = np.argwhere(turned)[0]
        i = int(where[-1])
        raise ValueError(
            f"{who} predicted a motion no push can cause: push {i} ({length[i]:.3g} px long) "
            f"turns the object by {out[tuple(where)][0]:.3g} rad, more than half a turn (pi);"
            + broken
        )
    where = np.argwhere(carried)[0]
    i = int(where[-1])
    raise ValueError(
        f"{who} predicted a motion no push can cause: push {i} ({length[i]:.3g} px long) "
        f"moves the object by {shift[tuple(where)]:.3g} px, more than "
        f"{MAX_TRANSLATION_PER_PUSH_LENGTH:g} times the push's length;" + broken
    )


@runtime_checkable
class Predictor(Protocol):
    """Anything that predicts the motion of pushes on an object.

    One method: ``predict(mask, actions, priors=())`` returns one motion
    ``(theta, tx, ty)`` per action, as an array of shape (n, 3) or a sequence
    of :class:`comcore.Motion`. ``priors`` are ``(Action, Motion)`` pairs
    already observed on the same mask (a few-shot predictor conditions on
    them; others may ignore them). Conventions: :mod:`comcore.conventions`.

    Examples
    --------
    A toy predictor that believes the CoM is the mask's centroid and turns the
    object by 0.01 rad per pixel of lever arm:

    >>> import numpy as np
    >>> import comcore
    >>> class LeverArm:
    ...     def predict(self, mask, actions, priors=()):
    ...         acts = comcore.checks.check_actions(actions)
    ...         lever = comcore.geometry.signed_line_distance([mask.centroid], acts)[0]
    ...         theta = 0.01 * lever  # CoM on the push's CCW side: CCW
    ...         return np.column_stack([theta, acts[:, 2] - acts[:, 0], acts[:, 3] - acts[:, 1]])
    >>> isinstance(LeverArm(), comcore.Predictor)
    True
    >>> m = comcore.Mask(np.pad(np.ones((10, 10), bool), 3))
    >>> comcore.motion.predict_motions(LeverArm(), m, [(0, 5, 6, 5)]).round(3)
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

    How often it is called: :func:`comcore.estimate_posterior` asks once per friction
    value, all pushes in one call (in chunks on large masks); a session once per push
    and friction value. An optional ``predict_frictions(mask, actions, coms, mus)``
    returning ``(n_mus, n_coms, n_actions, 3)`` is asked once for every friction value
    instead (docs/how-to/your-predictor.md, "How often your model is called").

    Examples
    --------
    >>> import numpy as np
    >>> import comcore
    >>> class Lever:
    ...     def predict_hypotheses(self, mask, actions, coms, mu):
    ...         lever = comcore.geometry.signed_line_distance(coms, actions)  # (n_coms, n_actions)
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
    """Call a predictor and validate what it returns.

    Parameters
    ----------
    predictor : Predictor
    mask : Mask
    actions : array_like, shape (n, 4)
    priors : sequence of (Action, Motion), optional

    Returns
    -------
    numpy.ndarray, shape (n, 3)
        The predicted motions, read-only.

    Raises
    ------
    TypeError
        If ``predictor`` does not implement :class:`Predictor`.
    ValueError
        If it returns other than one finite motion per action, or a motion
        no push can cause (:func:`check_plausible_motions`: ``|theta|`` over
        pi, a translation over ten times the push's length), naming it.
    """
    predictor = check_predictor(predictor)
    acts = check_actions(actions)
    out = predictor.predict(mask, acts, priors)
    who = type(predictor).__name__
    try:
        motions = check_motions(out, n=acts.shape[0], name=f"{who}.predict output")
    except (TypeError, ValueError) as e:
        raise ValueError(f"predictor returned invalid motions: {e}") from e
    check_plausible_motions(motions, acts, who)
    return motions
