"""The oracle: answers with the simulator of the true object (needs ``comcore[sim]``)."""

from __future__ import annotations

import numpy as np

import comcore
from comcore.motion import check_plausible_motions

__all__ = ["OraclePredictor"]

#: A CoM hypothesis is kept this fraction (of the way from the support's mean) inside
#: the hull of the support points, where tilting the mass can still reach it.
HULL_SHRINK = 0.01
#: Hypotheses closer than this fraction to the hull count as on it (unreachable).
ON_HULL = 1e-6


class OraclePredictor:
    """A :class:`comcore.Predictor` that runs the simulator on the true object.

    The upper bound every learned or analytic predictor is measured against: it
    knows the true mass distribution and contact friction. It only answers for
    its own object, so the mask it is asked about must be the simulator's
    (same shape, resolution and pixels); priors are ignored.

    It is also a :class:`comcore.Predictor`: for a CoM hypothesis it
    tilts the true mass distribution to put the CoM there (see
    :meth:`simulators.PushSimulator.with_com`). A hypothesis that no tilt can
    reach (on an outline pixel or near one: outside the hull of the support
    points, which lie half a support cell inside the outline) is answered for
    the CoM where the line from the support points' mean to it enters the hull,
    moved 1 % of that way farther in.

    Parameters
    ----------
    simulator : simulators.PushSimulator

    Examples
    --------
    >>> import comcore, simulators
    >>> from predictors import OraclePredictor
    >>> sim = simulators.random_simulator("Obj1", rng=0)
    >>> oracle = OraclePredictor(sim)
    >>> isinstance(oracle, comcore.Predictor)
    True
    >>> actions = comcore.sample_pushes(sim.mask, 2, rng=0)
    >>> bool((oracle.predict(sim.mask, actions) == sim.push_motions(actions)).all())
    True
    """

    def __init__(self, simulator):
        from simulators import PushSimulator

        if not isinstance(simulator, PushSimulator):
            raise TypeError(
                f"simulator must be a simulators.PushSimulator, got {type(simulator).__name__}"
            )
        self.simulator = simulator

    def _check_mask(self, mask) -> None:
        mask = comcore.checks.check_mask(mask)
        own = self.simulator.mask
        if (
            mask.shape != own.shape
            or mask.resolution != own.resolution
            or not np.array_equal(mask.data, own.data)
        ):
            raise ValueError(
                "mask must be the simulator's own mask (the oracle knows only its object): "
                f"got {mask!r}, expected {own!r}"
            )

    def predict(self, mask, actions, priors=()) -> np.ndarray:
        """Motions ``(theta, tx, ty)`` of the actions on the true object, shape (n, 3)."""
        self._check_mask(mask)
        comcore.checks.check_priors(priors)
        acts = comcore.checks.check_actions(actions)
        return check_plausible_motions(self.simulator.push_motions(acts), acts, repr(self))

    def predict_hypotheses(self, mask, actions, coms, mu) -> np.ndarray:
        """Motions if the CoM were at each of ``coms`` (pixels) and friction ``mu``.

        Returns
        -------
        numpy.ndarray, shape (n_coms, n_actions, 3)
        """
        self._check_mask(mask)
        acts = comcore.checks.check_actions(actions)
        points = comcore.checks.check_points(coms, "coms")
        lo, hi = comcore.checks.check_mu(mu)
        if lo != hi:
            raise ValueError(f"mu must be a single number, got {mu!r}")
        sim = self.simulator
        out = np.zeros((len(points), len(acts), 3))
        for i, com_m in enumerate(self._reachable(sim.to_world(points))):
            out[i] = sim.with_com(com_m, mu_contact=lo).push_motions(acts)
        return check_plausible_motions(out, acts, repr(self))

    def _reachable(self, coms_m: np.ndarray) -> np.ndarray:
        """Hypotheses (world metres) moved inside the support's hull where they lie outside it.

        Tilting the mass puts the CoM anywhere strictly inside the convex hull of the
        support points (cell centres, half a cell inside the outline), not on an outline
        pixel. A hypothesis outside the hull (or within ``ON_HULL`` of it, as a fraction
        of the way from the points' mean) slides towards that mean until it is
        ``HULL_SHRINK`` inside; the others are unchanged.
        """
        from scipy.spatial import ConvexHull

        points = self.simulator.mass.points_m
        centre = points.mean(axis=0)
        eq = ConvexHull(points).equations  # a . x + b <= 0 inside
        slack = -(eq[:, :2] @ centre + eq[:, 2])  # > 0: the centre's distance to each facet
        out = np.array(coms_m, dtype=float)
        towards = (out - centre) @ eq[:, :2].T  # (k, facets)
        with np.errstate(divide="ignore", invalid="ignore"):
            limit = np.where(towards > 0, (1.0 - HULL_SHRINK) * slack / towards, np.inf)
        # outside the hull (to within rounding): no tilt reaches it
        move = limit.min(axis=1) * (1.0 - ON_HULL) / (1.0 - HULL_SHRINK) < 1.0
        scale = limit[move].min(axis=1)
        out[move] = centre + scale[:, None] * (out[move] - centre)
        return out

    def __repr__(self) -> str:
        return f"OraclePredictor({self.simulator!r})"
