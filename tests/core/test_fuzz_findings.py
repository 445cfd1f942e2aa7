"""Inputs a fuzzing pass of the public API found unchecked: each now gets a named error."""

import numpy as np
import pytest

import comcore


@pytest.fixture
def rect():
    return comcore.Mask(np.pad(np.ones((40, 60), bool), 10))


@pytest.mark.parametrize(
    ("points", "match"),
    [
        (0.0, r"points must have shape \(n, 2\), got \(\)"),
        (np.zeros((2, 2, 2)), r"points must have shape \(n, 2\), got \(2, 2, 2\)"),
        ([[np.nan, 3.0]], "points must be finite"),
    ],
)
def test_inward_normals_checks_its_points_as_its_siblings_do(rect, points, match):
    with pytest.raises(ValueError, match=match):
        rect.inward_normals(points)


def test_inward_normals_of_no_points_is_empty(rect):
    assert rect.inward_normals([]).shape == (0, 2)


@pytest.mark.parametrize(
    ("option", "match"),
    [
        ({"standoff": 12}, r"standoff 12 m is implausible .*did you mean millimetres, 0.012\?"),
        ({"clearance": 9}, r"clearance 9 m is implausible \(expected at most 0.5 m\)"),
        ({"standoff": -1}, "standoff"),
    ],
)
def test_sample_pushes_names_an_implausible_standoff_or_clearance(rect, option, match):
    with pytest.raises(ValueError, match=match):
        comcore.sample_pushes(rect, 5, rng=0, **option)


def test_sample_pushes_names_the_clearance_when_no_start_fits(rect):
    with pytest.raises(ValueError, match=r"no valid push with clearance=0.3 m and standoff=0.012 m"):
        comcore.sample_pushes(rect, 5, clearance=0.3, rng=0)


@pytest.mark.parametrize("prior", [[[True]], np.zeros((0, 0)), [(70.0, 70.0, 1.0)]])
def test_goal_session_names_a_bad_prior_as_prior(prior):
    mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 60))
    goal = comcore.Goal(displacement=(0.05, 0.0))
    with pytest.raises(ValueError, match=r"^prior's CoMs must be finite, shape \(k, 2\) pixels"):
        comcore.GoalSession(mask, goal, prior=prior, rng=0)


@pytest.mark.parametrize(
    ("covariance", "match"),
    [
        (np.ones(4), r"must have shape \(2, 2\), got \(4,\)"),
        (np.eye(3), r"must have shape \(2, 2\), got \(3, 3\)"),
        (np.full((2, 2), np.nan), "must be finite"),
        ([[1.0, 2.0], [0.0, 1.0]], "must be symmetric"),
        ([[-1.0, 0.0], [0.0, 1.0]], "must be symmetric with variances >= 0"),
        ("ab", "must be a 2 x 2 array of numbers"),
    ],
)
def test_estimate_checks_its_covariance(covariance, match):
    with pytest.raises(ValueError, match="Estimate.covariance " + match):
        comcore.Estimate(com=(4.0, 3.0), com_m=(0.01, 0.0075), region=np.ones((6, 8), bool),
                         covariance=covariance)  # fmt: skip


@pytest.mark.parametrize(("field", "value"), [("com", 5), ("com", None), ("com", [[1, 2]]),
                                              ("com_m", "ab"), ("com_m", (1.0, np.inf))])  # fmt: skip
def test_estimate_names_a_bad_com(field, value):
    kwargs = {"com": (4.0, 3.0), "com_m": (0.01, 0.0075), field: value}
    with pytest.raises(ValueError, match=rf"Estimate.{field} must be two finite numbers \(x, y\)"):
        comcore.Estimate(region=np.ones((6, 8), bool), **kwargs)


def test_estimate_keeps_a_symmetric_covariance_read_only():
    est = comcore.Estimate(com=(4.0, 3.0), com_m=(0.01, 0.0075), region=np.ones((6, 8), bool),
                           covariance=[[4.0, 1.0], [1.0, 9.0]])  # fmt: skip
    assert est.covariance.tolist() == [[4.0, 1.0], [1.0, 9.0]] and not est.covariance.flags.writeable


@pytest.mark.parametrize("radius", [0.0, 1.6])
def test_a_push_path_far_longer_than_the_image_is_marched_only_over_the_image(radius):
    mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 8))
    field = comcore.geometry.outline_field(mask)
    far = field.pusher_paths([(-1e12, 30.0, 1e12, 30.0)], radius)  # a full march: 58 TiB
    near = field.pusher_paths([(-10.0, 30.0, 60.0, 30.0)], radius)
    assert far[3].tolist() == near[3].tolist() == [True]
    assert np.allclose(far[0], near[0], atol=0.01)  # the disc's centre at first contact
    assert far[2][0] == pytest.approx(1e12 - far[0][0, 0] - radius, abs=1.0)  # travel on


def test_a_long_executed_path_gives_an_answer_not_an_allocation():
    mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 8))
    actions = [(-1e12, 30, 1e12, 30), (0, 13, 45, 13), (13, 0, 13, 45), (30, 0, 30, 45)]
    motions = [(0.1, 3, 0), (0.2, 3, 0), (-0.2, 0, 3), (0.2, 0, 3)]
    est = comcore.estimate_posterior(mask, actions, motions)
    assert mask.contains([est.com])[0]


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda m: m.contains([[1, 0], [1]]), "points"),
        (lambda m: comcore.vt.region(m, [[0, 20, 40, 20], [1]], [0.1, 0.1]), "action"),
        (lambda m: comcore.geometry.contacts(m, [[0, 20, 40, 20], [1]]), "actions"),
        (lambda m: comcore.geometry.mask_from_outline([[0, 0], [1], [0, 1]]), "outline"),
        (lambda m: comcore.Mask([[1, 0], [1]]), "mask data"),
    ],
)
def test_ragged_nested_lists_are_named_not_left_to_numpy(rect, call, name):
    with pytest.raises(TypeError, match=rf"^{name} must be .*got ragged rows") as info:
        call(rect)
    assert "inhomogeneous" not in str(info.value)
