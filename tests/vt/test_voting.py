"""Mason's Voting Theorem: examples and one property per test."""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import comcore
from comcore import vt
from tests.strategies import friction, masks, points, seeds, unit_vectors

MIRROR = np.diag([-1.0, 1.0])  # reflect x -> -x


def test_normal_push_example():
    senses = vt.predicted_sense([[5, 3], [5, 7], [5, 5]], (0, 5), (1, 0), (1, 0), mu=0.3)
    assert senses.tolist() == [1, -1, 0]


def test_oblique_push_inside_the_cone_is_decided_by_the_push_direction():
    # Normal +x at the origin, push turned 20 deg towards -y (CCW on screen), mu=1 (45 deg cone).
    push = comcore.conventions.rotate_vectors([[1.0, 0.0]], np.deg2rad(20))[0]
    com_between = 10 * comcore.conventions.rotate_vectors([[1.0, 0.0]], np.deg2rad(10))[0]
    # The CoM lies inside the cone, CCW of the normal but CW of the push line.
    assert vt.predicted_sense(com_between, (0, 0), (1, 0), push, mu=1.0) == -1
    # With almost no friction the cone collapses on the normal and the edges decide.
    assert vt.predicted_sense(com_between, (0, 0), (1, 0), push, mu=0.01) == 1


@given(com=points, normal=unit_vectors, push_turn=st.floats(-1.4, 1.4), mu=friction)
def test_sense_flips_under_mirror_reflection(com, normal, push_turn, mu):
    push = comcore.conventions.rotate_vectors(normal, push_turn)
    contact = np.array([1.0, -2.0])
    s = vt.predicted_sense(com, contact, normal, push, mu)
    s_mirror = vt.predicted_sense(MIRROR @ com, MIRROR @ contact, MIRROR @ normal, MIRROR @ push, mu)
    assert s_mirror == -s


@given(com=points, normal=unit_vectors, mu1=friction, mu2=friction)
def test_normal_push_sense_does_not_depend_on_mu(com, normal, mu1, mu2):
    assume(abs(comcore.conventions.ccw_cross(np.zeros(2) - com, normal)) > 1e-6)
    assert vt.predicted_sense(com, (0, 0), normal, normal, mu1) == vt.predicted_sense(
        com, (0, 0), normal, normal, mu2
    )


@given(t=st.floats(0.5, 60), normal=unit_vectors, push_turn=st.floats(-1.2, 1.2), mu=friction)
def test_push_line_through_the_com_gives_no_rotation_when_inside_the_cone(t, normal, push_turn, mu):
    assume(
        abs(push_turn) < np.arctan(mu) - 1e-6
    )  # push direction strictly inside the friction cone
    push = comcore.conventions.rotate_vectors(normal, push_turn)
    com = np.array([2.0, 3.0]) + t * push
    assert vt.predicted_sense(com, (2.0, 3.0), normal, push, mu, band=1e-6) == 0


@settings(max_examples=25, deadline=None)
@given(mask=masks(), seed=seeds)
def test_normal_push_regions_cover_the_mask(mask, seed):
    action = comcore.sample_pushes(mask, 1, cone=0.0, rng=seed)[0]
    plus = vt.region(mask, action, 0.1)
    minus = vt.region(mask, action, -0.1)
    assert np.array_equal(plus | minus, mask.data)


@settings(max_examples=40, deadline=None)
@given(mask=masks(), seed=seeds, mu=st.floats(0.05, 1.5), cone=st.floats(0, 1.2))
def test_true_com_is_in_the_region_with_mu_unknown_or_a_range(mask, seed, mu, cone):
    rng = np.random.default_rng(seed)
    action = comcore.sample_pushes(mask, 1, cone=cone, rng=rng)[0]
    com = mask.pixels[rng.integers(mask.area_px)]
    con = comcore.geometry.contacts(mask, action)
    sense = vt.predicted_sense(com, con.point[0], con.normal[0], action[2:] - action[:2], mu)
    row, col = int(com[1]), int(com[0])
    assert vt.region(mask, action, float(sense), mu=None)[row, col]
    assert vt.region(mask, action, float(sense), mu=(mu * 0.5, mu * 2))[row, col]
    assert vt.region(mask, action, float(sense), mu=mu)[row, col]


@settings(max_examples=20, deadline=None)
@given(mask=masks(), seed=seeds, mu=st.floats(0.05, 1.5))
def test_region_shrinks_as_the_mu_range_narrows(mask, seed, mu):
    action = comcore.sample_pushes(mask, 1, cone=0.8, rng=seed)[0]
    wide = vt.region(mask, action, 0.2, mu=None)
    narrow = vt.region(mask, action, 0.2, mu=(mu, mu * 1.5))
    exact = vt.region(mask, action, 0.2, mu=mu)
    assert np.all(exact <= narrow) and np.all(narrow <= wide)


def test_normal_push_region_is_the_paper_half_plane(square_mask):
    action = (0, 20, 40, 20)  # push right along row 20, normal to the left edge
    ccw, cw = comcore.geometry.split_by_line(square_mask, action)
    plus = vt.region(square_mask, action, 0.3)
    assert np.array_equal(plus & ~ccw & ~cw, square_mask.data & ~ccw & ~cw)  # band kept
    assert np.array_equal(plus & (ccw | cw), ccw)


