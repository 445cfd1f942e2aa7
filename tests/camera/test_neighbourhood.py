"""The object's neighbourhood (comcore/_neighbourhood.py): the same numbers as the whole frame.

Each per-mask field that is now computed on a window around the object is
compared, bit for bit, with the whole-frame computation it replaces (written
out here as it was), at points near the object (the window as first made),
across the frame and beyond it (the window grown), on small objects in wide
frames and on objects that touch the frame's border.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

import comcore
import comcore._neighbourhood as neighbourhood
from comcore._mask import NORMAL_SMOOTHING_PX
from comcore._neighbourhood import LocalArrays, Window, margin_px, padded_crop
from comcore.geometry._disc_contacts import FIELD_PAD_PX, SDF_SMOOTHING_PX, OutlineField
from comcore.motion._lattice import PushLattice, _memo, _table_step, pressure_table, table_pressures
from comcore.motion._limit_surface import _on_object
from comcore.motion._pressure import pressures, support
from simulators.frames import star_polygon


def wide_mask(seed, shape=(300, 520), share=0.004, resolution=0.001, corner=False):
    """A star-shaped object of ``share`` of a wide frame, somewhere in it (or over a corner)."""
    rng = np.random.default_rng(seed)
    h, w = shape
    poly = star_polygon(rng, share * h * w)
    if corner:
        poly = poly + np.array([w - 5.0, 3.0])  # cut by the top and right borders
    else:
        reach = np.abs(poly).max() + 2
        poly = poly + rng.uniform([reach, reach], [w - reach, h - reach])
    return comcore.Mask(comcore.geometry.rasterise_polygon(poly, shape), resolution=resolution)


MASKS = [
    wide_mask(0),
    wide_mask(1, resolution=0.0025),
    wide_mask(2, share=0.0005),
    wide_mask(3, corner=True),
    wide_mask(4, shape=(90, 70), share=0.2),  # the object fills much of a small image
    wide_mask(5, resolution=0.04),  # a coarse camera: a margin of two pixels
]


def points_near_and_far(mask, seed, n=400):
    """Points over the object's box and 40 px round it, then over the frame and beyond it."""
    rng = np.random.default_rng(seed)
    h, w = mask.shape
    rows, cols = np.nonzero(mask.data)
    near = rng.uniform(
        [cols.min() - 40, rows.min() - 40], [cols.max() + 40, rows.max() + 40], (n, 2)
    )
    far = rng.uniform([-60.0, -60.0], [w + 60.0, h + 60.0], (n, 2))
    whole = np.array([[0.0, 0.0], [w - 1.0, h - 1.0], [w + 0.3, -0.7], [12.5, h - 1.5]])
    return near, np.vstack([far, whole])


# -- the whole-frame computations as they were -----------------------------------------


class WholeOutlineField:
    """OutlineField's fields on the whole padded frame (comcore before the neighbourhood)."""

    def __init__(self, mask, pad=FIELD_PAD_PX):
        img = np.pad(mask.data, pad)
        outside = ndimage.distance_transform_edt(~img)
        inside = ndimage.distance_transform_edt(img)
        sdf = ndimage.gaussian_filter(
            np.where(img, 0.5 - inside, outside - 0.5), SDF_SMOOTHING_PX, mode="nearest"
        )
        gy, gx = np.gradient(sdf)
        self.pad, self._fields = pad, (sdf, gx, gy)
        self.shape = mask.shape  # the mask image's (rows, columns), as OutlineField.shape

    def sample(self, x, y):
        shape = np.shape(x)
        coords = np.vstack([np.ravel(y) + self.pad, np.ravel(x) + self.pad])
        d, gx, gy = (
            ndimage.map_coordinates(f, coords, order=1, mode="nearest") for f in self._fields
        )
        norm = np.maximum(np.hypot(gx, gy), 1e-12)
        return d.reshape(shape), (gx / norm).reshape(shape), (gy / norm).reshape(shape)

    def distance(self, x, y):
        return self.sample(x, y)[0]

    def first_touch(self, origin, unit, t, radius, rows=None):
        """Every step of every path read (OutlineField.first_touch stops a path at its touch)."""
        px, py = origin[:, :1] + t * unit[:, :1], origin[:, 1:] + t * unit[:, 1:]
        touching = self.distance(px, py) <= radius[:, None]
        if rows is not None:
            touching &= rows[:, None]
        return np.argmax(touching, axis=1), touching.any(axis=1)


