import numpy as np
import pytest

import comcore
from comcore import Action


def test_contact_on_a_square_edge(square_mask):
    c = comcore.contacts(square_mask, [Action(0, 20, 30, 20), Action(25, 60, 25, 30)])
    assert c.hit.tolist() == [True, True]
    assert np.allclose(c.point, [[9.5, 20.0], [25.0, 39.5]], atol=0.02)
    assert np.allclose(c.normal, [[1, 0], [0, -1]], atol=1e-6)
    assert np.allclose(c.travel, [9.5, 20.5], atol=0.02)


def test_contact_normal_is_robust_on_a_pixelated_circle(disk_mask):
    # An oblique approach onto the disk: the normal must point to the centre, not along a pixel step.
    angle = np.deg2rad(37)
    start = 26 + 40 * np.array([np.cos(angle), np.sin(angle)])
    c = comcore.contacts(disk_mask, [(*start, 26.0, 26.0)])
    expected = -np.array([np.cos(angle), np.sin(angle)])
    assert float(c.normal[0] @ expected) > np.cos(np.deg2rad(5))


def test_miss_and_start_inside_are_reported(square_mask):
    c = comcore.contacts(square_mask, [(0, 0, 5, 0), (20, 20, 60, 20), (0, 20, 40, 20)])
    assert c.status.tolist() == ["miss", "starts_inside", "hit"]
    assert np.allclose(c.normal[:2], 0)
    with pytest.raises(ValueError, match=r"action\(s\) \[1\] start inside"):
        c.require_hits()
    with pytest.raises(ValueError, match=r"action\(s\) \[0\] miss"):
        comcore.contacts(square_mask, [(0, 0, 5, 0)]).require_hits()


def test_first_entry_on_a_concave_shape(l_mask):
    # Along row 30 from the left: the L's foot is entered at column 5, not later.
    c = comcore.contacts(l_mask, [(0, 30, 45, 30)])
    assert c.point[0] == pytest.approx((4.5, 30.0), abs=0.02)


def test_signed_line_distance_sign_and_batch():
    d = comcore.signed_line_distance([[0, -1], [0, 1], [3, 0]], [(0, 0, 1, 0), (0, 0, 0, 1)])
    # push right: the row above (y=-1) is on the CCW side; push down: +x is on the CCW side.
    assert d.tolist() == [[1.0, 0.0], [-1.0, 0.0], [0.0, 3.0]]


def test_split_by_line_excludes_the_band(square_mask):
    ccw, cw = comcore.split_by_line(square_mask, (0, 24, 50, 24), band=0.5)
    assert ccw.sum() == 14 * 30 and cw.sum() == 15 * 30
    assert not (ccw & cw).any()
    assert not ccw[24].any() and not cw[24].any()
    ccw2, cw2 = comcore.split_by_line(square_mask, (0, 24, 50, 24), band=0.0)
    assert ccw2.sum() + cw2.sum() == 870  # row 24 lies exactly on the line


def test_split_by_line_rejects_batches_and_bad_band(square_mask):
    with pytest.raises(ValueError, match="single action"):
        comcore.split_by_line(square_mask, [(0, 0, 1, 0), (0, 0, 0, 1)])
    with pytest.raises(ValueError, match="band must be a finite number >= 0"):
        comcore.split_by_line(square_mask, (0, 0, 1, 0), band=-1)


def test_contacts_do_not_mutate_inputs(square_mask):
    acts = np.array([[0.0, 20.0, 30.0, 20.0]])
    before = acts.copy()
    comcore.contacts(square_mask, acts)
    assert np.array_equal(acts, before)


@pytest.mark.parametrize("band", [0.0, 0.5, 2.0])
def test_side_counts_match_a_direct_distance_count(band):
    """Row prefix sums count the same pixels as thresholding every pixel's distance."""
    from comcore._geometry import line_distances, side_counts

    rng = np.random.default_rng(7)
    image = rng.random((37, 53)) < 0.6
    actions = rng.uniform(-10, 60, (40, 4))
    actions[:5, 3] = actions[:5, 1]  # horizontal lines: constant distance along a row
    actions[5:10, 2] = actions[5:10, 0]  # vertical lines
    ys, xs = np.nonzero(image)
    d = line_distances(np.column_stack([xs, ys]).astype(float), actions)
    ccw, cw = side_counts(image, actions, band)
    np.testing.assert_array_equal(ccw, (d > band).sum(axis=0))
    np.testing.assert_array_equal(cw, (d < -band).sum(axis=0))
    empty = side_counts(np.zeros_like(image), actions, band)
    assert not empty[0].any() and not empty[1].any()


