import math

import numpy as np
import pytest

import comcore
from comcore import Action, Estimate, Motion


def test_action_fields_and_derived_values():
    a = Action(1, 2, 4, 6)
    assert a.start == (1.0, 2.0) and a.end == (4.0, 6.0)
    assert a.length == 5.0
    assert a.direction == pytest.approx((0.6, 0.8))
    assert isinstance(a.sx, float)


@pytest.mark.parametrize(
    ("args", "error", "match"),
    [
        ((0, 0, 0, 0), ValueError, "non-zero length"),
        ((0, float("nan"), 1, 1), ValueError, r"Action.sy must be finite"),
        ((0, 0, float("inf"), 1), ValueError, r"Action.ex must be finite"),
        (("a", 0, 1, 1), TypeError, r"Action.sx must be a real number"),
        ((True, 0, 1, 1), TypeError, r"Action.sx must be a real number"),
    ],
)
def test_action_rejects_bad_values(args, error, match):
    with pytest.raises(error, match=match):
        Action(*args)


def test_motion_validation_and_sense():
    assert Motion(-0.2, 1, 2).sense == -1
    assert Motion(0.0).sense == 0
    with pytest.raises(ValueError, match="Motion.tx must be finite"):
        Motion(0.1, math.inf, 0)


def test_value_types_are_immutable():
    a = Action(0, 0, 1, 0)
    with pytest.raises(AttributeError):
        a.sx = 3.0  # type: ignore[misc]
    e = Estimate(com=(1, 2), com_m=(0.1, 0.2), region=np.ones((2, 2)), extras={"h": np.zeros(3)})
    with pytest.raises(AttributeError):
        e.com = (0, 0)  # type: ignore[misc]
    with pytest.raises(ValueError):
        e.region[0, 0] = False
    with pytest.raises(ValueError):
        e.extras["h"][0] = 1.0
    with pytest.raises(TypeError):
        e.extras["new"] = 1  # type: ignore[index]


def test_estimate_copies_the_callers_arrays():
    region = np.ones((2, 2), bool)
    e = Estimate(com=(0, 0), com_m=(0, 0), region=region)
    region[0, 0] = False
    assert e.region.all()
    assert region.flags.writeable


def test_estimate_rejects_nan_com():
    with pytest.raises(ValueError, match="two finite numbers"):
        Estimate(com=(float("nan"), 0), com_m=(0, 0), region=np.ones((1, 1)))


def test_estimate_error_px():
    e = Estimate(com=(3, 4), com_m=(0, 0), region=np.ones((1, 1)))
    assert e.error_px((0, 0)) == 5.0
    assert e.ok and Estimate(com=(0, 0), com_m=(0, 0), region=[[1]], status="budget").ok is False


def test_batches_accept_namedtuples_and_arrays_alike():
    a = comcore.checks.check_actions([Action(0, 0, 1, 0), (0, 0, 0, 1)])
    assert a.shape == (2, 4) and not a.flags.writeable
    m = comcore.checks.check_motions(Motion(0.1, 1, 2))
    assert m.tolist() == [[0.1, 1.0, 2.0]]


@pytest.mark.parametrize(
    ("region", "error", "match"),
    [
        (np.array(True), ValueError, r"2-D image of shape \(H, W\).*got shape \(\)"),
        (np.ones(4, bool), ValueError, r"got shape \(4,\)"),
        (np.ones((2, 2, 2), bool), ValueError, r"got shape \(2, 2, 2\)"),
        (np.zeros((0, 3), bool), ValueError, r"got shape \(0, 3\)"),
        (np.full((2, 2), 0.5), ValueError, r"booleans \(or the numbers 0 and 1\), got 4 other"),
        (np.array([[1.0, np.nan]]), ValueError, r"1 other value\(s\), e.g. nan"),
        (np.array([["a", "b"]]), TypeError, "image of booleans, got dtype <U1"),
        ([[1, 0], [1]], ValueError, "2-D image of shape"),
    ],
)
def test_estimate_refuses_a_region_that_is_not_an_image(region, error, match):
    # A 0-d array and a length-4 vector used to be accepted as regions.
    with pytest.raises(error, match=match):
        Estimate(com=(1.0, 1.0), com_m=(0.0, 0.0), region=region)


def test_estimate_takes_a_region_of_numbers_zero_and_one():
    e = Estimate(com=(0, 0), com_m=(0, 0), region=np.array([[1, 0], [0, 1]], np.uint8))
    assert e.region.dtype == bool and e.region.tolist() == [[True, False], [False, True]]


def test_each_estimator_attaches_its_typed_details_read_only():
    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
    motions = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)]
    heat = comcore.estimate_heatmap(mask, actions, motions)
    cuts = comcore.estimate_progressive(mask, actions, motions)
    post = comcore.estimate_posterior(mask, actions, motions, model=None)
    assert isinstance(heat.heatmap, comcore.paper.HeatmapDetails) and heat.posterior is None
    assert isinstance(cuts.progressive, comcore.paper.ProgressiveDetails) and cuts.heatmap is None
    assert cuts.progressive.region_sizes[0] == mask.area_px and cuts.skipped == ()
    assert isinstance(post.posterior, comcore.active.PosteriorDetails) and post.progressive is None
    assert post.posterior.image.shape == mask.shape and post.posterior.pose is None
    for array in (heat.heatmap.image, post.posterior.image, post.posterior.mu_posterior):
        assert not array.flags.writeable
    with pytest.raises(TypeError, match="Estimate.posterior must be a PosteriorDetails or None"):
        Estimate(com=(1, 2), com_m=(0.1, 0.2), region=np.ones((2, 2)), posterior={"image": 1})
    with pytest.raises(TypeError, match="Estimate.skipped must hold comcore.SkippedPush"):
        Estimate(com=(1, 2), com_m=(0.1, 0.2), region=np.ones((2, 2)), skipped=[(0, "", "", "")])
