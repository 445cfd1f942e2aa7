import numpy as np
import pytest

import comcore

from .conftest import synthetic_motions


def random_pushes(mask, n=60, cone=0.0, seed=0):
    return comcore.sample_pushes(mask, n, cone=cone, rng=seed)


def test_equality_score_laws():
    assert comcore.equality_score(5, 5) == 1.0
    assert comcore.equality_score(1, 9) == pytest.approx(0.6)
    assert comcore.equality_score(0, 0) == 0.0
    assert comcore.equality_score(3, 7) == comcore.equality_score(7, 3)


@pytest.mark.parametrize("com", [(20.0, 30.0), (33.0, 14.0), (24.0, 25.0)])
@pytest.mark.parametrize("cone", [0.0, 0.6])
def test_true_com_stays_in_the_region_and_the_estimate_is_close(square_mask, com, cone):
    acts = random_pushes(square_mask, cone=cone)
    mots = synthetic_motions(square_mask, acts, com, mu=0.5, gain=0.02)
    est = comcore.estimate_progressive(square_mask, acts, mots)
    assert est.ok
    assert est.region[int(com[1]), int(com[0])]
    assert est.error_px(com) < 6.0
    sizes = est.extras["region_sizes"]
    assert sizes[0] == square_mask.area_px and all(b <= a for a, b in zip(sizes, sizes[1:]))
    if cone == 0.0:  # normal pushes cut a half-plane: every applied push removes pixels
        assert all(b < a for a, b in zip(sizes, sizes[1:]))
    assert len(est.used) == len(sizes) - 1 and len(set(est.used)) == len(est.used)


def test_equality_selection_halves_the_region(square_mask):
    acts = random_pushes(square_mask, n=120)
    mots = synthetic_motions(square_mask, acts, (22.0, 27.0), gain=0.02)
    est = comcore.estimate_progressive(
        square_mask, acts, mots, area_ratio=0.0, min_score=0.0, min_rotation=0.0
    )
    sizes = np.array(est.extras["region_sizes"], float)
    # The first cut is the most even split available: close to half the object.
    assert sizes[1] / sizes[0] == pytest.approx(0.5, abs=0.05)


def test_stops_once_the_region_is_small_enough(square_mask):
    acts = random_pushes(square_mask, n=120)
    # A large gain: only pushes within 0.5 px of the CoM turn it by less than 5 degrees.
    mots = synthetic_motions(square_mask, acts, (22.0, 27.0), gain=0.2)
    est = comcore.estimate_progressive(square_mask, acts, mots, area_ratio=0.1, min_score=0.0)
    sizes = est.extras["region_sizes"]
    assert sizes[-1] <= 0.1 * square_mask.area_px < sizes[-2]


def test_rotation_selection_takes_actions_in_ascending_rotation(square_mask):
    acts = random_pushes(square_mask, n=40)
    mots = synthetic_motions(square_mask, acts, (22.0, 27.0), gain=0.02)
    est = comcore.estimate_progressive(square_mask, acts, mots, selection="rotation")
    used_theta = np.abs(mots[list(est.used), 0])
    assert np.all(np.diff(used_theta) >= 0)
    assert np.all(used_theta >= np.deg2rad(5))


def test_min_score_prunes_actions(square_mask):
    acts = random_pushes(square_mask, n=60)
    mots = synthetic_motions(square_mask, acts, (22.0, 27.0), gain=0.02)
    strict = comcore.estimate_progressive(square_mask, acts, mots, min_score=0.99, area_ratio=0.0)
    loose = comcore.estimate_progressive(square_mask, acts, mots, min_score=0.0, area_ratio=0.0)
    assert len(strict.used) < len(loose.used)


def test_small_rotations_are_dropped_and_none_left_is_reported(square_mask):
    acts = random_pushes(square_mask, n=10)
    tiny = np.column_stack([np.full(10, np.deg2rad(1)), np.zeros(10), np.zeros(10)])
    est = comcore.estimate_progressive(square_mask, acts, tiny)
    assert est.status == "no_actions" and est.com == square_mask.centroid and est.used == ()


def test_contradictions_are_skipped_and_reported(square_mask):
    # Two parallel normal pushes that disagree: the CoM cannot be above row 15 and below row 35.
    acts = [(0, 15, 40, 15), (0, 35, 40, 35)]
    mots = [(0.3, 0, 0), (-0.3, 0, 0)]
    est = comcore.estimate_progressive(
        square_mask, acts, mots, selection="rotation", area_ratio=0.0
    )
    assert est.status == "contradiction"
    assert len(est.extras["contradicted"]) == 1
    assert np.isfinite(est.com).all()


def test_progressive_input_errors(square_mask):
    acts = random_pushes(square_mask, n=4)
    with pytest.raises(ValueError, match="selection must be one of"):
        comcore.estimate_progressive(square_mask, acts, np.ones((4, 3)), selection="best")
    with pytest.raises(ValueError, match=r"area_ratio must be in \[0, 1\]"):
        comcore.estimate_progressive(square_mask, acts, np.ones((4, 3)), area_ratio=-0.1)
    with pytest.raises(ValueError, match="expected 4, got 3"):
        comcore.estimate_progressive(square_mask, acts, np.ones((3, 3)))
    with pytest.raises(ValueError, match="start inside"):
        comcore.estimate_progressive(square_mask, [(20, 20, 30, 20)], [(0.3, 0, 0)])


def test_known_mu_is_at_least_as_tight_as_unknown(square_mask):
    acts = random_pushes(square_mask, n=60, cone=0.7)
    mots = synthetic_motions(square_mask, acts, (20.0, 30.0), mu=0.3, gain=0.02)
    known = comcore.estimate_progressive(square_mask, acts, mots, mu=0.3, area_ratio=0.0)
    assert known.region[30, 20]
