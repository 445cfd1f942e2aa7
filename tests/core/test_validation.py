import numpy as np
import pytest

import comcore
from comcore import Action, Motion


@pytest.mark.parametrize(
    ("value", "error", "match"),
    [
        ([[0, 0, 1]], ValueError, r"actions must have shape \(n, 4\), got \(1, 3\)"),
        (np.zeros((2, 4, 1)), ValueError, r"actions must have shape \(n, 4\)"),
        ([[0, 0, np.nan, 1]], ValueError, r"actions must be finite.*row\(s\) \[0\]"),
        ([[0, 0, 1, 1], [2, 2, 2, 2]], ValueError, r"zero-length action\(s\) at index \[1\]"),
        ("abcd", TypeError, "actions must be array_like"),
        ([["a", 0, 1, 1]], TypeError, "actions must be array_like of real numbers"),
    ],
)
def test_check_actions_errors(value, error, match):
    with pytest.raises(error, match=match):
        comcore.checks.check_actions(value)


def test_check_motions_count_mismatch():
    with pytest.raises(ValueError, match="expected 2, got 3"):
        comcore.checks.check_motions(np.zeros((3, 3)), n=2)


def test_check_motions_rejects_inf():
    with pytest.raises(ValueError, match="motions must be finite"):
        comcore.checks.check_motions([[0, np.inf, 0]])


def test_check_priors_roundtrip_and_errors():
    a, m = comcore.checks.check_priors([(Action(0, 0, 1, 0), Motion(0.1, 1, 0))] * 3)
    assert a.shape == (3, 4) and m.shape == (3, 3)
    assert comcore.checks.check_priors(())[0].shape == (0, 4)
    with pytest.raises(TypeError, match="sequence of"):
        comcore.checks.check_priors(5)
    with pytest.raises(ValueError, match=r"priors\[1\]"):
        comcore.checks.check_priors([(Action(0, 0, 1, 0), Motion(0.1)), ((1, 2), (3,))])


@pytest.mark.parametrize(
    ("mu", "match"),
    [(-0.1, ">= 0"), ((0.5, 0.1), "lo <= hi"), ((np.nan, 1), "NaN"), ("x", "a number or")],
)
def test_check_mu_errors(mu, match):
    with pytest.raises((ValueError, TypeError), match=match):
        comcore.checks.check_mu(mu)


def test_check_mask_requires_a_mask():
    with pytest.raises(TypeError, match=r"mask must be a comcore.Mask, got ndarray \(wrap"):
        comcore.checks.check_mask(np.ones((3, 3), bool))


def test_validators_do_not_mutate_input():
    arr = np.array([[0.0, 0.0, 1.0, 0.0]])
    out = comcore.checks.check_actions(arr)
    assert arr.flags.writeable and out is not arr
    assert not out.flags.writeable
