import numpy as np
import pytest

import comcore
from comcore import Action


def test_contact_on_a_square_edge(square_mask):
    c = comcore.geometry.contacts(square_mask, [Action(0, 20, 30, 20), Action(25, 60, 25, 30)])
    assert c.hit.tolist() == [True, True]
    assert np.allclose(c.point, [[9.5, 20.0], [25.0, 39.5]], atol=0.02)
    assert np.allclose(c.normal, [[1, 0], [0, -1]], atol=1e-6)
    assert np.allclose(c.travel, [9.5, 20.5], atol=0.02)


def test_contact_normal_is_robust_on_a_pixelated_circle(disk_mask):
    # An oblique approach onto the disk: the normal must point to the centre, not along a pixel step.
    angle = np.deg2rad(37)
    start = 26 + 40 * np.array([np.cos(angle), np.sin(angle)])
    c = comcore.geometry.contacts(disk_mask, [(*start, 26.0, 26.0)])
    expected = -np.array([np.cos(angle), np.sin(angle)])
    assert float(c.normal[0] @ expected) > np.cos(np.deg2rad(5))


def test_miss_and_start_inside_are_reported(square_mask):
    c = comcore.geometry.contacts(square_mask, [(0, 0, 5, 0), (20, 20, 60, 20), (0, 20, 40, 20)])
    assert c.status.tolist() == ["miss", "starts_inside", "hit"]
    assert np.allclose(c.normal[:2], 0)
    with pytest.raises(ValueError, match=r"action\(s\) \[1\] start inside"):
        c.require_hits()
    with pytest.raises(ValueError, match=r"action\(s\) \[0\] miss"):
        comcore.geometry.contacts(square_mask, [(0, 0, 5, 0)]).require_hits()


def test_first_entry_on_a_concave_shape(l_mask):
    # Along row 30 from the left: the L's foot is entered at column 5, not later.
    c = comcore.geometry.contacts(l_mask, [(0, 30, 45, 30)])
    assert c.point[0] == pytest.approx((4.5, 30.0), abs=0.02)


def test_signed_line_distance_sign_and_batch():
    d = comcore.geometry.signed_line_distance([[0, -1], [0, 1], [3, 0]], [(0, 0, 1, 0), (0, 0, 0, 1)])
    # push right: the row above (y=-1) is on the CCW side; push down: +x is on the CCW side.
    assert d.tolist() == [[1.0, 0.0], [-1.0, 0.0], [0.0, 3.0]]


def test_split_by_line_excludes_the_band(square_mask):
    ccw, cw = comcore.geometry.split_by_line(square_mask, (0, 24, 50, 24), band=0.5)
    assert ccw.sum() == 14 * 30 and cw.sum() == 15 * 30
    assert not (ccw & cw).any()
    assert not ccw[24].any() and not cw[24].any()
    ccw2, cw2 = comcore.geometry.split_by_line(square_mask, (0, 24, 50, 24), band=0.0)
    assert ccw2.sum() + cw2.sum() == 870  # row 24 lies exactly on the line


def test_split_by_line_rejects_batches_and_bad_band(square_mask):
    with pytest.raises(ValueError, match="single action"):
        comcore.geometry.split_by_line(square_mask, [(0, 0, 1, 0), (0, 0, 0, 1)])
    with pytest.raises(ValueError, match="band must be a finite number >= 0"):
        comcore.geometry.split_by_line(square_mask, (0, 0, 1, 0), band=-1)


def test_contacts_do_not_mutate_inputs(square_mask):
    acts = np.array([[0.0, 20.0, 30.0, 20.0]])
    before = acts.copy()
    comcore.geometry.contacts(square_mask, acts)
    assert np.array_equal(acts, before)


@pytest.mark.parametrize("band", [0.0, 0.5, 2.0])
def test_side_counts_match_a_direct_distance_count(band):
    """Row prefix sums count the same pixels as thresholding every pixel's distance."""
    from comcore.geometry._contacts import line_distances, side_counts

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
    from comcore.geometry._contacts import BISECTION_STEPS, MARCH_STEP_PX

    far = comcore.geometry.contacts(
        square_mask, [(-1e9, 20, 40, 20), (-1e9, 20 - 0.3e9, 40, 32), (25, 1e9, 25, 30)]
    )
    near = comcore.geometry.contacts(square_mask, [(-10, 20, 40, 20), (-10, 17, 40, 32), (25, 60, 25, 30)])
    assert far.hit.all()
    # Horizontal: the far start lies on the near march's grid (1e9 - 10 is a multiple of
    # 0.25 px), so the contact is the same to the bit; otherwise within the bisection step.
    assert np.array_equal(far.point[0], near.point[0])
    np.testing.assert_allclose(far.point, near.point, atol=MARCH_STEP_PX / 2**BISECTION_STEPS)
    np.testing.assert_array_equal(far.normal, near.normal)
    assert far.travel[0] == pytest.approx(1e9 + 9.5, abs=0.01)
    # A path that never comes near the image, however long, is a miss.
    assert comcore.geometry.contacts(square_mask, [(-1e9, -5, 1e9, -5)]).status.tolist() == ["miss"]


