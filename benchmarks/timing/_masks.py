"""Masks the timing scripts share (this folder is on ``sys.path`` when a script runs)."""

from __future__ import annotations

import numpy as np

import comcore


def ellipse_mask(n_pixels: int) -> comcore.Mask:
    """An ellipse (axes 5:4) of about ``n_pixels`` pixels, at the default 2.5 mm per pixel."""
    a = np.sqrt(n_pixels / np.pi * 5 / 4)
    b = 0.8 * a
    size = int(2 * a) + 12
    yy, xx = np.mgrid[:size, :size]
    return comcore.Mask(((xx - size / 2) / a) ** 2 + ((yy - size / 2) / b) ** 2 < 1)
