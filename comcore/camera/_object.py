"""The object against the table's fitted light: ``mask_from_image``'s default (``"auto"``).

On ``values``, a window of the grey image, or of its difference from an image
of the empty table:

1. **The table's light** (:mod:`comcore.camera._light`): a quadratic surface
   fitted on a coarse grid from the window's rim in, then what it leaves
   smoothed from the table around. Regions that differ from it and stay off
   the window's border are left out of that smoothing (the table surrounds
   the object); regions that reach the border (a shadow, the table's edge)
   are the table's and are smoothed. An object inside a shadow comes off the
   border once the shadow is smoothed, so this is done again, at most
   :data:`SMOOTH_ROUNDS` times.
2. **Candidates**: cells differing from that light by more than
   :data:`DETECT_SIGMAS` times the table's noise (the robust spread of the
   table cells: noise and texture), less what is thinner than 3 cells (a
   cutting mat's lines, a seam: they would join the object to the border).
   Their 8-connected regions, per side (brighter or darker), ranked by their
   summed difference from the table, give the object: the first region off
   the border, else the first; and the checks (nothing at all, speckled,
   several objects).
3. **At full resolution, in the object's neighbourhood only**: each pixel's
   share of object, ``alpha = (image - under) / (object - under)``, with
   ``under`` the table under it (the fitted light, plus the image of the
   empty table if there is one) and ``object`` the object's grey level; the
   mask is the region where ``alpha >= 1/2`` (the middle of a blurred edge,
   whatever the table's light or pattern there) over the candidates.

The thresholds were tuned on generated frames (``simulators/frames.py``, seed 0):
``python benchmarks/accuracy/bench_mask_from_image.py --seed 0``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy import ndimage

from .._status import ImageError
from ..geometry._regions import EIGHT_CONNECTED
from ._light import SMOOTH_SHARE, Grid, Quadratic, smooth_leftover, spread

__all__ = ["Found", "find_object"]

#: Candidates differ from the table's light by more than this many times its noise.
DETECT_SIGMAS = 5.0
#: Unless the table's rim is exactly flat, the least difference seen is this many times half
#: the image's step (1.5 grey levels for integer images): a noise-free light rounded to grey
#: levels (a drawn image) leaves steps of a level, two where a colour map skips one.
QUANTISED_STEPS = 3.0
#: At most this many rounds of leaving the object out and smoothing the table's leftovers.
SMOOTH_ROUNDS = 3
#: Speckled: the first region holds less than this share of its side's summed difference.
MIN_LARGEST_SHARE = 0.5
#: Several objects: the second region's summed difference is at least this share of the first's.
MAX_SECOND_RATIO = 0.5
#: Another object: off the rim, differing by this share of the object's level, as large.
WEAK_SHARE = 0.6
#: Low contrast: the object must differ from the table by this many times its noise per pixel.
MIN_CONTRAST_SIGMAS = 3.0
#: Cut up: the mask must hold this share of the candidate pixels past half the object's contrast.
MIN_HELD = 0.98
#: Hidden: at most this share of the ring just outside the outline may be table that the object
#: hardly differs from (less than a quarter of its contrast: the object could go on unseen).
MAX_HIDDEN = 0.1
#: Soft-edged (a shadow): the median slope on the outline, as a share of the contrast a pixel.
MIN_SHARPNESS = 0.2


class Found(NamedTuple):
    """The object found in a window."""

    region: np.ndarray
    """The object's pixels, bool, the window's shape."""
    side: str
    """``"bright"`` or ``"dark"``: brighter or darker than the table."""
    contrast: float
    """The object's typical difference from the table (grey levels, > 0)."""


class _Regions(NamedTuple):
    """The candidate regions of one side, by summed difference from the table, first first."""

    labels: np.ndarray
    ids: np.ndarray
    sizes: np.ndarray
    """Cells."""
    masses: np.ndarray
    """Summed absolute difference from the table."""
    off: np.ndarray
    """Whether the region stays off the rim (the table surrounds it)."""

    def rank(self) -> tuple[bool, float]:
        """Has it a region off the rim, and the largest mass among those (else among all)."""
        if not len(self.ids):
            return (False, -1.0)
        inner = self.masses[self.off]
        return (bool(inner.size), float(inner.max() if inner.size else self.masses.max()))

    def objects(self) -> _Regions:
        """The regions that may be the object: those off the rim if there are any."""
        if not self.off.any():
            return self
        k = self.off
        return _Regions(self.labels, self.ids[k], self.sizes[k], self.masses[k], k[k])


