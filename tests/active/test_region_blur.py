"""The region's blur by the systematic error at a fine resolution (comcore.active._grid).

At 1e-5 m/px a 1.5 mm blur is 150 px wide: a direct Gaussian filter over the object's box
padded by four of them cost (1.5 mm / resolution)^3 (21 s for 12 pushes on a 20 x 20 px
plate). A wide blur is applied as kernel matrices over the grid's box instead.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

import comcore
from comcore.active import _grid

IMAGE = np.pad(np.ones((20, 20), bool), 4)
ACTIONS = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)] * 3
MOTIONS = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)] * 3


@pytest.mark.parametrize("sigma", [0.6, 5.0, 40.0, 150.0])
def test_the_box_blur_is_the_direct_gaussian_filter(sigma):
    rows, cols = np.nonzero(np.ones((18, 23), bool))
    w = np.random.default_rng(0).random(len(rows))
    radius = int(4 * sigma + 0.5)
    pad = radius + 1
    image = np.zeros((18 + 2 * pad, 23 + 2 * pad))
    image[rows + pad, cols + pad] = w
    want = ndimage.gaussian_filter(image, sigma, mode="constant", truncate=4.0)[
        rows + pad, cols + pad
    ]
    got = _grid._box_blur(rows, cols, w, sigma, radius)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-15 * want.max())


def test_a_fine_resolution_does_not_filter_with_a_kernel_wider_than_the_box(monkeypatch):
    widths = []
    direct = ndimage.gaussian_filter

    def recorded(image, sigma, **kwargs):
        widths.append(sigma)
        return direct(image, sigma, **kwargs)

    monkeypatch.setattr(_grid.ndimage, "gaussian_filter", recorded)
    fine = comcore.estimate_posterior(
        comcore.Mask(IMAGE, resolution=1e-5), ACTIONS, MOTIONS, model=None
    )
    assert all(int(4 * s + 0.5) <= _grid.DIRECT_BLUR_RADIUS for s in widths)
    assert fine.status == "ok"  # a 20 px plate at 10 um per pixel: well under 6 mm
    # the blur still acts: 1.5 mm over a 0.2 mm plate spreads the region over all of it
    assert fine.posterior.credible_radius_px > 8


def test_an_ordinary_resolution_keeps_the_direct_filter(monkeypatch):
    widths = []
    direct = ndimage.gaussian_filter
    monkeypatch.setattr(
        _grid.ndimage, "gaussian_filter", lambda *a, **k: widths.append(a[1]) or direct(*a, **k)
    )
    comcore.estimate_posterior(comcore.Mask(IMAGE, resolution=0.001), ACTIONS, MOTIONS, model=None)
    assert any(s == pytest.approx(1.5) for s in widths)  # 1.5 mm at 1 mm per pixel