def whole_inward_normals(mask, points):
    pad = int(4 * NORMAL_SMOOTHING_PX) + 2
    smooth = ndimage.gaussian_filter(
        np.pad(mask.data.astype(float), pad), NORMAL_SMOOTHING_PX, mode="constant"
    )
    gy, gx = np.gradient(smooth)
    coords = np.vstack([points[:, 1] + pad, points[:, 0] + pad])
    nx = ndimage.map_coordinates(gx, coords, order=1, mode="constant")
    ny = ndimage.map_coordinates(gy, coords, order=1, mode="constant")
    v, norm = np.column_stack([nx, ny]), np.hypot(nx, ny)
    good = norm > 1e-9
    v[good] /= norm[good, None]
    v[~good] = 0.0
    return v


def whole_distance_to_object(mask, p):
    h, w = mask.shape
    col = np.clip(np.floor(p[:, 0] + 0.5), 0, w - 1)
    row = np.clip(np.floor(p[:, 1] + 0.5), 0, h - 1)
    off = np.hypot(p[:, 0] - col, p[:, 1] - row)
    far = ndimage.distance_transform_edt(~mask.data)
    return far[row.astype(int), col.astype(int)] + np.where(
        (col == np.floor(p[:, 0] + 0.5)) & (row == np.floor(p[:, 1] + 0.5)), 0.0, off
    )


def whole_on_object(mask, points):
    h, w = mask.shape
    rows = np.clip(np.rint(points[:, 1]).astype(np.intp), 0, h - 1)
    cols = np.clip(np.rint(points[:, 0]).astype(np.intp), 0, w - 1)
    exact = (rows == np.rint(points[:, 1])) & (cols == np.rint(points[:, 0]))
    near_r, near_c = ndimage.distance_transform_edt(
        ~mask.data, return_distances=False, return_indices=True
    )
    moved = np.column_stack([near_c[rows, cols], near_r[rows, cols]]).astype(float)
    return np.where((mask.data[rows, cols] & exact)[:, None], points, moved)


# -- the window itself ------------------------------------------------------------------


def test_margin_covers_a_push_and_the_pusher():
    # standoff 1.2 cm + a 5 cm pusher's reach is not needed together; 3 cm travel + 1.2 cm is
    assert margin_px(0.001) * 0.001 >= 0.03 + 0.012 + 0.004
    assert margin_px(0.5) == 1  # never below a pixel


@pytest.mark.parametrize("pad", [0, 3, 24])
def test_padded_crop_is_the_crop_of_the_padded_image(pad):
    data = np.random.default_rng(0).random((17, 23)) > 0.6
    padded = np.pad(data, pad)
    for lo, hi in [((0, 0), padded.shape), ((2, 5), (9, 30)), ((pad, pad), (pad + 4, pad + 2))]:
        hi = (min(hi[0], padded.shape[0]), min(hi[1], padded.shape[1]))
        win = Window(lo, hi, padded.shape)
        np.testing.assert_array_equal(padded_crop(data, pad, win), win.crop(padded))


def test_window_exact_part_keeps_the_image_border():
    win = Window((0, 5), (20, 30), (20, 40))
    assert win.exact(3) == ((0, 8), (20, 27))  # the top and bottom are the image's own
    assert win.covers([0, 19], [8, 26], halo=3) and not win.covers([0], [27], halo=3)


def test_local_arrays_grow_only_when_asked_outside():
    image = np.zeros((50, 80), bool)
    image[20:24, 30:35] = True
    calls = []

    def make(win):
        calls.append(win)
        return (ndimage.distance_transform_edt(~win.crop(image)),)

    local = LocalArrays(Window.around(image, 4), make, margin=2)
    whole = ndimage.distance_transform_edt(~image)
    assert local.at([21, 16], [32, 38])[0].tolist() == whole[[21, 16], [32, 38]].tolist()
    assert len(calls) == 1
    assert local.at([49], [0])[0][0] == whole[49, 0]
    assert len(calls) == 2 and calls[-1].lo == (16, 0) and calls[-1].hi == (50, 39)


# -- each field against the whole frame -------------------------------------------------


