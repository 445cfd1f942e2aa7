import numpy as np
import pytest

import comcore


class Constant:
    def __init__(self, out):
        self.out = out

    def predict(self, mask, actions, priors=()):
        return self.out


def test_non_predictors_are_rejected_with_the_protocol_name(square_mask):
    with pytest.raises(TypeError, match="must implement comcore.Predictor"):
        comcore.predict_motions(object(), square_mask, [(0, 20, 40, 20)])


def test_invalid_predictions_are_caught(square_mask):
    with pytest.raises(ValueError, match="predictor returned invalid motions"):
        comcore.predict_motions(Constant(np.full((1, 3), np.nan)), square_mask, [(0, 20, 40, 20)])
    with pytest.raises(ValueError, match="expected 1, got 2"):
        comcore.predict_motions(Constant(np.zeros((2, 3))), square_mask, [(0, 20, 40, 20)])


def test_valid_predictions_pass_through(square_mask):
    out = comcore.predict_motions(
        Constant([comcore.Motion(0.1, 1, 2)]), square_mask, [(0, 20, 40, 20)]
    )
    assert out.tolist() == [[0.1, 1.0, 2.0]]