def _regions(candidates: np.ndarray, rim: np.ndarray, weight: np.ndarray) -> _Regions:
    """8-connected regions, by summed ``weight``, first first."""
    labels, n = ndimage.label(candidates, structure=EIGHT_CONNECTED)
    ids = np.arange(1, n + 1)
    sizes = np.bincount(labels.ravel(), minlength=n + 1)[1:]
    masses = np.bincount(labels.ravel(), weights=weight.ravel(), minlength=n + 1)[1:]
    hit = np.zeros(n + 1, bool)
    hit[labels[rim & candidates]] = True
    order = np.argsort(-masses, kind="stable")
    return _Regions(labels, ids[order], sizes[order], masses[order], ~hit[ids[order]])


def _beyond(beyond: np.ndarray, grid: Grid) -> np.ndarray:
    """Candidate cells; on a coarse grid, less what is thinner than 3 cells (lines, seams)."""
    out = grid.cells & beyond
    if grid.f > 1:
        out = ndimage.binary_opening(out, structure=EIGHT_CONNECTED)
    return out


def _inner(residual: np.ndarray, limit: float, grid: Grid, *, rim_too: bool = False) -> np.ndarray:
    """Cells of the candidate regions (either side, each on its own) off the rim (or all)."""
    out = np.zeros_like(grid.cells)
    for beyond in (residual > limit, residual < -limit):
        candidates = _beyond(beyond, grid)
        if rim_too:
            out |= candidates
            continue
        labels, n = ndimage.label(candidates, structure=EIGHT_CONNECTED)
        hit = np.zeros(n + 1, bool)
        hit[labels[grid.rim & candidates]] = True
        hit[0] = True
        out |= ~hit[labels]
    return out


class _Light(NamedTuple):
    model: Quadratic
    leftover: np.ndarray
    residual: np.ndarray
    """The coarse means less the light."""
    noise: float
    limit: float | np.ndarray
    """Candidates differ by more than this (per cell where the cells' noise is known)."""
    floored: bool
    """Whether the limit is the least step believed, not the noise."""
    seen: np.ndarray
    """The cells left out of the table in any round: what differed from it at some point."""


def _fit_light(
    grid: Grid, floor: float, frame_side: int, *, foreign: bool = False, cell_limit=0.0
) -> _Light:
    """The table's light on the grid, and what differs from it.

    ``foreign``: ``values`` is a difference from the empty table, so what
    differs from it even at the rim (the arm, a thing put down) is not light.
    ``cell_limit``: the least difference of each cell (its own noise), if larger.
    """
    means, cells, rim = grid.means, grid.cells, grid.rim
    if np.ptp(means[rim]) > 0:
        floor = QUANTISED_STEPS * floor  # a smooth light rounded to grey levels leaves steps
    noise_floor = floor / DETECT_SIGMAS
    model = Quadratic(grid.shape)
    noise = model.fit(grid.x[rim], grid.y[rim], means[rim], noise_floor)
    residual = means - model.at(grid.x, grid.y)
    table = cells & (np.abs(residual) <= DETECT_SIGMAS * noise)
    noise = model.fit(grid.x[table], grid.y[table], means[table], noise_floor)
    residual = means - model.at(grid.x, grid.y)
    leftover, smoothed = np.zeros_like(residual), residual
    exclude = np.zeros_like(cells)
    for round_ in range(SMOOTH_ROUNDS):
        limit = np.maximum(DETECT_SIGMAS * noise, cell_limit)
        inner = _inner(smoothed, limit, grid, rim_too=foreign)
        if round_ and not (inner & ~exclude).any():
            break
        exclude |= inner
        table = cells & ~ndimage.binary_dilation(exclude, structure=EIGHT_CONNECTED)
        leftover = smooth_leftover(residual, table, SMOOTH_SHARE * frame_side / grid.f)
        smoothed = residual - leftover
        noise = spread(smoothed[table], noise_floor)
    limit = np.maximum(DETECT_SIGMAS * noise, cell_limit)
    return _Light(model, leftover, smoothed, noise, limit, noise <= noise_floor, exclude)


