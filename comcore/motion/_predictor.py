"""The :class:`Predictor` protocol and the checks on what a model returns.

A motion model plugs into every estimator through one method,
``predict_hypotheses(mask, actions, coms, mu)`` (:class:`Predictor`); the paper's
few-shot form ``predict(mask, actions, priors=())`` is a default method built on it.
What a model returns is checked where it enters an estimator
(:func:`check_model_output`): its shape, NaN and inf, and a turn no push of that
length can cause (theta in degrees, corrupt weights).
"""

from __future__ import annotations

import abc
import math
from functools import partial

import numpy as np

from .._mask import Mask
from .._types import readonly
from .._validation import check_actions, check_mask, check_priors

__all__ = [
    "MAX_PUSH_THETA",
    "MAX_TRANSLATION_PER_PUSH_LENGTH",
    "MAX_TURN_PER_LENGTH",
    "Predictor",
    "check_model_output",
    "check_plausible_motions",
    "check_predictor",
    "predict_motions",
    "turn_bounds",
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


#: The largest turn (radians) a model may predict for a push, as a multiple of the push's
#: length over the object's size: ``MAX_TURN_PER_LENGTH * L / rho`` for a push of length ``L``
#: (pixels, its whole path, approach included) on a mask whose radius of gyration about its
#: centroid is ``rho`` (pixels).
MAX_TURN_PER_LENGTH = 10.0
# Why a bound of this form. In a quasi-static push the pusher moves the contact by at most
# L along the push. On a limit surface whose pressure has radius of gyration c about the CoM,
# a force line at distance d from the CoM turns the object about a centre of rotation c^2 / d
# beyond the CoM, so the contact is at least d + c^2 / d >= 2 c from it and the object turns
# by at most L / (2 c). The pressure's c is not the footprint's rho: the pressure consistent
# with a CoM near the outline crowds there, and a CoM on the outline (any friction, pushes of
# 0.5 to 10 cm) turns comcore's LimitSurfaceModel by up to 3.7 L / rho on the 20 benchmark
# objects, EllipsoidPredictor by 3.1 L / rho and the simulator by 1.8 L / rho. A factor of 10
# keeps 2.7 times that margin (tests/motion/test_model_output.py checks the shipped models),
# and a model whose turns are in degrees (57 times its radians) still overshoots it: over
# every CoM hypothesis, the outline's included, a push turns the object by a good part of
# L / rho, 57 times which is beyond 10 L / rho.

_COMPONENTS = ("theta", "tx", "ty")


def turn_bounds(actions, mask: Mask) -> np.ndarray:
    """The largest turn (radians) each push may cause: :data:`MAX_TURN_PER_LENGTH` ``L / rho``.

    Parameters
    ----------
    actions : array_like, shape (n, 4)
        Pushes in pixels; ``L`` is each one's length.
    mask : Mask
        The object; ``rho`` is its radius of gyration about its centroid
        (pixels, at least half a pixel).

    Returns
    -------
    numpy.ndarray, shape (n,)

    Examples
    --------
    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> turn_bounds([(0, 13, 30, 13)], mask).round(2).tolist()
    [36.79]
    """
    acts = check_actions(actions)
    length = np.hypot(acts[:, 2] - acts[:, 0], acts[:, 3] - acts[:, 1])
    return MAX_TURN_PER_LENGTH * length / _gyration_px(mask)


def _gyration_px(mask: Mask) -> float:
    """The mask's radius of gyration about its centroid (pixels, at least 0.5)."""
    offsets = mask.pixels - np.asarray(mask.centroid)
    return max(float(np.sqrt((offsets**2).sum(axis=1).mean())), 0.5)


def check_model_output(model, output, actions, coms, mu, mask: Mask, *, method=None):
    """What a motion model returned, checked where it enters an estimator; as an array.

    Refused with a ValueError that names the model's class and method: a shape
    other than one motion per CoM hypothesis and push; NaN or inf (naming it,
    the hypothesis' CoM and friction, and the push); a turn beyond what a push
    of that length can cause (:func:`turn_bounds`), said to be theta in degrees
    where every turn divided by 180 / pi would be possible (over CoM
    hypotheses, for those on the object). A model that is merely wrong (a
    flipped sign) passes: the estimator finds that its predictions and the
    observed motions disagree.

    Parameters
    ----------
    model : object
        The model (named in the message by its class).
    output : array_like, shape (n_coms, n_actions, 3), or (n_actions, 3) without ``coms``
        What it returned: ``(theta, tx, ty)``, radians counter-clockwise on
        screen and pixels.
    actions : array_like, shape (n_actions, 4)
        The pushes it was asked about (pixels).
    coms : array_like, shape (n_coms, 2), or None
        The CoM hypotheses it was asked about (pixels); None for a few-shot
        ``predict`` (one motion per push).
    mu : float, array_like of shape (n_coms,), or None
        The contact friction of each hypothesis (for the message).
    mask : Mask
        The object the pushes were asked about.
    method : str, optional
        The method that returned ``output`` (default ``"predict_hypotheses"``,
        or ``"predict"`` without ``coms``).

    Returns
    -------
    numpy.ndarray of float, the shape of ``output``

    Raises
    ------
    ValueError
        As above.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> class Mine: pass
    >>> check_model_output(Mine(), [[[0.2, 9.0, 0.0]]], [(0, 13, 30, 13)], [(14, 14)], 0.3, mask)
    array([[[0.2, 9. , 0. ]]])
    >>> check_model_output(Mine(), [[[45.0, 9.0, 0.0]]], [(0, 8, 30, 8)], [(14, 14)], 0.3, mask)
    Traceback (most recent call last):
    ...
    ValueError: Mine.predict_hypotheses turns the object by up to 45 rad, more than a push of that length can (push 0, 30 px long, turns an object of radius of gyration 8.15 px by at most 36.8 rad); every turn times pi/180 would be possible: theta in degrees? multiply by pi/180
    """  # noqa: E501
    acts = check_actions(actions)
    method = method or ("predict" if coms is None else "predict_hypotheses")
    who = f"{type(model).__name__}.{method}"
    pts = None if coms is None else np.asarray(coms, dtype=float).reshape(-1, 2)
    expected = (len(acts), 3) if pts is None else (len(pts), len(acts), 3)
    try:
        out = np.asarray(output, dtype=float)
    except (TypeError, ValueError) as e:
        raise ValueError(
            f"{who} must return numbers (theta, tx, ty), got {type(output).__name__}: {e}"
        ) from e
    if out.shape != expected:
        what = "(n_actions, 3)" if pts is None else "(n_coms, n_actions, 3)"
        raise ValueError(
            f"{who} returned motions of shape {out.shape}, expected {what} = {expected}: one "
            "(theta, tx, ty) per " + ("push" if pts is None else "CoM hypothesis and push")
        )
    _refuse_not_finite(who, out, pts, mu)
    if pts is None:
        _refuse_impossible(who, out, acts, mask, pts)
        return out
    # The bounds hold for a CoM on the object; the estimators also ask about CoMs a pusher's
    # error away from it (the offset's marginal), where a model may answer anything finite.
    # Over CoM hypotheses the turn is bounded, not the displacement: a hypothesis next to the
    # contact may be answered with a wild translation (the limit-surface model's integration
    # does so for a few), which the likelihood then scores as it deserves.
    on = mask.contains(pts)
    _refuse_impossible(who, out[on], acts, mask, pts[on], displacement=False)
    return out


def _hypothesis(where: tuple, pts, mu) -> str:
    """`` for the CoM (x, y) px and mu = m`` of an index into a model's output."""
    if pts is None:
        return ""
    h = int(where[0])
    mu_h = mu if mu is None or np.ndim(mu) == 0 else np.asarray(mu).reshape(-1)[h]
    friction = "" if mu_h is None else f" and mu = {float(mu_h):.3g}"
    return f" for the CoM hypothesis ({pts[h, 0]:.1f}, {pts[h, 1]:.1f}) px{friction}"


def _refuse_not_finite(who: str, out: np.ndarray, pts, mu) -> None:
    """A ValueError naming the first NaN or inf of ``out`` (which value, push, hypothesis)."""
    bad = ~np.isfinite(out)
    if not bad.any():
        return
    where = tuple(int(i) for i in np.argwhere(bad)[0])
    value = float(out[where])
    kind = "NaN" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    raise ValueError(
        f"{who} returned {kind} as the {_COMPONENTS[where[-1]]} of push {where[-2]}"
        f"{_hypothesis(where, pts, mu)} ({int(bad.sum())} of {out.size} values are not "
        "finite): a motion model must return finite motions"
    )


def _refuse_impossible(
    who: str, out: np.ndarray, acts: np.ndarray, mask: Mask, pts, *, displacement: bool = True
) -> None:
    """A ValueError for a turn or a displacement no push of that length can cause.

    The displacement is the area centroid's: the CoM's own (at most
    :data:`MAX_TRANSLATION_PER_PUSH_LENGTH` push lengths) plus the turn's swing of the
    centroid about the CoM, at most twice their distance (a half turn's chord); without
    CoM hypotheses (``pts`` None), twice the object's largest distance from its centroid.
    """
    if out.size == 0:
        return
    length = np.hypot(acts[:, 2] - acts[:, 0], acts[:, 3] - acts[:, 1])
    rho = _gyration_px(mask)
    bound = MAX_TURN_PER_LENGTH * length / rho
    theta = np.abs(out[..., 0])
    if (theta > bound).any():
        where = np.unravel_index(np.argmax(theta / np.maximum(bound, 1e-300)), theta.shape)
        i = int(where[-1])
        limit = (
            f"push {i}, {length[i]:.3g} px long, turns an object of radius of gyration "
            f"{rho:.3g} px by at most {bound[i]:.3g} rad"
        )
        if (theta * (math.pi / 180) <= bound).all():
            raise ValueError(
                f"{who} turns the object by up to {theta.max():.3g} rad, more than a push of "
                f"that length can ({limit}); every turn times pi/180 would be possible: theta "
                "in degrees? multiply by pi/180"
            )
        raise ValueError(
            f"{who} predicted a turn no push can cause: {float(out[where][0]):.3g} rad ({limit}); "
            "the model is broken (corrupt weights, a unit mistake?), not the object"
        )
    if not displacement:
        return
    shift = np.hypot(out[..., 1], out[..., 2])
    centroid = np.asarray(mask.centroid)
    if pts is None:
        swing = 2.0 * float(np.sqrt(((mask.pixels - centroid) ** 2).sum(axis=1).max()))
    else:
        swing = 2.0 * np.hypot(*(pts - centroid).T)[:, None]  # (n_coms, 1)
    carried = shift > MAX_TRANSLATION_PER_PUSH_LENGTH * length + swing
    if carried.any():
        where = tuple(np.argwhere(carried)[0])
        i = int(where[-1])
        raise ValueError(
            f"{who} predicted a motion no push can cause: push {i} ({length[i]:.3g} px long) "
            f"moves the object by {shift[where]:.3g} px, more than "
            f"{MAX_TRANSLATION_PER_PUSH_LENGTH:g} times the push's length and the turn's swing "
            "of the centroid about the CoM; the model is "
            "broken (corrupt weights, a unit mistake?), not the object"
        )


#: The fit behind the default few-shot :meth:`Predictor.predict`: ``fit(model, mask,
#: actions, motions) -> (com, mu)``. The posterior it needs lives a layer above the motion
#: models, which never import it: :mod:`comcore.active` registers its fit here
#: (:func:`register_few_shot_fit`) when it is imported, as ``import comcore`` does.
_FEW_SHOT_FIT = None


def register_few_shot_fit(fit) -> None:
    """Set the fit the default :meth:`Predictor.predict` uses (``comcore.active`` calls this)."""
    global _FEW_SHOT_FIT
    _FEW_SHOT_FIT = fit


class Predictor(abc.ABC):
    """A motion model that plugs into every estimator: one method, ``predict_hypotheses``.

    ``predict_hypotheses(mask, actions, coms, mu)`` returns an array of shape
    ``(n_coms, n_actions, 3)``: the motion ``(theta, tx, ty)`` of each push in
    ``actions`` (pixels of ``mask``, shape (n_actions, 4)) if the CoM were at each
    of ``coms`` (pixels, shape (n_coms, 2)) and the contact friction were ``mu``.
    ``theta`` is the turn in radians, counter-clockwise on screen; ``(tx, ty)``
    is the displacement in pixels (x = column, y = row, down) of the material
    point under the mask's area centroid (:mod:`comcore.conventions`).
    ``ActiveSession``, ``estimate_posterior``, ``estimate_active`` and
    ``GoalSession`` take it as ``model=``; what it returns is checked
    (:func:`check_model_output`).

    Any object with that method is a ``Predictor`` (``isinstance`` says so);
    a subclass also inherits the paper's few-shot form :meth:`predict`, so
    Alg. 1 and 2 (:func:`predict_motions`) take it too.

    How often it is called: :func:`comcore.estimate_posterior` asks once per friction
    value, all pushes in one call (in chunks on large masks); a session once per push
    and friction value. An optional ``predict_frictions(mask, actions, coms, mus)``
    returning ``(n_mus, n_coms, n_actions, 3)`` is asked once for every friction value
    instead (docs/how-to/your-predictor.md, "How often your model is called").

    Examples
    --------
    A quasi-static lever arm: the object turns more the farther the push's
    line passes from the CoM, and its CoM moves along the push.

    >>> import numpy as np, comcore
    >>> class LeverArm(comcore.Predictor):
    ...     def predict_hypotheses(self, mask, actions, coms, mu):
    ...         acts = comcore.checks.check_actions(actions)  # (n_actions, 4) pixels
    ...         coms = np.asarray(coms, dtype=float).reshape(-1, 2)  # (n_coms, 2) pixels
    ...         push = acts[:, 2:] - acts[:, :2]
    ...         unit = push / np.hypot(*push.T)[:, None]
    ...         travel = np.hypot(*(acts[:, 2:] - comcore.geometry.contacts(mask, acts).point).T)
    ...         lever = comcore.geometry.signed_line_distance(coms, acts)  # > 0: CoM on the left
    ...         offset = (np.asarray(mask.centroid) - coms)[:, None]  # centroid from each CoM
    ...         spread = 0.5 * (((mask.pixels - mask.centroid) ** 2).sum(1).mean()
    ...                         + (offset**2).sum(-1))  # the pressure's spread about the CoM
    ...         theta = travel * lever / (spread + lever**2)  # CCW when the CoM is on the left
    ...         along = travel * spread / (spread + lever**2)  # the CoM's travel along the push
    ...         turned = comcore.conventions.rotate_vectors(offset, theta) - offset
    ...         moved = along[..., None] * unit + turned  # the centroid's displacement
    ...         return np.concatenate([theta[..., None], moved], axis=-1)
    >>> mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    >>> LeverArm().predict_hypotheses(mask, [(0, 9, 10, 9)], [(13.5, 13.5)], 0.3).round(2)
    array([[[-0.55,  4.04,  0.  ]]])
    >>> isinstance(LeverArm(), comcore.Predictor), isinstance(object(), comcore.Predictor)
    (True, False)
    """

    @classmethod
    def __subclasshook__(cls, other):
        """Any class with a ``predict_hypotheses`` method is a Predictor."""
        if cls is Predictor:
            if any(callable(vars(k).get("predict_hypotheses")) for k in other.__mro__):
                return True
        return NotImplemented

    @abc.abstractmethod
    def predict_hypotheses(self, mask: Mask, actions, coms, mu: float):
        """Motions ``(theta, tx, ty)`` of each action for each CoM, shape (n_coms, n_actions, 3)."""

    def predict(self, mask: Mask, actions, priors=()) -> np.ndarray:
        """The paper's few-shot form: motions of ``actions`` after the prior pushes, (n, 3).

        Fits the CoM and the contact friction to ``priors`` (``(Action, Motion)``
        pairs observed on ``mask``, theta in radians) with
        :func:`comcore.estimate_posterior` under this model, and predicts at
        the estimate (the CoM's posterior mean, the most probable friction).
        Without priors it predicts at the mask's area centroid with the
        middle of the default friction range.
        """
        if _FEW_SHOT_FIT is None:  # pragma: no cover - comcore imports comcore.active
            raise RuntimeError("Predictor.predict needs comcore.active: import comcore first")
        acts = check_actions(actions)
        prior_actions, prior_motions = check_priors(priors)
        com, mu = _FEW_SHOT_FIT(self, mask, prior_actions, prior_motions)
        out = self.predict_hypotheses(mask, acts, [com], mu)
        return check_model_output(self, out, acts, [com], mu, mask)[0]


def check_predictor(model, name: str = "model"):
    """``model`` if it implements :class:`Predictor` (``predict_hypotheses``), else a TypeError.

    A few-shot model with only ``predict(mask, actions, priors)`` (such as
    ``predictors.AnpPredictor``) is told why it cannot score CoM hypotheses.

    Examples
    --------
    >>> class FewShot:
    ...     def predict(self, mask, actions, priors=()): ...
    >>> check_predictor(FewShot())
    Traceback (most recent call last):
    ...
    TypeError: model must implement comcore.Predictor (a predict_hypotheses(mask, actions, coms, mu) method), got FewShot: it has only the few-shot predict(mask, actions, priors), and this estimator scores CoM hypotheses, asking how each push would move the object if the CoM were at each of many points; use it through comcore.motion.predict_motions (Alg. 1 and 2), or give it a CoM input
    """  # noqa: E501
    if callable(getattr(model, "predict_hypotheses", None)):
        return model
    why = ""
    if callable(getattr(model, "predict", None)):
        why = (
            ": it has only the few-shot predict(mask, actions, priors), and this estimator "
            "scores CoM hypotheses, asking how each push would move the object if the CoM "
            "were at each of many points; use it through comcore.motion.predict_motions "
            "(Alg. 1 and 2), or give it a CoM input"
        )
    raise TypeError(
        f"{name} must implement comcore.Predictor (a predict_hypotheses(mask, actions, coms, mu) "
        f"method), got {type(model).__name__}{why}"
    )


def predict_motions(predictor, mask: Mask, actions, priors=()) -> np.ndarray:
    """Call a predictor's few-shot ``predict`` and check what it returns.

    Every :class:`Predictor` has one (a structural one gets
    :meth:`Predictor.predict`); a purely few-shot model (``predictors.AnpPredictor``)
    needs only ``predict(mask, actions, priors=())``.

    Parameters
    ----------
    predictor : Predictor, or an object with ``predict(mask, actions, priors=())``
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
        If ``predictor`` has neither method, naming :class:`Predictor`.
    ValueError
        If it returns other than one finite motion per action, or a motion no
        push of that length can cause (:func:`check_model_output`), naming it.
    """
    predict = getattr(predictor, "predict", None)
    if not callable(predict):
        if not callable(getattr(predictor, "predict_hypotheses", None)):
            raise TypeError(
                "predictor must implement comcore.Predictor (a predict_hypotheses(mask, actions, "
                "coms, mu) method) or have a few-shot predict(mask, actions, priors=()) method, "
                f"got {type(predictor).__name__}"
            )
        predict = partial(Predictor.predict, predictor)
    mask = check_mask(mask)
    acts = check_actions(actions)
    out = predict(mask, acts, priors)
    motions = check_model_output(predictor, out, acts, None, None, mask, method="predict")
    return readonly(motions)