def test_march_covers_only_the_image_so_a_far_start_costs_nothing(square_mask):
    # A start 1e9 px away used to allocate a 4e9-step march (29.8 GiB, MemoryError).
    from comcore._geometry import BISECTION_STEPS, MARCH_STEP_PX

    far = comcore.contacts(
        square_mask, [(-1e9, 20, 40, 20), (-1e9, 20 - 0.3e9, 40, 32), (25, 1e9, 25, 30)]
    )
    near = comcore.contacts(square_mask, [(-10, 20, 40, 20), (-10, 17, 40, 32), (25, 60, 25, 30)])
    assert far.hit.all()
    # Horizontal: the far start lies on the near march's grid (1e9 - 10 is a multiple of
    # 0.25 px), so the contact is the same to the bit; otherwise within the bisection step.
    assert np.array_equal(far.point[0], near.point[0])
    np.testing.assert_allclose(far.point, near.point, atol=MARCH_STEP_PX / 2**BISECTION_STEPS)
    np.testing.assert_array_equal(far.normal, near.normal)
    assert far.travel[0] == pytest.approx(1e9 + 9.5, abs=0.01)
    # A path that never comes near the image, however long, is a miss.
    assert comcore.contacts(square_mask, [(-1e9, -5, 1e9, -5)]).status.tolist() == ["miss"]


def _full_march_contacts(mask, actions):
    """The march over the whole path, as before clipping to the image (the reference)."""
    from comcore._geometry import BISECTION_STEPS, MARCH_STEP_PX

    start, end = actions[:, :2], actions[:, 2:]
    length = np.hypot(*(end - start).T)
    direction = (end - start) / length[:, None]
    n_steps = int(np.ceil(length.max() / MARCH_STEP_PX)) + 1
    t = np.minimum(np.arange(n_steps)[None, :] * MARCH_STEP_PX, length[:, None])
    samples = start[:, None, :] + t[..., None] * direction[:, None, :]
    inside = mask.contains(samples.reshape(-1, 2)).reshape(len(actions), n_steps)
    hit = inside.any(axis=1) & ~inside[:, 0]
    first = np.argmax(inside, axis=1)
    rows = np.arange(len(actions))
    lo = np.where(hit, t[rows, np.maximum(first - 1, 0)], 0.0)
    hi = np.where(hit, t[rows, first], 0.0)
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        inn = mask.contains(start + mid[:, None] * direction)
        hi, lo = np.where(inn, mid, hi), np.where(inn, lo, mid)
    return hit, inside[:, 0], np.where(hit, 0.5 * (lo + hi), 0.0)


@pytest.mark.parametrize("fixture", ["square_mask", "disk_mask", "l_mask"])
def test_clipped_march_finds_the_same_contacts_as_the_full_march(fixture, request):
    mask = request.getfixturevalue(fixture)
    rng = np.random.default_rng(3)
    h, w = mask.shape
    actions = rng.uniform(-15, max(h, w) + 15, (600, 4))
    actions[:100, 3] = actions[:100, 1]  # horizontal and vertical paths
    actions[100:200, 2] = actions[100:200, 0]
    actions[200:300] = np.round(actions[200:300])  # starts and ends on pixel centres
    actions = np.vstack([actions, comcore.sample_pushes(mask, 100, cone=0.8, rng=4)])
    hit, starts_inside, travel = _full_march_contacts(mask, actions)
    c = comcore.contacts(mask, actions)
    assert hit.sum() > 100 and starts_inside.sum() > 20  # both cases are exercised
    np.testing.assert_array_equal(c.hit, hit)
    np.testing.assert_array_equal(c.starts_inside, starts_inside)
    np.testing.assert_array_equal(c.travel, travel)  # to the bit
