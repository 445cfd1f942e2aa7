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


# -- what the fuzz harness (benchmarks/accuracy/fuzz_api.py) found accepted ---------------


@pytest.mark.parametrize(
    "call",
    [
        lambda m, a, k: comcore.estimate_heatmap(m, np.array(a, complex), k),
        lambda m, a, k: comcore.estimate_progressive(m, a, np.array(k, complex)),
        lambda m, a, k: comcore.checks.check_actions([(0, 1, 2, 3 + 1j)]),
        lambda m, a, k: comcore.conventions.rotation_matrix(0.1 + 0.2j),
        lambda m, a, k: comcore.conventions.rotate_vectors([(1 + 1j, 0)], 0.1),
    ],
)
def test_complex_numbers_are_refused_not_cast(call):
    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    actions = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
    motions = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)]
    with pytest.raises(TypeError, match="real numbers|angle in radians"):
        call(mask, actions, motions)


@pytest.mark.parametrize("rng", [{}, {"seed": 1}, [], set(), {1, 2}])
def test_a_dict_set_or_empty_sequence_is_no_seed(rng):
    with pytest.raises(TypeError, match="rng must be None, a non-negative int seed"):
        comcore.checks.check_rng(rng)
    assert comcore.checks.check_rng([1, 2]).random() == np.random.default_rng([1, 2]).random()


def test_an_image_over_max_image_pixels_is_refused_by_its_shape():
    huge = np.broadcast_to(np.True_, (100_000, 100_000))  # a view: no memory behind it
    with pytest.raises(ValueError, match="mask data of 100000 x 100000 pixels .*MAX_IMAGE_PIXELS"):
        comcore.Mask(huge)
    with pytest.raises(ValueError, match="image of 100000 x 100000 pixels"):
        comcore.conventions.pixel_centres(huge)
    side = int(np.sqrt(comcore.conventions.MAX_IMAGE_PIXELS))
    assert comcore.conventions.pixel_centres(np.zeros((side, 1), bool)).shape == (0, 2)


@pytest.mark.parametrize(
    ("call", "error", "match"),
    [
        (lambda: comcore.conventions.check_plausible(0.0025, "resolution", "bogus"),
         ValueError, "kind must be one of angle_noise, .*got 'bogus'"),
        (lambda: comcore.mask_from_image(np.pad(np.ones((20, 20)), 4) * 200, fill_holes="no"),
         TypeError, "fill_holes must be True or False, got 'no'"),
        (lambda: comcore.mask_from_image(np.broadcast_to(np.uint8(3), (100_000, 100_000))),
         ValueError, "image of 100000 x 100000 pixels is larger than MAX_IMAGE_PIXELS"),
        (lambda: comcore.conventions.object_motion_from_camera((0.1, 0, 0), float("nan")),
         ValueError, "pose_theta must be a finite number"),
        (lambda: comcore.conventions.object_motion_from_camera((float("nan"), 0, 0), 0.2),
         ValueError, "motion must be finite"),
        (lambda: comcore.conventions.object_motion_from_camera((0.1, 0), 0.2),
         ValueError, r"motion must be 3 numbers \(theta, tx, ty\)"),
        (lambda: comcore.geometry.OutlineField(np.ones((5, 5), bool)),
         TypeError, "mask must be a comcore.Mask"),
        (lambda: comcore.geometry.OutlineField(comcore.Mask(np.pad(np.ones((9, 9)), 3)), pad=2.5),
         TypeError, "pad must be an int"),
        (lambda: comcore.geometry.rasterise_polygon([(0, 0), (3, 0), (0, 3)], (10**6, 10**6)),
         ValueError, "shape of 1000000 x 1000000 pixels is larger than MAX_IMAGE_PIXELS"),
        (lambda: comcore.geometry.largest_component(np.broadcast_to(np.True_, (10**5, 10**5))),
         ValueError, "image of 100000 x 100000 pixels is larger than MAX_IMAGE_PIXELS"),
        (lambda: comcore.GoalSession(comcore.Mask(np.pad(np.ones((20, 20)), 4)), model=None,
                                     goal=comcore.Goal(displacement=(0.03, 0)), n_particles=2**63),
         ValueError, "n_particles must be at most 10000"),
    ],
)  # fmt: skip
def test_more_fuzz_findings_are_refused_by_name(call, error, match):
    with pytest.raises(error, match=match):
        call()


def test_a_goal_session_refuses_a_ring_as_the_active_session_does():
    ring = np.zeros((40, 40), bool)
    ring[5:35, 5:35] = True
    ring[12:28, 12:28] = False
    goal = comcore.Goal(displacement=(0.03, 0.0))
    with pytest.raises(ValueError, match="mask has holes of 256 px"):
        comcore.GoalSession(comcore.Mask(ring), goal=goal, model=None)
    with pytest.raises(ValueError, match="mask has holes of 256 px"):
        comcore.ActiveSession(comcore.Mask(ring), model=None)