@pytest.mark.parametrize("k", range(len(MASKS)))
def test_outline_field_matches_the_whole_frame(k):
    mask = MASKS[k]
    near, far = points_near_and_far(mask, k)
    whole = WholeOutlineField(mask)
    for pad in (FIELD_PAD_PX, 40):
        local, ref = OutlineField(mask, pad=pad), WholeOutlineField(mask, pad=pad)
        for pts in (near, far):
            for a, b in zip(local.sample(pts[:, 0], pts[:, 1]), ref.sample(pts[:, 0], pts[:, 1])):
                np.testing.assert_array_equal(a, b)
    # the pushes' contacts: the march along each path samples the field all the way
    pushes = comcore.sample_pushes(mask, 24, rng=k)
    field = OutlineField(mask)
    for radius in (0.0, 4.0):
        got, want = (
            outcome(field.pusher_paths, pushes, radius),
            outcome(OutlineField.pusher_paths, whole, pushes, radius),
        )
        assert type(got) is type(want)
        if isinstance(want, Exception):  # a push that starts inside the object
            assert str(got) == str(want)
        else:
            for a, b in zip(got, want):
                np.testing.assert_array_equal(a, b)


def outcome(f, *args):
    """``f(*args)``, or the ValueError it raised."""
    try:
        return f(*args)
    except ValueError as e:
        return e


@pytest.mark.parametrize("k", range(len(MASKS)))
def test_mask_fields_match_the_whole_frame(k):
    mask = MASKS[k]
    near, far = points_near_and_far(mask, 10 + k)
    fresh = comcore.Mask(mask.data, resolution=mask.resolution)  # asked far first: no cache
    for m in (mask, fresh):
        for pts in (near, far) if m is mask else (far, near):
            np.testing.assert_array_equal(m.inward_normals(pts), whole_inward_normals(m, pts))
            np.testing.assert_array_equal(
                m.distance_to_object(pts), whole_distance_to_object(m, pts)
            )


@pytest.mark.parametrize("k", range(len(MASKS)))
def test_nearest_object_pixel_matches_the_whole_frame(k):
    mask = MASKS[k]
    near, far = points_near_and_far(mask, 20 + k)
    for pts in (near, np.rint(near), far):
        np.testing.assert_array_equal(_on_object(mask, pts), whole_on_object(mask, pts))


def test_nearest_object_pixel_keeps_the_whole_frames_ties():
    # a square and a ring: many pixels with two or more nearest object pixels
    image = np.zeros((200, 300), bool)
    image[90:100, 140:150] = True
    image[40:60, 240:260] = True
    image[45:55, 245:255] = False
    mask = comcore.Mask(image, resolution=0.001)
    rows, cols = np.mgrid[0:200:3, 0:300:3]
    pts = np.column_stack([cols.ravel(), rows.ravel()]).astype(float)
    np.testing.assert_array_equal(_on_object(mask, pts), whole_on_object(mask, pts))


#: How closely two solves of the exponential tilt agree (see the test below).
TILT_ATOL = 1e-8


@pytest.mark.parametrize("k", [0, 1, 3])
def test_pressure_table_matches_the_whole_frame(k):
    mask = comcore.Mask(MASKS[k].data, resolution=MASKS[k].resolution)  # nothing cached
    model = comcore.LimitSurfaceModel(pusher_radius=0.004)
    sup = support(mask, model.support_points)
    step = _table_step(mask)
    h, w = mask.shape
    ni, nj = int(np.ceil((w - 1) / step)) + 2, int(np.ceil((h - 1) / step)) + 2
    ii, jj = np.meshgrid(np.arange(ni), np.arange(nj), indexing="ij")
    grid = step * np.column_stack([ii.ravel(), jj.ravel()]).astype(float)
    rel = whole_on_object(mask, grid) - np.asarray(mask.centroid)
    for spread in ("tilted", "linear"):
        whole = pressures(sup, rel, spread).reshape(ni, nj, -1)
        table = pressure_table(
            mask, (spread, "test"), lambda m, p, s=spread: model._pressures(m, p, s)
        )
        assert not table.window.whole  # the first window is the neighbourhood
        (values,), _ = table.local([table.window.lo[0]], [table.window.lo[1]])
        # a node is its own row, up to the exponential tilt's stopping rule: its Newton steps
        # stop once the mean is within 1e-9 px of the CoM, and the rows solved in another batch
        # (BLAS rounding differs with the batch) may stop one step apart: pressures (which sum
        # to 1) then agree to about 1e-8, not to the last bit
        np.testing.assert_allclose(values, table.window.crop(whole), rtol=1e-12, atol=TILT_ATOL)
        near, far = points_near_and_far(mask, 30 + k)
        for pts in (near, far):
            pts = np.clip(pts, 0, None)
            got = table_pressures(table, pts, step)
            cell = np.clip(pts / step, 0.0, np.array([ni, nj]) - 1 - 1e-9)
            lo = np.floor(cell).astype(np.intp)
            f = cell - lo
            i, j, fx, fy = lo[:, 0], lo[:, 1], f[:, :1], f[:, 1:]
            want = (
                whole[i, j] * (1 - fx) * (1 - fy) + whole[i, j + 1] * (1 - fx) * fy
                + whole[i + 1, j] * fx * (1 - fy) + whole[i + 1, j + 1] * fx * fy
            )  # fmt: skip
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=TILT_ATOL)  # as above