def find_object(
    values: np.ndarray,
    valid: np.ndarray | None,
    side: str,
    *,
    floor: float,
    frame_side: int | None = None,
    reference: np.ndarray | None = None,
    point: tuple[float, float] | None = None,
    spread: np.ndarray | None = None,
) -> Found:
    """The object in ``values`` (a window of the grey image, or of its difference).

    ``valid``: the pixels to look at (the region of interest; None: all);
    ``side``: ``"auto"``, ``"bright"`` or ``"dark"``; ``floor``: half the
    image's step (half a grey level for integer images), the least difference
    believed on a flat table (:data:`QUANTISED_STEPS` times it otherwise);
    ``frame_side``: the short side of the whole frame (default: of the
    window), which sets the grid and the smoothing; ``reference``: the same
    window of the image of the empty table, when ``values`` is the difference
    from it; ``spread``: each pixel's noise in that difference, from several
    frames of the empty table (a cell's candidates must then differ by
    :data:`DETECT_SIGMAS` times its own noise too).
    """
    table = "the table" if reference is None else "the background image (the empty table)"
    grid = Grid(values, valid, min(values.shape) if frame_side is None else frame_side)
    side_px = min(values.shape) if frame_side is None else frame_side
    own = _cell_limit(grid, spread, valid)
    light = _fit_light(grid, floor, side_px, foreign=reference is not None, cell_limit=own)
    residual, limit = light.residual, light.limit
    names = ("bright", "dark") if side == "auto" else (side,)
    found = {
        name: _regions(
            _beyond(residual > limit if name == "bright" else residual < -limit, grid),
            grid.rim, np.abs(residual),
        )
        for name in names
    }
    if not any(len(regions.ids) for regions in found.values()):
        cells = grid.cells
        largest = float(np.abs(residual[cells]).max()) if cells.any() else 0.0
        region = f"region {3 * grid.f} pixels across or more" if grid.f > 1 else "pixel"
        words = {"auto": "", "bright": "brighter ", "dark": "darker "}[side]
        why = "the least step believed" if light.floored else f"{DETECT_SIGMAS:g} times its noise"
        raise ImageError(
            f"no object: the image matches {table} (no {words}{region} differs from it by more "
            f"than {np.median(limit):.3g} grey levels, {why}; the largest difference is "
            f"{largest:.3g}): "
            + ("" if reference is not None else "on a patterned or textured table give "
               "background= (an image of the empty table, arm away), and if several objects "
               "are in view choose one: point=(x, y) or roi=(x0, y0, x1, y1); ")
            + "check that the object is in view, or give threshold= a grey level"
        )
    if point is not None:
        side, core = _at_point(found, point, grid.f)
    else:
        side = max(found, key=lambda name: found[name].rank())
        regions = found[side].objects()
        _check_regions(regions, side, grid.f, table, reference is not None)
        core = regions.labels == regions.ids[0]
        sign = 1.0 if side == "bright" else -1.0
        plain = sign * (grid.means - light.model.at(grid.x, grid.y))  # before the leftovers
        weak = plain > WEAK_SHARE * np.median(plain[core])
        weak = ndimage.binary_opening(grid.cells & weak, EIGHT_CONNECTED, iterations=2)
        _check_seen(light.seen | weak, core, grid, table, reference is not None)
    return _refine(_Window(values, valid, grid, reference), core, side, light, table)


def _cell_limit(grid: Grid, spread: np.ndarray | None, valid) -> np.ndarray | float:
    """:data:`DETECT_SIGMAS` times each cell's own noise (its pixels' ``spread``), or 0."""
    if spread is None:
        return 0.0
    return DETECT_SIGMAS * np.sqrt(Grid(spread**2, valid, grid.frame_side).means) / grid.f


def _at_point(found: dict, point, f: int) -> tuple[str, np.ndarray]:
    """The side and cells of the candidate region nearest ``point`` (window pixels)."""
    cell = np.array([point[1], point[0]]) // f
    best = (np.inf, "", None)
    for name, regions in found.items():
        for label in regions.ids[:50]:
            cells = np.argwhere(regions.labels == label)
            gap = float(np.min(np.hypot(*(cells - cell).T)))
            if gap < best[0]:
                best = (gap, name, regions.labels == label)
    if best[2] is None:
        raise ImageError("no object near point: nothing differs from the table there")
    return best[1], best[2]