def test_region_batches_and_motion_inputs(square_mask):
    actions = [(0, 20, 40, 20), (20, 0, 20, 40)]
    out = vt.region(square_mask, actions, [comcore.Motion(0.2), comcore.Motion(-0.2)])
    assert out.shape == (2, 50, 50)
    assert np.array_equal(out[0], vt.region(square_mask, actions[0], comcore.Motion(0.2)))
    zero = vt.region(square_mask, actions[0], 0.0)
    assert zero.sum() == 30  # no rotation: the CoM is on the push line (band 0.5 px)


def test_region_errors(square_mask):
    with pytest.raises(ValueError, match=r"action\(s\) \[0\] miss"):
        vt.region(square_mask, (0, 0, 5, 0), 0.1)
    with pytest.raises(ValueError, match="one value per action: expected 2, got 1"):
        vt.region(square_mask, [(0, 20, 40, 20), (20, 0, 20, 40)], [0.1])
    with pytest.raises(ValueError, match="theta must be finite"):
        vt.region(square_mask, (0, 20, 40, 20), np.nan)
    with pytest.raises(ValueError, match="mu must be >= 0"):
        vt.region(square_mask, (0, 20, 40, 20), 0.1, mu=-1)
    with pytest.raises(TypeError, match="mask must be a comcore.Mask"):
        vt.region(np.ones((3, 3)), (0, 20, 40, 20), 0.1)


def test_predicted_sense_errors():
    with pytest.raises(ValueError, match="normal must be a non-zero vector"):
        vt.predicted_sense([1, 1], (0, 0), (0, 0), (1, 0), 0.3)
    with pytest.raises(ValueError, match="single value"):
        vt.predicted_sense([1, 1], (0, 0), (1, 0), (1, 0), (0.1, 0.2))
    with pytest.raises(ValueError, match="push_dir must be finite"):
        vt.predicted_sense([1, 1], (0, 0), (1, 0), (np.nan, 0), 0.3)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"band": np.nan}, r"band must be a finite number >= 0, got nan"),
        ({"band": -5}, r"band must be a finite number >= 0, got -5.0"),
        ({"band": np.inf}, r"band must be a finite number >= 0, got inf"),
        ({"theta_tol": np.nan}, r"theta_tol must be a finite number >= 0, got nan"),
        ({"theta_tol": -1}, r"theta_tol must be a finite number >= 0, got -1.0"),
        ({"band": "0.5"}, r"band must be a number, got str"),
    ],
)
def test_region_rejects_bad_band_and_theta_tol(square_mask, kwargs, match):
    # NaN used to return the whole mask and -5 a region without the band (and the true CoM).
    with pytest.raises((ValueError, TypeError), match=match):
        vt.region(square_mask, (0, 20, 40, 20), 0.3, **kwargs)


def test_region_accepts_a_zero_band_and_theta_tol(square_mask):
    action = (0, 20, 40, 20)
    # rows 10..19, and row 20 on the push line (a tie is kept even without a band)
    assert vt.region(square_mask, action, 0.3, band=0).sum() == 330
    assert vt.region(square_mask, action, 0.0, theta_tol=0).sum() == 30  # the push line


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (
            ((0, 0), [(1, 0), (0, 1)], (1, 0)),
            r"normal must be a single 2-vector.*got shape \(2, 2\)",
        ),
        (((0, 0), (1, 0), [(1, 0), (0, 1)]), r"push_dir must be a single 2-vector.*\(2, 2\)"),
        (((0, 0), (1, 0, 0), (1, 0)), r"normal must be a single 2-vector.*got shape \(3,\)"),
        (([(0, 0), (1, 1)], (1, 0), (1, 0)), r"contact must be a single point.*\(2, 2\)"),
        (([[0, 0]], (1, 0), (1, 0)), r"contact must be a single point.*\(1, 2\)"),
    ],
)
def test_predicted_sense_and_consistent_take_one_push(args, match):
    # A (2, 2) normal used to broadcast against the CoMs, pairing them with different normals.
    with pytest.raises(ValueError, match=match):
        vt.predicted_sense([[1, 1], [2, 2]], *args, mu=0.3)
    with pytest.raises(ValueError, match=match):
        vt.consistent([[1, 1], [2, 2]], *args, sense=1)


def test_predicted_sense_takes_an_infinite_mu():
    # mu = inf is allowed by the docstring (cone half-angle pi/2) and was refused.
    com = [[5, 3], [5, 7], [3, 5]]
    contact, normal, push = (0, 5), (1, 0), (1, 0.5)
    inf = vt.predicted_sense(com, contact, normal, push, mu=np.inf)
    assert inf.tolist() == vt.predicted_sense(com, contact, normal, push, mu=1e12).tolist()
    with pytest.raises(ValueError, match=r"single value for predicted_sense, got None"):
        vt.predicted_sense(com, contact, normal, push, mu=None)
