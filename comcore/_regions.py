"""Helpers shared by the estimators: largest component, region mean, Estimate building."""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from ._mask import Mask
from ._types import Estimate

__all__ = ["EIGHT_CONNECTED", "estimate_from_region", "largest_component"]

#: Connectivity used for "the largest connected region": 8-neighbour.
EIGHT_CONNECTED = np.ones((3, 3), dtype=bool)


def largest_component(image: np.ndarray) -> np.ndarray:
    """The largest 8-connected component of a boolean image (ties: lowest label).

    Examples
    --------
    >>> img = np.array([[1, 1, 0, 1], [0, 0, 0, 1], [0, 0, 0, 1]], bool)
    >>> largest_component(img).astype(int)
    array([[0, 0, 0, 1],
           [0, 0, 0, 1],
           [0, 0, 0, 1]])
    """
    labels, n = ndimage.label(image, structure=EIGHT_CONNECTED)
    if n <= 1:
        return image.astype(bool, copy=True)
    sizes = np.bincount(labels.ravel())[1:]
    return labels == (int(np.argmax(sizes)) + 1)


def estimate_from_region(mask: Mask, region: np.ndarray, **fields) -> Estimate:
    """An :class:`Estimate` whose CoM is the mean of ``region``'s pixels.

    An empty region falls back to the mask's centroid and the whole mask, with
    ``status`` set to ``"empty_region"`` unless the caller gave a status.
    """
    if not region.any():
        fields.setdefault("status", "empty_region")
        region = mask.data
    rows, cols = np.nonzero(region)
    com = (float(cols.mean()), float(rows.mean()))
    return Estimate(com=com, com_m=mask.to_metres(com), region=region, **fields)
