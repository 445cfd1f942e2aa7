"""The oracle predictor: the simulator of the true object behind comcore.Predictor."""

import numpy as np
import pytest

pytest.importorskip("shapely")
pytest.importorskip("trimesh")

import comcore
import simulators
from predictors import OraclePredictor


@pytest.fixture(scope="module")
def sim():
    return simulators.random_simulator("Obj11", friction="high", rng=4)


def test_is_a_predictor_and_answers_like_the_simulator(sim):
    oracle = OraclePredictor(sim)
    assert isinstance(oracle, comcore.Predictor)
    assert isinstance(oracle, comcore.Predictor)
    actions = comcore.sample_pushes(sim.mask, 5, cone=0.3, rng=2)
    got = comcore.motion.predict_motions(oracle, sim.mask, actions)
    assert np.array_equal(got, sim.push_motions(actions))
    priors = [(comcore.Action(*actions[0]), comcore.Motion(*got[0]))]
    assert np.array_equal(oracle.predict(sim.mask, actions, priors), got)


def test_refuses_another_mask(sim):
    oracle = OraclePredictor(sim)
    other = comcore.Mask(np.pad(np.ones((10, 10), bool), 5))
    with pytest.raises(ValueError, match="simulator's own mask"):
        oracle.predict(other, [(0, 10, 8, 10)])
    with pytest.raises(TypeError, match="PushSimulator"):
        OraclePredictor("not a simulator")


def test_hypotheses_put_the_com_where_asked(sim):
    oracle = OraclePredictor(sim)
    actions = comcore.sample_pushes(sim.mask, 4, rng=5)
    coms = np.array([sim.com_px, sim.mask.centroid])
    out = oracle.predict_hypotheses(sim.mask, actions, coms, sim.mu_contact)
    assert out.shape == (2, 4, 3)
    assert np.allclose(out[0], sim.push_motions(actions), atol=1e-9)
    with pytest.raises(ValueError, match="single number"):
        oracle.predict_hypotheses(sim.mask, actions, coms, (0.1, 0.3))


def test_oracle_drives_the_progressive_estimator(sim):
    actions = comcore.sample_pushes(sim.mask, 40, rng=6)
    estimate = comcore.estimate_progressive(
        sim.mask, actions, OraclePredictor(sim).predict(sim.mask, actions)
    )
    assert estimate.error_px(sim.com_px) < 6.0


def test_a_hypothesis_on_an_outline_pixel_is_answered(sim):
    # An outline pixel lies outside the hull of the support points: tilting the mass there
    # raised "target ... is not strictly inside the support points" (and estimate_active,
    # whose hypotheses cover every object pixel, crashed with it).
    oracle = OraclePredictor(sim)
    actions = comcore.sample_pushes(sim.mask, 2, rng=5)
    rows, cols = np.nonzero(sim.mask.boundary)
    outline = np.column_stack([cols, rows]).astype(float)[:1]
    out = oracle.predict_hypotheses(sim.mask, actions, outline, sim.mu_contact)
    assert out.shape == (1, 2, 3) and np.isfinite(out).all()
    # answered for the reachable CoM nearest on the way to the support's mean
    reachable = oracle._reachable(sim.to_world(outline))[0]
    assert np.linalg.norm(reachable - sim.to_world(outline)[0]) > 0
    expected = sim.with_com(reachable, mu_contact=sim.mu_contact).push_motions(actions)
    np.testing.assert_array_equal(out[0], expected)


def test_reachable_hypotheses_are_left_where_they_are(sim):
    oracle = OraclePredictor(sim)
    inner = sim.to_world(np.array([sim.com_px, sim.mask.centroid]))
    np.testing.assert_array_equal(oracle._reachable(inner), inner)