def _full_march_contacts(mask, actions):
    """The march over the whole path, as before clipping to the image (the reference)."""
    from comcore.geometry._contacts import BISECTION_STEPS, MARCH_STEP_PX

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
    c = comcore.geometry.contacts(mask, actions)
    assert hit.sum() > 100 and starts_inside.sum() > 20  # both cases are exercised
    np.testing.assert_array_equal(c.hit, hit)
    np.testing.assert_array_equal(c.starts_inside, starts_inside)
    np.testing.assert_array_equal(c.travel, travel)  # to the bit


# -- disc_contacts: the contact of a round pusher ---------------------------------------------


def test_disc_contact_head_on_agrees_with_the_leading_line(square_mask, disk_mask):
    # Head on (along the normal), the disc's leading point is the contact: both agree to a pixel.
    pushes = [(0, 20, 30, 20), (25, 60, 25, 30), (45, 33, 20, 33)]
    for mask, acts in ((square_mask, pushes), (disk_mask, [(26, 60, 26, 20), (-10, 26, 20, 26)])):
        line = comcore.geometry.contacts(mask, acts)
        disc = comcore.geometry.disc_contacts(mask, acts, 0.00475)
        assert disc.hit.all() and line.hit.all()
        assert np.abs(disc.point - line.point).max() < 1.0
        assert np.abs(disc.travel - line.travel).max() < 1.0
        assert (np.einsum("ij,ij->i", disc.normal, line.normal) > np.cos(np.deg2rad(5))).all()


def test_disc_contact_of_a_grazing_push_the_leading_line_misses(square_mask):
    # Square pixels 10..39 (outline at 9.5 and 39.5); a push onto the top edge, down-right at
    # 70 deg to its normal, whose leading point passes 1.2 px beyond the top-right corner: the
    # line misses; the 4.75 mm (1.9 px) disc's underside lands on the top edge just before the
    # corner, where its centre is 1.9 px above the edge.
    r_px = 0.00475 / square_mask.resolution
    direction = np.array([np.sin(np.deg2rad(70)), np.cos(np.deg2rad(70))])  # right, down
    across = np.array([direction[1], -direction[0]])  # perpendicular, away from the square
    corner = np.array([39.5, 9.5])
    through = corner + 1.2 * across  # the line passes 1.2 px from the corner, outside
    start, end = through - 20 * direction, through + 12 * direction
    push = [(*start, *end)]
    assert comcore.geometry.contacts(square_mask, push).status.tolist() == ["miss"]
    disc = comcore.geometry.disc_contacts(square_mask, push, 0.00475)
    assert disc.status.tolist() == ["hit"]
    centre_y = 9.5 - r_px  # the disc's centre when it lands; its x on the line:
    centre_x = through[0] + (centre_y - through[1]) * direction[0] / direction[1]
    assert 37.0 < centre_x < 39.0
    assert np.hypot(*(disc.point[0] - (centre_x, 9.5))) < 0.5
    assert float(disc.normal[0] @ (0.0, 1.0)) > np.cos(np.deg2rad(5))  # the edge's, into it
    centre = start - r_px * direction + disc.travel[0] * direction
    assert np.hypot(*(centre - (centre_x, centre_y))) < 0.5
    # Straight down 1 px beside the right edge: the disc meets the corner itself, and the normal
    # is the direction from its centre to the corner, not the edge's.
    down = [(40.5, 0.0, 40.5, 20.0)]
    assert not comcore.geometry.contacts(square_mask, down).hit[0]
    corner_hit = comcore.geometry.disc_contacts(square_mask, down, 0.00475)
    centre = np.array([40.5, 9.5 - np.sqrt(r_px**2 - 1.0)])
    expected = (corner - centre) / r_px
    assert corner_hit.hit[0] and np.hypot(*(corner_hit.point[0] - corner)) < 1.0
    assert float(corner_hit.normal[0] @ expected) > np.cos(np.deg2rad(15))
    # A point pusher on the same path misses too, and a smaller disc misses.
    assert not comcore.geometry.disc_contacts(square_mask, push, 0.0).hit[0]
    assert not comcore.geometry.disc_contacts(square_mask, push, 0.001).hit[0]