# -- the session: what a caller sees ----------------------------------------------------


def session_run(first, second):
    session = comcore.ActiveSession(first, pusher_radius=0.004, rng=0)
    pushes = [session.next_push()]
    session.observe(second)
    pushes.append(session.next_push())
    return pushes, session.estimate()


def test_session_on_a_wide_frame_is_the_whole_frames(monkeypatch):
    first = wide_mask(7, shape=(360, 640), share=0.004)
    moved = comcore.apply_motion(first.pixels, 0.05, (3.0, -2.0), first.centroid)
    image = np.zeros(first.shape, bool)
    image[np.rint(moved[:, 1]).astype(int), np.rint(moved[:, 0]).astype(int)] = True
    second = comcore.Mask(ndimage.binary_closing(image), resolution=first.resolution)
    pushes, est = session_run(first, second)
    # the same session with a neighbourhood larger than the frame: the whole-frame fields
    monkeypatch.setattr(neighbourhood, "NEIGHBOURHOOD_MARGIN_M", 100.0)
    first_w = comcore.Mask(first.data, resolution=first.resolution)
    second_w = comcore.Mask(second.data, resolution=second.resolution)
    assert Window.around(first_w.data, margin_px(first_w.resolution)).whole
    pushes_w, est_w = session_run(first_w, second_w)
    assert pushes == pushes_w
    np.testing.assert_allclose(est.com, est_w.com, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(est.region, est_w.region)
    np.testing.assert_allclose(est.posterior.image, est_w.posterior.image, atol=1e-12)


def points_at_the_edges(window, pad, seed, n=600):
    """Image points inside the window, within 10 px of its edges (window on the padded image).

    Asked alone, they would not grow a window that forgot its filters' reach.
    """
    rng = np.random.default_rng(seed)
    (r0, c0), (r1, c1) = window.lo, window.hi
    r0, c0, r1, c1 = r0 - pad, c0 - pad, r1 - pad - 1, c1 - pad - 1
    x, y, band = rng.uniform(c0, c1, n), rng.uniform(r0, r1, n), rng.uniform(0, 10, n)
    side = rng.integers(4, size=n)
    x = np.where(side == 0, c0 + band, np.where(side == 1, c1 - band, x))
    y = np.where(side == 2, r0 + band, np.where(side == 3, r1 - band, y))
    return np.column_stack([x, y])


@pytest.mark.parametrize("k", range(len(MASKS)))
def test_fields_are_exact_at_the_windows_cut_edges(k):
    # where a filter's support crosses the window's edge the window must grow first
    mask = MASKS[k]
    field, whole = OutlineField(mask), WholeOutlineField(mask)
    pts = points_at_the_edges(field._local.window, field.pad, k)
    for a, b in zip(field.sample(pts[:, 0], pts[:, 1]), whole.sample(pts[:, 0], pts[:, 1])):
        np.testing.assert_array_equal(a, b)
    fresh = comcore.Mask(mask.data, resolution=mask.resolution)
    pts = points_at_the_edges(fresh._inward_field.window, int(4 * NORMAL_SMOOTHING_PX) + 2, k)
    np.testing.assert_array_equal(fresh.inward_normals(pts), whole_inward_normals(fresh, pts))


@pytest.mark.parametrize("k", range(len(MASKS)))
def test_pixels_and_boundary_match_the_whole_frame(k):
    mask = MASKS[k]
    data = mask.data
    rows, cols = np.nonzero(data)
    np.testing.assert_array_equal(mask.pixels, np.column_stack([cols, rows]).astype(float))
    np.testing.assert_array_equal(
        mask.boundary, data & ~ndimage.binary_erosion(data, border_value=0)
    )
    full = comcore.Mask(np.ones((5, 7), bool))  # the object is the whole image
    np.testing.assert_array_equal(full.boundary, ~ndimage.binary_erosion(full.data, border_value=0))


@pytest.mark.parametrize("k", range(len(MASKS)))
def test_outline_pixels_of_sample_pushes_match_the_whole_frame(k):
    # the outline pixels drawn from: the box's, in the whole frame's order
    mask = MASKS[k]
    np.testing.assert_array_equal(
        neighbourhood.true_pixels(mask.boundary, mask._box), comcore.conventions.pixel_centres(mask.boundary)
    )


def test_push_lattice_on_the_neighbourhood_is_part_of_the_whole_ones():
    mask = MASKS[0]
    push = comcore.sample_pushes(mask, 1, rng=3)[0]
    whole = PushLattice(mask, push, 0.01)
    near = PushLattice(mask, push, 0.01, mask._box.grown_by(margin_px(mask.resolution)))
    assert len(near.points) < len(whole.points) / 10
    np.testing.assert_array_equal(near.points, whole.points[near.whole_ids()])
    pts = np.vstack([mask.pixels, mask.pixels + 0.37])
    (c_near, w_near, used_near), (c_whole, w_whole, used_whole) = near.cells(pts), whole.cells(pts)
    np.testing.assert_array_equal(near.whole_ids()[c_near], c_whole)
    np.testing.assert_array_equal(w_near, w_whole)
    np.testing.assert_array_equal(near.whole_ids()[used_near], used_whole)
    far = np.array([[1.0, 1.0], [mask.shape[1] - 2.0, 5.0]])
    assert near.cells(np.vstack([pts, far])) is None and whole.cells(far) is not None


def model_calls(mask):
    """Motions of one push for hypotheses on the object, then some far off it, then again."""
    model = comcore.LimitSurfaceModel(pusher_radius=0.004)
    push = comcore.sample_pushes(mask, 1, rng=4)
    h, w = mask.shape
    far = np.vstack([mask.pixels, [[2.0, 2.0], [w - 3.0, h - 3.0], [w / 2, 1.0]]])
    out = [model.predict_hypotheses(mask, push, mask.pixels, 0.5)]
    ((lattice, _),) = _memo(mask)["pushes"].values()
    n_first = len(lattice.points)
    return n_first, [
        *out,
        model.predict_hypotheses(mask, push, far, 0.5),
        model.predict_hypotheses(mask, push, mask.pixels, 0.2),
        model.predict_hypotheses(mask, push, far[::-1], 0.2),
    ]


def test_model_off_the_neighbourhood_is_the_whole_frames(monkeypatch):
    # hypotheses off the object widen the push's lattice to the whole image, carrying over
    # the node motions already integrated: the same numbers as a whole lattice from the start
    data = MASKS[0].data
    n_near, got = model_calls(comcore.Mask(data, resolution=0.001))
    monkeypatch.setattr(neighbourhood, "NEIGHBOURHOOD_MARGIN_M", 100.0)
    n_whole, want = model_calls(comcore.Mask(data, resolution=0.001))
    assert n_near < n_whole / 5  # the first calls used the neighbourhood's lattice
    for a, b in zip(got, want):
        np.testing.assert_array_equal(a, b)


def test_a_mask_and_its_fields_still_pickle():
    # the fields a mask caches are windows with the function that grows them: picklable
    import pickle

    mask = comcore.Mask(MASKS[0].data, resolution=MASKS[0].resolution)
    near, far = points_near_and_far(mask, 40)
    mask.inward_normals(near), mask.distance_to_object(near)
    field = OutlineField(mask)
    copy_mask, copy_field = pickle.loads(pickle.dumps((mask, field)))
    np.testing.assert_array_equal(copy_mask.inward_normals(far), mask.inward_normals(far))
    np.testing.assert_array_equal(copy_mask.distance_to_object(far), mask.distance_to_object(far))
    for a, b in zip(copy_field.sample(far[:, 0], far[:, 1]), field.sample(far[:, 0], far[:, 1])):
        np.testing.assert_array_equal(a, b)
