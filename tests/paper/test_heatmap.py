import numpy as np
import pytest

import comcore
from tests.conftest import synthetic_motions


def grid_pushes(lo=10, hi=39, step=2, outside=(0, 50)):
    rows = [(outside[0], r, outside[1], r) for r in range(lo, hi + 1, step)]
    cols = [(c, outside[0], c, outside[1]) for c in range(lo, hi + 1, step)]
    return np.array(rows + cols, float)


def test_heatmap_is_normalised_and_zero_off_the_object(square_mask):
    acts = grid_pushes()
    heat = comcore.paper.rotation_heatmap(
        square_mask, acts, synthetic_motions(square_mask, acts, (20, 30))
    )
    assert heat.shape == square_mask.shape
    assert heat[square_mask.data].min() == 0.0 and heat[square_mask.data].max() == pytest.approx(
        1.0
    )
    assert not heat[~square_mask.data].any()


def test_heatmap_matches_a_per_pixel_reference(l_mask):
    acts = np.array([[0, 12, 45, 14], [8, 0, 10, 39], [0, 38, 45, 20]], float)
    mots = np.array([[0.2, 0, 0], [-0.05, 0, 0], [0.4, 0, 0]])
    heat = comcore.paper.rotation_heatmap(l_mask, acts, mots, length_scale=3.0)
    ref = np.zeros(l_mask.shape)
    for x, y in l_mask.pixels:
        for a, m in zip(acts, mots):
            d = abs(comcore.geometry.signed_line_distance([[x, y]], [a])[0, 0])
            ref[int(y), int(x)] += np.exp(-d / 3.0) * abs(m[0])
    vals = ref[l_mask.data]
    ref[l_mask.data] = (vals - vals.min()) / (vals.max() - vals.min())
    assert np.allclose(heat, ref, atol=1e-5)


@pytest.mark.parametrize("com", [(20, 30), (31, 14), (24.5, 24.5)])
def test_estimate_finds_the_calm_region_of_synthetic_pushes(square_mask, com):
    acts = grid_pushes(step=1)
    mots = synthetic_motions(square_mask, acts, com)
    est = comcore.estimate_heatmap(square_mask, acts, mots, length_scale=1.0, threshold=0.1)
    assert est.status == "unchecked" and not est.ok
    assert est.error_px(com) < 2.0
    assert est.used == tuple(range(len(acts)))
    assert est.com_m == pytest.approx(tuple(0.0025 * v for v in est.com))
    assert est.region.sum() > 0 and np.all(est.region <= square_mask.data)


def test_no_actions_and_flat_heatmap_fall_back_to_the_centroid(square_mask):
    est = comcore.estimate_heatmap(square_mask, np.zeros((0, 4)), np.zeros((0, 3)))
    assert est.status == "no_actions" and est.com == square_mask.centroid
    acts = grid_pushes()
    flat = comcore.estimate_heatmap(square_mask, acts, np.zeros((len(acts), 3)))
    assert flat.status == "flat_heatmap" and flat.com == square_mask.centroid


def test_estimate_heatmap_input_errors(square_mask):
    acts = grid_pushes()
    with pytest.raises(ValueError, match="expected 30, got 2"):
        comcore.estimate_heatmap(square_mask, acts, np.zeros((2, 3)))
    with pytest.raises(ValueError, match=r"threshold must be in \[0, 1\]"):
        comcore.estimate_heatmap(square_mask, acts, np.zeros((30, 3)), threshold=1.5)
    with pytest.raises(ValueError, match="length_scale must be a finite number > 0"):
        comcore.estimate_heatmap(square_mask, acts, np.zeros((30, 3)), length_scale=0)
    with pytest.raises(ValueError, match="miss"):
        comcore.estimate_heatmap(square_mask, [(0, 0, 5, 0)], [(0.1, 0, 0)])


def test_estimate_heatmap_does_not_mutate_inputs(square_mask):
    acts = grid_pushes()
    mots = synthetic_motions(square_mask, acts, (20, 30))
    a0, m0 = acts.copy(), mots.copy()
    comcore.estimate_heatmap(square_mask, acts, mots)
    assert np.array_equal(acts, a0) and np.array_equal(mots, m0)


@pytest.mark.parametrize("length_scale", [1e-40, 1e-3, 0.005])
def test_a_length_scale_that_underflows_float32_is_refused(square_mask, length_scale):
    # 1e-40 used to overflow (a RuntimeWarning) and 1e-3 to report a flat heat map silently.
    acts = grid_pushes()
    mots = synthetic_motions(square_mask, acts, (20, 30))
    with pytest.raises(ValueError, match=r"length_scale must be at least 0.005725 px.*underflows"):
        comcore.estimate_heatmap(square_mask, acts, mots, length_scale=length_scale)
    with pytest.raises(ValueError, match=r"length_scale must be at least 0.005725 px"):
        comcore.paper.rotation_heatmap(square_mask, acts, mots, length_scale=length_scale)


def test_the_smallest_length_scale_still_sees_lines_between_pixel_centres(square_mask):
    from comcore.paper._heatmap import MIN_LENGTH_SCALE_PX

    # Lines half a pixel from the nearest centres: every weight is exp(-0.5 / length_scale).
    acts = np.array([(0, r + 0.5, 50, r + 0.5) for r in range(10, 39, 2)], float)
    mots = synthetic_motions(square_mask, acts, (20, 30))
    heat = comcore.paper.rotation_heatmap(square_mask, acts, mots, length_scale=MIN_LENGTH_SCALE_PX)
    assert heat[square_mask.data].max() == 1.0  # not flat
    est = comcore.estimate_heatmap(square_mask, acts, mots, length_scale=MIN_LENGTH_SCALE_PX)
    assert est.status == "unchecked" and est.com[1] == pytest.approx(30, abs=1)


def test_alg1_is_never_ok_because_it_cannot_tell_wrong_motions_from_right_ones(square_mask):
    # The user's mistake: theta with the y-up sign (every sense flipped). The heat map
    # weighs |theta|, so it gives the very same answer; an "ok" would vouch for it.
    acts = grid_pushes(step=1)
    mots = synthetic_motions(square_mask, acts, (31, 14))
    flipped = mots * np.array([-1.0, 1.0, 1.0])
    right = comcore.estimate_heatmap(square_mask, acts, mots)
    wrong = comcore.estimate_heatmap(square_mask, acts, flipped)
    assert right.com == wrong.com
    assert right.status == wrong.status == "unchecked"
    assert not right.ok and not wrong.ok