def test_disc_contacts_match_the_exact_polygon_contact_to_a_pixel():
    # The simulator's contact is exact on the polygon; on its mask the disc's agrees to a pixel,
    # for pushes head on and up to 80 deg off the normal, including ones the line misses.
    pytest.importorskip("shapely")  # the simulators need comcore[sim]
    simulators = pytest.importorskip("simulators")
    sim = simulators.PushSimulator.from_polygon(
        [(0, 0), (0.09, 0), (0.09, 0.06), (0.03, 0.075), (0, 0.05)], pusher_radius=0.00475
    )
    acts = comcore.sample_pushes(sim.mask, 60, cone=np.deg2rad(80), rng=3)
    line_hits = comcore.geometry.contacts(sim.mask, acts).hit
    # Shift every push sideways by up to 3 px: some leading lines now miss the mask.
    rng = np.random.default_rng(0)
    d = acts[:, 2:] - acts[:, :2]
    side = np.column_stack([d[:, 1], -d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None]
    shift = rng.uniform(-3, 3, len(acts))[:, None] * side
    acts = acts + np.hstack([shift, shift])
    disc = comcore.geometry.disc_contacts(sim.mask, acts, sim.pusher_radius)
    exact = sim.push_many(acts)
    hit = np.array([r.contact_px is not None for r in exact])
    assert line_hits.all() and not comcore.geometry.contacts(sim.mask, acts).hit.all()
    assert hit.sum() > 50 and (~hit).any()
    # Hit or miss agree wherever the exact disc clears or overlaps the outline by a pixel.
    def hits(radius):
        other = simulators.PushSimulator(sim.shape, sim.mass, pusher_radius=radius)
        return np.array([r.contact_px is not None for r in other.push_many(acts)])

    sure = hits(sim.pusher_radius + sim.resolution) == hits(sim.pusher_radius - sim.resolution)
    assert sure.sum() >= 55 and np.array_equal(disc.hit[sure], hit[sure])
    both = disc.hit & hit
    points = np.array([r.contact_px for r, b in zip(exact, both) if b])
    assert np.hypot(*(disc.point[both] - points).T).max() < 1.0


def test_disc_contacts_report_misses_and_starts_inside_in_one_batch(square_mask):
    acts = [(0, 0, 5, 0), (20, 20, 60, 20), (0, 20, 40, 20), (0, 7.5, 50, 7.5)]
    disc = comcore.geometry.disc_contacts(square_mask, acts, 0.00475)
    # The last runs 2 px above the top edge (row 9.5): the 1.9 px disc grazes it... not quite.
    assert disc.status.tolist() == ["miss", "starts_inside", "hit", "miss"]
    assert np.allclose(disc.normal[[0, 1, 3]], 0) and np.allclose(disc.point[0], (0, 0))
    each = [comcore.geometry.disc_contacts(square_mask, [a], 0.00475) for a in acts]
    assert np.allclose(disc.point, np.vstack([c.point for c in each]))
    assert np.allclose(disc.travel, [c.travel[0] for c in each])
    wide = comcore.geometry.disc_contacts(square_mask, acts[3:], 0.006)  # 2.4 px: it touches
    assert wide.hit.tolist() == [True]


def test_disc_contacts_cost_does_not_grow_with_the_path(square_mask):
    far = comcore.geometry.disc_contacts(square_mask, [(-1e7, 20, 1e7, 20)], 0.00475)
    near = comcore.geometry.disc_contacts(square_mask, [(0, 20, 40, 20)], 0.00475)
    assert far.hit[0] and np.allclose(far.point, near.point, atol=1e-3)


def test_disc_contacts_validate_the_radius(square_mask):
    with pytest.raises(TypeError, match="pusher_radius"):
        comcore.geometry.disc_contacts(square_mask, [(0, 20, 40, 20)], "4 mm")
    with pytest.raises(ValueError, match="pusher_radius must be a finite number >= 0"):
        comcore.geometry.disc_contacts(square_mask, [(0, 20, 40, 20)], float("nan"))
