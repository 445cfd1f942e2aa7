"""The analytic ellipsoidal limit-surface motion model: :class:`EllipsoidPredictor`.

numpy/scipy only. The physics lives in :mod:`predictors.ellipsoid._model`,
the fit to prior pushes in :mod:`predictors.ellipsoid._fit`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from comcore.checks import check_actions, check_mask, check_points, check_priors
from comcore.geometry import outline_field
from comcore.motion import check_plausible_motions

from ._fit import MU_GRID, EllipsoidFit, fit_priors
from ._model import simulate
from ._support import characteristic_length_sq

__all__ = ["DEFAULT_MU_CONTACT", "MU_GRID", "EllipsoidFit", "EllipsoidPredictor"]

#: Contact friction assumed when none is given and there are no priors to fit it.
DEFAULT_MU_CONTACT = 0.5
#: Pressure distributions of the support that the model knows.
PRESSURES = ("uniform", "linear", "tilted")
#: Where the ellipsoid matches the true limit surface (see ``characteristic_length_sq``).
LIMIT_SURFACES = ("rotation", "translation", "directional")


def _check_com(com):
    if com is None:
        return None
    pts = check_points(com, "com")
    if pts.shape[0] != 1:
        raise ValueError(f"com must be a single point (x, y) in pixels, got shape {np.shape(com)}")
    return (float(pts[0, 0]), float(pts[0, 1]))


def _check_mu_value(mu, name="mu_contact"):
    if mu is None:
        return None
    if isinstance(mu, bool) or not isinstance(mu, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a number >= 0 or None, got {type(mu).__name__}")
    mu = float(mu)
    if math.isnan(mu) or mu < 0:
        raise ValueError(f"{name} must be a number >= 0 (inf allowed), got {mu}")
    return mu


@dataclass(frozen=True)
class EllipsoidPredictor:
    """Quasi-static pushing with the ellipsoidal limit surface (Lynch et al. 1992).

    Given a CoM hypothesis and the contact friction it predicts directly.
    Without a CoM it first fits one (with ``mu_contact`` too, unless given) to
    the prior pushes, which makes it a few-shot predictor and, through
    :meth:`fit`, a CoM estimator in its own right.

    Parameters
    ----------
    com : (float, float) or None, optional
        CoM ``(x, y)`` in pixels of the mask's frame; ``None`` fits it to the priors.
    mu_contact : float or None, optional
        Pusher-object friction (``inf``: the contact never slides); ``None``
        fits it to the priors, or uses ``DEFAULT_MU_CONTACT`` when there are none.
    pressure : {"tilted", "uniform", "linear"}, optional
        Pressure of the support on the floor. The default ``"tilted"`` is the
        distribution closest to uniform whose centre of pressure is the CoM
        (as it must be); ``"uniform"`` ignores that.
    limit_surface : {"translation", "rotation", "directional"}, optional
        Where the ellipsoid matches the true limit surface: its curvature at
        pure translation (default: pushes mostly translate), its pure-rotation
        pole (the classic ``c = m_max / f_max``), or its curvature along the
        push direction. See
        :func:`predictors.ellipsoid._support.characteristic_length_sq` and
        ``docs/results/motion.md`` for the measurements behind the defaults.
    pusher_radius : float, optional
        Radius of the round pusher in metres (0: a point). As in
        :mod:`simulators`, an action is the path of the disc's leading point
        (the point farthest along the push); its centre runs ``pusher_radius``
        behind it, so a push along the normal of a flat edge is unchanged.
    n_steps : int, optional
        Integration steps over the push after first contact (default 24).

    Examples
    --------
    A 20 x 30 px plate pushed to the right through its CoM (pure translation),
    then 5 px above it (clockwise on screen, drifting down):

    >>> import numpy as np, comcore
    >>> from predictors import EllipsoidPredictor
    >>> mask = comcore.Mask(np.pad(np.ones((20, 30), bool), 10))
    >>> p = EllipsoidPredictor(com=mask.centroid, mu_contact=0.3)
    >>> p.predict(mask, [(0, 19.5, 24, 19.5), (0, 14.5, 24, 14.5)]).round(2)
    array([[ 0.  , 14.5 ,  0.  ],
           [-0.34, 11.97,  4.72]])
    >>> EllipsoidPredictor().predict(mask, [(0, 19.5, 24, 19.5)])
    Traceback (most recent call last):
    ...
    ValueError: EllipsoidPredictor needs a CoM: give com=(x, y) or at least one prior push to fit it
    """

    com: tuple[float, float] | None = None
    mu_contact: float | None = None
    pressure: str = "tilted"
    limit_surface: str = "translation"
    pusher_radius: float = 0.0
    n_steps: int = 24

    def __post_init__(self):
        object.__setattr__(self, "com", _check_com(self.com))
        object.__setattr__(self, "mu_contact", _check_mu_value(self.mu_contact))
        if self.pressure not in PRESSURES:
            raise ValueError(f"pressure must be one of {PRESSURES}, got {self.pressure!r}")
        if self.limit_surface not in LIMIT_SURFACES:
            raise ValueError(
                f"limit_surface must be one of {LIMIT_SURFACES}, got {self.limit_surface!r}"
            )
        radius = _check_mu_value(self.pusher_radius, "pusher_radius")
        if radius is None or math.isinf(radius):
            raise ValueError(f"pusher_radius must be a finite number >= 0, got {radius}")
        object.__setattr__(self, "pusher_radius", radius)
        n = self.n_steps
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ValueError(f"n_steps must be a positive integer, got {n!r}")
        object.__setattr__(self, "n_steps", int(n))

    def _radius_px(self, mask) -> float:
        return self.pusher_radius / mask.resolution

    def predict_hypotheses(self, mask, actions, coms, mu) -> np.ndarray:
        """Motions of each action for each CoM hypothesis (:class:`comcore.Predictor`).

        Parameters
        ----------
        mask : comcore.Mask
        actions : array_like, shape (n_actions, 4)
        coms : array_like, shape (n_coms, 2)
            CoM hypotheses in pixels.
        mu : float
            Contact friction (``inf`` allowed).

        Returns
        -------
        numpy.ndarray, shape (n_coms, n_actions, 3)
            ``(theta, tx, ty)`` per hypothesis and action; pushes that miss give zeros.

        Raises
        ------
        ValueError
            If an action starts inside the object, or ``mu`` is negative; or
            if a prediction is physically impossible (``|theta|`` over pi, a
            translation over ten times the push's length: a broken input such
            as a unit mistake, see :func:`comcore.motion.check_plausible_motions`).

        Examples
        --------
        A push to the right along row 19.5 turns the plate counter-clockwise if
        the CoM is above the line (smaller row), clockwise if below:

        >>> import numpy as np, comcore
        >>> from predictors import EllipsoidPredictor
        >>> mask = comcore.Mask(np.pad(np.ones((20, 30), bool), 10))
        >>> out = EllipsoidPredictor().predict_hypotheses(
        ...     mask, [(0, 19.5, 24, 19.5)], [(24.5, 15.0), (24.5, 24.0)], mu=0.5)
        >>> out.shape, comcore.conventions.rotation_sense(out[:, 0, 0]).tolist()
        ((2, 1, 3), [1, -1])
        """
        mask = check_mask(mask)
        acts = check_actions(actions)
        pts = check_points(coms, "coms")
        mu = _check_mu_value(mu, "mu")
        if mu is None:
            raise TypeError("mu must be a number >= 0, got None")
        if len(acts) == 0 or len(pts) == 0:
            return np.zeros((len(pts), len(acts), 3))
        c2 = characteristic_length_sq(mask, pts, self.pressure, self.limit_surface)
        mus = np.full(len(pts), mu)
        radius = self._radius_px(mask)
        out = simulate(
            mask, outline_field(mask), acts, pts, c2, mus, radius=radius, n_steps=self.n_steps
        )
        return check_plausible_motions(out, acts, "EllipsoidPredictor")

    def fit(self, mask, priors) -> EllipsoidFit:
        """Fit the CoM (unless given) and the contact friction (unless given) to priors.

        Parameters
        ----------
        mask : comcore.Mask
        priors : sequence of (Action, Motion)
            Pushes observed on this mask, at least one.

        Returns
        -------
        EllipsoidFit

        Raises
        ------
        ValueError
            If there are no priors, or a prior starts inside the object.

        Examples
        --------
        >>> import numpy as np, comcore
        >>> from predictors import EllipsoidPredictor
        >>> mask = comcore.Mask(np.pad(np.ones((20, 30), bool), 10))
        >>> truth = EllipsoidPredictor(com=(20.0, 22.0), mu_contact=0.3)
        >>> acts = comcore.sample_pushes(mask, 12, cone=0.4, rng=0)
        >>> priors = list(zip(acts, truth.predict(mask, acts)))
        >>> fit = EllipsoidPredictor().fit(mask, priors)
        >>> np.round(fit.com), fit.mu_contact
        (array([20., 22.]), 0.3)
        """
        mask = check_mask(mask)
        acts, mots = check_priors(priors)
        if len(acts) == 0:
            raise ValueError("priors must hold at least one (Action, Motion) pair to fit to")
        return fit_priors(
            mask,
            acts,
            mots,
            com=self.com,
            mu=self.mu_contact,
            support=(self.pressure, self.limit_surface),
            radius=self._radius_px(mask),
            n_steps=self.n_steps,
        )

    def predict(self, mask, actions, priors=()) -> np.ndarray:
        """Predict motions ``(theta, tx, ty)``, shape (n, 3) (:class:`comcore.Predictor`).

        With ``com=None`` the CoM (and ``mu_contact`` if ``None``) is first
        fitted to ``priors``; with a CoM but no ``mu_contact``, ``mu`` is fitted
        to the priors if there are any, else ``DEFAULT_MU_CONTACT`` is used.
        """
        mask = check_mask(mask)
        acts = check_actions(actions)
        pri_acts, _ = check_priors(priors)
        com, mu = self.com, self.mu_contact
        if com is None and len(pri_acts) == 0:
            raise ValueError(
                "EllipsoidPredictor needs a CoM: give com=(x, y) or at least one prior push "
                "to fit it"
            )
        if com is None or (mu is None and len(pri_acts) > 0):
            fit = self.fit(mask, priors)
            com, mu = fit.com, fit.mu_contact
        if mu is None:
            mu = DEFAULT_MU_CONTACT
        return self.predict_hypotheses(mask, acts, [com], mu)[0]