def _check_regions(regions: _Regions, side: str, f: int, table: str, background: bool) -> None:
    """ImageError for a speckled side or several objects of similar size."""
    sizes, masses = regions.sizes * f * f, regions.masses
    about = "" if f == 1 else "about "
    if masses[0] < MIN_LARGEST_SHARE * masses.sum():
        fix = "roi= (where to look)"
        if not background:
            fix = "background= (an image of the empty table) or " + fix
        raise ImageError(
            f"speckled result: the {side} side differs from {table} in {len(sizes)} regions, the "
            f"largest only {about}{sizes[0]} of their {sizes.sum()} pixels "
            f"({100 * masses[0] / masses.sum():.0f} % of the difference); a textured or "
            f"patterned table? give {fix}"
        )
    if len(sizes) > 1 and masses[1] >= MAX_SECOND_RATIO * masses[0]:
        also = "" if background else ", and background= (an image of the empty table)"
        raise ImageError(
            f"several objects of similar size on the {side} side: the largest regions have "
            f"{about}{sizes[0]} and {sizes[1]} pixels; choose one: point=(x, y) a pixel on it, "
            f"or roi=(x0, y0, x1, y1) a box around it{also}; or show one object at a time"
        )


def _check_seen(seen: np.ndarray, core: np.ndarray, grid: Grid, table: str, background: bool):
    """ImageError if another object, off the rim, differed from the table in an earlier round.

    Such an object (one beside a shadow or the arm, whose light took it in,
    or one a little fainter than the limit, ``seen`` holding what differs from
    the fitted light by :data:`WEAK_SHARE` of the object's level) is no candidate in the end, yet
    it is as much an object as the one found.
    """
    labels, n = ndimage.label(seen | core, structure=EIGHT_CONNECTED)
    if n < 2:
        return
    sizes = np.bincount(labels.ravel(), minlength=n + 1)
    ours = np.unique(labels[core])
    first = int(sizes[ours].max())
    sizes[ours] = 0
    sizes[np.unique(labels[grid.rim])] = 0  # what reaches the rim is the table's (arm, shadow)
    sizes[0] = 0
    if sizes.max() >= MAX_SECOND_RATIO * first:
        f2 = grid.f * grid.f
        also = "" if background else ", and background= (an image of the empty table)"
        raise ImageError(
            f"several objects of similar size differ from {table}: about {first * f2} and "
            f"{int(sizes.max()) * f2} pixels; choose one: point=(x, y) a pixel on it, "
            f"or roi=(x0, y0, x1, y1) a box around it{also}; or show one object at a time"
        )


def _cut(region: np.ndarray, box: tuple[slice, slice], shape: tuple[int, int]) -> bool:
    """Whether the region reaches its box's edge where the box is not the window's."""
    rows, cols = box
    return bool(
        (region[0].any() and rows.start > 0)
        or (region[-1].any() and rows.stop < shape[0])
        or (region[:, 0].any() and cols.start > 0)
        or (region[:, -1].any() and cols.stop < shape[1])
    )


def _check_contrast(
    diff, around, inside, region, level, *, seen, table: str, background: bool
) -> None:
    """ImageError if the object is too faint or soft-edged for a whole outline, or cut up.

    ``diff``: the window's difference from the table towards the object's
    side; ``around``: table pixels round the object; ``inside``: its
    candidate cells' pixels that are at least half object (not a shadow
    beside it); ``region``: the mask found. A whole object holds nearly
    every one of those past half its contrast, and its edge is
    sharp (a shadow's is soft: a gentle slope for its contrast); ``seen``:
    where the object would differ from the table under it by a quarter of its
    contrast or more. With ``background``, its outline must not run along
    table the object matches (a pattern's stripes): it could go on unseen.
    """
    noise = spread(diff[around], 1e-9) if around.sum() >= 16 else 0.0
    strong = ndimage.binary_opening(inside) & (diff >= 0.5 * level)  # not single noisy pixels
    held = float(region[strong].mean()) if strong.any() else 1.0
    edge = region & ~ndimage.binary_erosion(region)
    slope = ndimage.gaussian_gradient_magnitude(diff, 1.0)
    sharp = float(np.median(slope[edge])) / level if edge.any() and level > 0 else 1.0
    ring = ndimage.binary_dilation(region, iterations=2) & ~region
    hidden = 0.0  # only the empty table's image tells what the object matches pixel by pixel
    if background and ring.any():
        hidden = float(np.mean(~np.broadcast_to(seen, region.shape)[ring]))
    if (
        level >= MIN_CONTRAST_SIGMAS * noise
        and held >= MIN_HELD
        and sharp >= MIN_SHARPNESS
        and hidden <= MAX_HIDDEN
    ):
        return
    fix = "" if background else "give background= (an image of the empty table, arm away); "
    what = (
        f"its edge is soft (a slope of {sharp:.2g} of its contrast a pixel, a shadow's?)"
        if held >= MIN_HELD and level >= MIN_CONTRAST_SIGMAS * noise and sharp < MIN_SHARPNESS
        else f"the outline found holds {100 * held:.0f} % of it"
        if held < MIN_HELD or level < MIN_CONTRAST_SIGMAS * noise
        else f"{100 * hidden:.0f} % of its outline runs along table it hardly differs from"
    )
    raise ImageError(
        f"low contrast: the object differs from {table} by {level:.3g} grey levels, "
        f"{level / max(noise, 1e-9):.2g} times the table's noise per pixel ({noise:.3g}), and "
        f"{what}: no whole outline; {fix}light the object better or put it on a table of "
        "another colour, and keep shadows off it (several objects? choose one: point=(x, y) "
        "or roi=(x0, y0, x1, y1))"
    )


