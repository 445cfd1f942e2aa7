import numpy as np
import pytest

import comcore


def test_pushes_hit_along_the_normal_with_the_requested_travel(disk_mask):
    pushes = comcore.sample_pushes(disk_mask, 50, cone=0.0, rng=3)
    con = comcore.geometry.contacts(disk_mask, pushes)
    assert con.hit.all()
    direction = pushes[:, 2:] - pushes[:, :2]
    direction /= np.hypot(*direction.T)[:, None]
    assert np.all(np.sum(direction * con.normal, axis=1) > np.cos(np.deg2rad(6)))
    after = np.hypot(*(pushes[:, 2:] - con.point).T)
    assert np.allclose(after, 0.03 / disk_mask.resolution, atol=1e-6)


def test_cone_bounds_the_angle_to_the_normal(square_mask):
    pushes = comcore.sample_pushes(square_mask, 200, cone=0.5, rng=1)
    con = comcore.geometry.contacts(square_mask, pushes)
    direction = pushes[:, 2:] - pushes[:, :2]
    direction /= np.hypot(*direction.T)[:, None]
    angle = np.arccos(np.clip(np.sum(direction * con.normal, axis=1), -1, 1))
    assert angle.max() <= 0.5 + 0.15  # the normal at a corner is a blend of both edges
    assert angle.max() > 0.3


def test_sampling_is_seeded(l_mask):
    a = comcore.sample_pushes(l_mask, 10, cone=0.3, rng=7)
    b = comcore.sample_pushes(l_mask, 10, cone=0.3, rng=np.random.default_rng(7))
    assert np.array_equal(a, b)
    assert not np.array_equal(a, comcore.sample_pushes(l_mask, 10, cone=0.3, rng=8))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"n": -1}, "non-negative integer"),
        ({"n": 2, "cone": 2.0}, r"cone must be in \[0, pi/2\)"),
        ({"n": 2, "travel": 0}, "travel must be"),
    ],
)
def test_sampling_errors(square_mask, kwargs, match):
    with pytest.raises(ValueError, match=match):
        comcore.sample_pushes(square_mask, **kwargs)


def test_a_negative_zero_cone_is_a_zero_cone(square_mask):
    # cone=-0.0 used to fail inside numpy ("high - low < 0").
    a = comcore.sample_pushes(square_mask, 5, cone=-0.0, rng=3)
    assert np.array_equal(a, comcore.sample_pushes(square_mask, 5, cone=0.0, rng=3))


@pytest.mark.parametrize(("rng", "error"), [(-1, ValueError), ("a", TypeError), (0.5, TypeError)])
def test_sampling_names_a_bad_rng(square_mask, rng, error):
    with pytest.raises(error, match="rng must be None, a non-negative int seed"):
        comcore.sample_pushes(square_mask, 2, rng=rng)


def test_starts_keep_clear_of_a_concave_object(l_mask):
    pushes = comcore.sample_pushes(l_mask, 100, cone=0.6, standoff=0.03, clearance=0.02, rng=2)
    free = l_mask.distance_to_object(pushes[:, :2]) - 0.5 * np.sqrt(2)
    assert np.all(free * l_mask.resolution >= 0.02)


def test_distance_to_object_off_the_image(square_mask):
    d = square_mask.distance_to_object([[-10.0, 20.0], [5.0, 20.0]])
    assert d[1] == 5.0 and d[0] == 20.0
