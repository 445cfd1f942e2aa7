import numpy as np
import pytest

import comcore
from tests.extras import require_simulators


class Constant:
    def __init__(self, out):
        self.out = out

    def predict(self, mask, actions, priors=()):
        return self.out


def test_non_predictors_are_rejected_with_the_protocol_name(square_mask):
    with pytest.raises(TypeError, match="must implement comcore.Predictor"):
        comcore.motion.predict_motions(object(), square_mask, [(0, 20, 40, 20)])


def test_invalid_predictions_are_caught(square_mask):
    with pytest.raises(ValueError, match="predictor returned invalid motions"):
        comcore.motion.predict_motions(Constant(np.full((1, 3), np.nan)), square_mask, [(0, 20, 40, 20)])
    with pytest.raises(ValueError, match="expected 1, got 2"):
        comcore.motion.predict_motions(Constant(np.zeros((2, 3))), square_mask, [(0, 20, 40, 20)])


def test_valid_predictions_pass_through(square_mask):
    out = comcore.motion.predict_motions(
        Constant([comcore.Motion(0.1, 1, 2)]), square_mask, [(0, 20, 40, 20)]
    )
    assert out.tolist() == [[0.1, 1.0, 2.0]]


def test_a_predicted_motion_no_push_can_cause_is_refused_naming_the_predictor(square_mask):
    # A broken predictor (corrupt weights) returned theta = 4e34: finite, so it flowed on.
    push = [(0, 20, 40, 20)]  # 40 px long
    with pytest.raises(
        ValueError,
        match=r"Constant predicted a motion no push can cause: push 0 "
        r"\(40 px long\) turns the object by 4e\+34 rad, more than half a turn",
    ):
        comcore.motion.predict_motions(Constant([(4e34, 1.0, 0.0)]), square_mask, push)
    with pytest.raises(
        ValueError,
        match=r"moves the object by 401 px, more than 10 times the "
        r"push's length",
    ):
        comcore.motion.predict_motions(Constant([(0.1, 401.0, 0.0)]), square_mask, push)
    edge = comcore.motion.predict_motions(Constant([(-np.pi, 400.0, 0.0)]), square_mask, push)
    assert edge.tolist() == [[-np.pi, 400.0, 0.0]]  # half a turn, ten lengths: still possible


def test_the_plausibility_check_reads_hypotheses_too():
    from comcore.motion._predictor import check_plausible_motions

    pushes = np.array([(0, 0, 10, 0), (0, 5, 0, 25)], float)
    fine = np.zeros((3, 2, 3))
    fine[2, 1] = (3.0, 0.0, 199.0)
    assert check_plausible_motions(fine, pushes, "M") is not None
    bad = fine.copy()
    bad[1, 1, 1] = 250.0  # hypothesis 1, push 1 (20 px): over 200 px
    with pytest.raises(
        ValueError, match=r"M predicted .* push 1 \(20 px long\) moves the object by 250 px"
    ):
        check_plausible_motions(bad, pushes, "M")
    with pytest.raises(ValueError, match=r"expected \(\.\.\., 2, 3\)"):
        check_plausible_motions(np.zeros((3, 3)), pushes, "M")


def test_the_shipped_predictors_refuse_impossible_motions_themselves(square_mask, monkeypatch):
    simulators = require_simulators()
    import predictors.ellipsoid
    from predictors import EllipsoidPredictor, OraclePredictor

    push = [(0, 20, 40, 20)]

    def exploded(*args, **kwargs):
        return np.full((1, 1, 3), 4e34)

    monkeypatch.setattr(predictors.ellipsoid, "simulate", exploded)
    with pytest.raises(ValueError, match="EllipsoidPredictor predicted a motion no push can cause"):
        EllipsoidPredictor(com=(24.0, 24.0)).predict(square_mask, push)
    sim = simulators.random_simulator("Obj1", rng=0)
    oracle = OraclePredictor(sim)
    monkeypatch.setattr(sim, "push_motions", lambda actions: np.full((len(actions), 3), 4e34))
    with pytest.raises(ValueError, match=r"OraclePredictor\(PushSimulator.* predicted a motion no"):
        oracle.predict(sim.mask, comcore.sample_pushes(sim.mask, 2, rng=0))
