"""Tests of calibrate_model_weight (comcore/active/_calibrate.py): coverage per power of the model."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

import comcore

MASK = comcore.Mask(np.pad(np.ones((20, 20), bool), 6))  # object pixels 6..25
#: The sessions' region: no floor, no bagging (what calibrate_model_weight scores)
SESSION = comcore.Likelihood(systematic_error=0.0)


def _senses(com, seed, n=5):
    """``n`` pushes and the noise-free senses they turned a plate with its CoM at ``com``."""
    actions = comcore.sample_pushes(MASK, n, cone=0.0, rng=seed)
    c = comcore.geometry.contacts(MASK, actions)
    senses = [comcore.vt.predicted_sense(com, p, nrm, comcore.Action(*a).direction, 0.3)
              for p, nrm, a in zip(c.point, c.normal, actions)]  # fmt: skip
    return actions, [(0.1 * s, 0.0, 0.0) for s in senses]


def _objects(coms=((11.0, 12.0), (20.0, 19.0), (14.0, 21.0))):
    return [(MASK, *_senses(com, seed), com) for seed, com in enumerate(coms)]


class Lever:
    """theta proportional to the CoM's signed distance to the push line (a motion model)."""

    def __init__(self, gain=0.01):
        self.gain = gain

    def predict_hypotheses(self, mask, actions, coms, mu):
        lever = comcore.geometry.signed_line_distance(coms, actions)
        return np.stack([self.gain * lever, 0 * lever + 4.0, 0 * lever], axis=-1)


def test_without_a_model_every_power_scores_the_same():
    cal = comcore.calibrate_model_weight(_objects(), model=None, powers=(1.0, 0.3, 0.6))
    assert isinstance(cal, comcore.PowerCalibration)
    assert cal.powers == (0.3, 0.6, 1.0) and cal.n_objects == 3 and cal.level == 0.9
    for values in (cal.coverage, cal.coverage_low, cal.radius_m, cal.error_m):
        assert values.shape == (3,) and np.all(values == values[0])
    assert cal.coverage.tolist() == [1.0] * 3 and cal.recommended == 1.0


def test_the_numbers_are_those_of_each_object_s_posterior():
    objects = _objects()
    cal = comcore.calibrate_model_weight(objects, model=None, powers=(0.5,), credible=0.8)
    errors, radii = [], []
    for mask, actions, motions, com in objects:
        est = comcore.estimate_posterior(mask, actions, motions, model=None, credible=0.8,
                                         likelihood=SESSION, bootstrap=0)  # fmt: skip
        assert est.region_holds(com)
        errors.append(est.error_px(com) * mask.resolution)
        radii.append(np.sqrt(est.region.sum() / np.pi) * mask.resolution)
    assert cal.error_m[0] == pytest.approx(np.mean(errors))
    # the radius counts the last pixel in part: within a pixel of the region's own
    assert abs(cal.radius_m[0] - np.mean(radii)) < MASK.resolution
    assert cal.level == 0.8


def test_a_measured_com_no_region_holds_recommends_the_smallest_power():
    objects = [(m, a, mo, (25.0, 6.0)) for m, a, mo, _ in _objects()]  # a corner, not the CoM
    cal = comcore.calibrate_model_weight(objects, model=None, powers=(0.4, 0.7))
    assert cal.coverage.tolist() == [0.0, 0.0]
    assert cal.coverage_low.tolist() == [0.0, 0.0]
    assert cal.recommended == 0.4


def test_the_lower_bound_is_clopper_pearson_at_90_percent():
    held = _objects()
    missed = [(m, a, mo, (25.0, 6.0)) for m, a, mo, _ in _objects(((11.0, 12.0), (20.0, 19.0)))]
    cal = comcore.calibrate_model_weight(held + missed, model=None, powers=(1.0,))
    assert cal.n_objects == 5 and cal.coverage[0] == pytest.approx(0.6)
    assert cal.coverage_low[0] == pytest.approx(stats.beta.ppf(0.1, 3, 3))
    assert cal.coverage_low[0] < cal.coverage[0]
    assert cal.recommended == 1.0  # the only one, though it did not reach 90 %


