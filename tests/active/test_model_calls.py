"""How often estimate_posterior asks the motion model (comcore.active._motion_term).

Never twice for the same push and friction value (the theta-units check reads the first
posterior's predictions), all pushes in one call per friction value, and every friction value
in one call for a model with ``predict_frictions``.
"""

from __future__ import annotations

import numpy as np
import pytest

import comcore
from comcore.active._motion_term import model_predictions
from tests.active.test_blocking import ToyModel

MASK = comcore.Mask(np.pad(np.ones((24, 30), bool), 8))
TRUE_COM = (20.0, 22.0)


class Counted(ToyModel):
    """The toy model, counting its calls (a plain model: no hook)."""

    def __init__(self):
        super().__init__()
        self.calls = []

    def predict_hypotheses(self, mask, actions, coms, mu):
        self.calls.append((len(actions), len(coms), mu))
        return super().predict_hypotheses(mask, actions, coms, mu)


class Batched(Counted):
    """The toy model with the friction hook: every friction value in one call."""

    def __init__(self):
        super().__init__()
        self.friction_calls = []

    def predict_frictions(self, mask, actions, coms, mus):
        self.friction_calls.append((len(actions), len(coms), len(mus)))
        return np.stack([ToyModel.predict_hypotheses(self, mask, actions, coms, m) for m in mus])


@pytest.fixture(scope="module")
def pushes():
    actions = comcore.sample_pushes(MASK, 8, cone=0.4, travel=0.01, rng=3)
    motions = ToyModel().predict_hypotheses(MASK, actions, [TRUE_COM], 0.5)[0]
    return actions, motions


@pytest.mark.parametrize("theta_units", ["auto", "rad"])
def test_a_plain_model_is_asked_once_per_friction_value_for_all_pushes(pushes, theta_units):
    model = Counted()
    est = comcore.estimate_posterior(MASK, *pushes, model=model, theta_units=theta_units)
    n_mus = len(comcore.Likelihood().mus)
    assert len(model.calls) <= 8 * n_mus  # at most once per push and friction value
    assert len(model.calls) == n_mus  # here: all 8 pushes in each call
    assert all(n_actions == 8 for n_actions, _, _ in model.calls)
    assert sorted(mu for _, _, mu in model.calls) == sorted(comcore.Likelihood().mus)
    assert est.status in ("ok", "wide") and est.error_px(TRUE_COM) < 3


def test_the_friction_hook_asks_every_friction_value_at_once_with_the_same_numbers(pushes):
    plain, batched = Counted(), Batched()
    want = comcore.estimate_posterior(MASK, *pushes, model=plain)
    got = comcore.estimate_posterior(MASK, *pushes, model=batched)
    assert batched.calls == [] and len(batched.friction_calls) == 1
    assert batched.friction_calls[0][0] == 8 and batched.friction_calls[0][2] == 6
    assert got.com == want.com
    assert got.posterior.log_evidence == want.posterior.log_evidence


def test_the_friction_hook_is_used_by_a_session_too():
    model = Batched()
    session = comcore.ActiveSession(MASK, model=model, rng=0)
    session.observe(motion=(0.1, 3.0, 0.0), executed=session.next_push())
    assert model.calls == [] and len(model.friction_calls) >= 1


def test_a_friction_hook_of_the_wrong_shape_is_refused_by_name():
    class Wrong(Batched):
        def predict_frictions(self, mask, actions, coms, mus):
            return super().predict_frictions(mask, actions, coms, mus)[0]

    alive = np.ones((3, 2, 1), bool)
    with pytest.raises(ValueError, match=r"model.predict_frictions must return finite motions "
                       r"of shape \(2, 3, 1, 3\) \(friction values, CoMs, actions, 3\), "
                       r"got shape \(3, 1, 3\)"):  # fmt: skip
        model_predictions([Wrong()], MASK, np.array([[0.0, 20, 40, 20]]),
                          np.array([[15.0, 20], [20, 20], [25, 20]]), [0.2, 0.6], alive)  # fmt: skip