def _object_level(differences: np.ndarray) -> float:
    """The object's typical difference from the table: the median of the pixels past half of it.

    Started from the 90th percentile of the candidates' pixels, so that a
    shadow or a blurred edge beside the object (weaker than half its
    contrast) does not pull it down.
    """
    level = float(np.percentile(differences, 90))
    for _ in range(3):
        strong = differences[differences >= 0.5 * level]
        if not strong.size:
            break
        level = float(np.median(strong))
    return level


class _Window(NamedTuple):
    """What the object is looked for in."""

    values: np.ndarray
    """The window of the grey image, or of its difference from the empty table."""
    valid: np.ndarray | None
    """The pixels to look at (None: all)."""
    grid: Grid
    """The window on the coarse grid."""
    reference: np.ndarray | None
    """The same window of the image of the empty table, or None."""


def _refine(window: _Window, core, side, light: _Light, table: str) -> Found:
    """The object at full resolution in the neighbourhood of its candidate cells."""
    values, valid, grid, reference = window
    h, w = grid.shape
    f = grid.f
    rows, cols = np.nonzero(core)
    sign = 1.0 if side == "bright" else -1.0
    pad = 2 * f + 4
    while True:
        box = (
            slice(max(rows.min() * f - pad, 0), min((rows.max() + 1) * f + pad, h)),
            slice(max(cols.min() * f - pad, 0), min((cols.max() + 1) * f + pad, w)),
        )
        yy, xx = np.mgrid[box]
        under = light.model.at(xx, yy)
        if light.leftover.any():
            under = under + grid.at_pixels(light.leftover, *box)
        ok = np.ones(under.shape, bool) if valid is None else valid[box]
        inside = grid.pixels(core, *box)
        around = ok & ~ndimage.binary_dilation(inside, iterations=f + 1)
        if around.sum() >= 16:  # the table's level right around the object
            under = under + float(np.median((values[box] - under)[around]))
        diff = values[box] - under
        if reference is not None:
            under = under + reference[box]
        level = _object_level(sign * diff[inside & ok])
        strong = inside & ok & (sign * diff >= 0.5 * level)
        # the object's grey level, and its contrast with the table under each pixel
        contrast = sign * (float(np.median((diff + under)[strong])) - under) if strong.any() else 0
        seen = contrast >= 0.25 * level  # else the object hardly differs from the table there
        share = sign * diff / np.where(seen, contrast, level)
        foreground = ok & (share >= 0.5)
        labels, n = ndimage.label(foreground, structure=EIGHT_CONNECTED)
        overlap = np.bincount(labels[inside & foreground], minlength=n + 1)
        if not level > 0 or not overlap[1:].any():
            raise ImageError(
                f"no object: the image matches {table} at full resolution (what differed from "
                "it on the coarse grid does not, pixel by pixel): "
                + (
                    ""
                    if reference is not None
                    else "give background= (an image of the empty table), "
                )
                + "check the lighting, or give threshold= a grey level"
            )
        region = labels == int(np.argmax(overlap[1:])) + 1
        if not _cut(region, box, (h, w)):
            break
        pad *= 2  # the object reaches further than its candidates: a larger neighbourhood
    _check_contrast(
        sign * diff,
        around,
        inside & foreground,  # a shadow beside it, past half the contrast, is no part of it
        region,
        level,
        seen=seen,
        table=table,
        background=reference is not None,
    )
    full = np.zeros((h, w), bool)
    full[box] = region
    return Found(full, side, level)