def test_an_estimate_s_records_score_as_its_pushes_do():
    com = (12.0, 19.0)

    def push(action):
        c = comcore.geometry.contacts(MASK, action)
        s = comcore.vt.predicted_sense(com, c.point[0], c.normal[0], action.direction, 0.3)
        return comcore.Motion(0.1 * s, 0.0, 0.0)

    est = comcore.estimate_active(MASK, push, model=None, rng=1,
                                  stop=comcore.StopRule(max_pushes=4))  # fmt: skip
    executed = [p for p in est.pushes if p.outcome != "failed"]
    actions = [p.action for p in executed]
    motions = [p.motion for p in executed]
    by_estimate = comcore.calibrate_model_weight([(MASK, est, com)], model=None, powers=(0.5, 1.0))
    by_pushes = comcore.calibrate_model_weight([(MASK, actions, motions, com)], model=None,
                                               powers=(0.5, 1.0))  # fmt: skip
    for field in ("coverage", "coverage_low", "radius_m", "error_m"):
        np.testing.assert_array_equal(getattr(by_estimate, field), getattr(by_pushes, field))
    # and the records may come from any iterable, a generator included
    lazy = comcore.calibrate_model_weight(((MASK, est, com) for _ in range(2)), model=None,
                                          powers=(1.0,))  # fmt: skip
    assert lazy.n_objects == 2


def test_the_power_is_recovered_full_for_a_right_model_and_low_for_one_that_errs_alike():
    """A model whose rotations are 30 % too small on every push needs a low power."""
    objects = []
    coms = [(11.0, 12.0), (20.0, 19.0), (14.0, 21.0), (18.0, 10.0), (9.0, 18.0)]
    for seed, com in enumerate(coms):
        actions = comcore.sample_pushes(MASK, 4, cone=0.0, rng=seed)
        motions = Lever(0.01).predict_hypotheses(MASK, actions, [com], 0.3)[0]
        objects.append((MASK, actions, motions, com))
    likelihood = comcore.Likelihood(mu=0.3, n_mu=1, motion_noise=(0.0, 0.0),
                                    theta_noise=(0.002, 0.0))  # fmt: skip
    kw = {"powers": (0.1, 0.4, 1.0), "likelihood": likelihood}
    right = comcore.calibrate_model_weight(objects, model=Lever(0.01), **kw)
    assert right.coverage.tolist() == [1.0] * 3 and right.recommended == 1.0
    assert np.all(np.diff(right.radius_m) < 0)  # a higher power, a smaller region
    wrong = comcore.calibrate_model_weight(objects, model=Lever(0.007), **kw)
    assert wrong.coverage[-1] < 0.5 and wrong.coverage[0] == 1.0
    assert wrong.recommended == 0.1


@pytest.mark.parametrize(
    ("records", "kwargs", "error", "match"),
    [
        (42, {}, TypeError, "records must be an iterable of"),
        ([(MASK, [(0, 15, 30, 15)], [(0.1, 0, 0)], (15.0, 15.0), "extra")], {}, TypeError,
         r"records\[0\] must be a \(mask, estimate, true_com\) or \(mask, actions, motions, true_com\)"),
        ([7], {}, TypeError, r"records\[0\] must be a"),
        ([(MASK, "not an estimate", (15.0, 15.0))], {}, TypeError, r"records\[0\] must be a"),
        ([(MASK, [(0, 15, 30, 15)], [(0.1, 0, 0)], (15.0, np.nan))], {}, ValueError,
         r"records\[0\] true_com"),
        ([(MASK, [(0, 15, 30, 15)], [(0.1, 0, 0)], (1.0, 2.0, 3.0))], {}, ValueError,
         r"records\[0\] true_com"),
        ("ok", {"powers": "0.5"}, TypeError, "powers must be a sequence of numbers in"),
        ("ok", {"powers": [[0.5, 1.0]]}, TypeError, "powers must be a sequence of numbers in"),
        ("ok", {"powers": ()}, ValueError, "powers must not be an empty sequence"),
        ("ok", {"powers": (0.0, 1.0)}, ValueError, r"powers must be in \(0, 1\]"),
        ("ok", {"powers": (0.5, 0.5)}, ValueError, "powers must be distinct"),
        ("ok", {"credible": 1.0}, ValueError, "credible"),
        ("ok", {"model": "limit surface"}, TypeError, "model must implement"),
    ],
)  # fmt: skip
def test_bad_records_and_options_are_named(records, kwargs, error, match):
    if records == "ok":
        records = _objects()[:1]
    kwargs = {"model": None, **kwargs}
    with pytest.raises(error, match=match):
        comcore.calibrate_model_weight(records, **kwargs)


@pytest.mark.parametrize("part", ["mask", "motions"])
def test_a_bad_mask_or_motions_is_named_by_its_record(part):
    objects = _objects()
    mask, actions, motions, com = objects[1]
    if part == "mask":
        objects[1] = (mask.data, actions, motions, com)
    else:
        objects[1] = (mask, actions, motions[:-1], com)
    with pytest.raises((TypeError, ValueError), match=r"records\[1\]"):
        comcore.calibrate_model_weight(objects, model=None, powers=(1.0,))
