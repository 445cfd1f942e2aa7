"""The oracle: answers with the simulator of the true object (needs ``comcore[sim]``)."""

from __future__ import annotations

import numpy as np

import comcore

__all__ = ["OraclePredictor"]


class OraclePredictor:
    """A :class:`comcore.Predictor` that runs the simulator on the true object.

    The upper bound every learned or analytic predictor is measured against: it
    knows the true mass distribution and contact friction. It only answers for
    its own object, so the mask it is asked about must be the simulator's
    (same shape, resolution and pixels); priors are ignored.

    It is also a :class:`comcore.HypothesisPredictor`: for a CoM hypothesis it
    tilts the true mass distribution to put the CoM there (see
    :meth:`simulators.PushSimulator.with_com`).

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
        mask = comcore.check_mask(mask)
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
        comcore.check_priors(priors)
        return self.simulator.push_motions(comcore.check_actions(actions))

    def predict_hypotheses(self, mask, actions, coms, mu) -> np.ndarray:
        """Motions if the CoM were at each of ``coms`` (pixels) and friction ``mu``.

        Returns
        -------
        numpy.ndarray, shape (n_coms, n_actions, 3)
        """
        self._check_mask(mask)
        acts = comcore.check_actions(actions)
        points = comcore.check_points(coms, "coms")
        lo, hi = comcore.check_mu(mu)
        if lo != hi:
            raise ValueError(f"mu must be a single number, got {mu!r}")
        sim = self.simulator
        out = np.zeros((len(points), len(acts), 3))
        for i, com_m in enumerate(sim.to_world(points)):
            out[i] = sim.with_com(com_m, mu_contact=lo).push_motions(acts)
        return out

    def __repr__(self) -> str:
        return f"OraclePredictor({self.simulator!r})"
