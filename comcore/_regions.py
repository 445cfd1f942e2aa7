"""Helpers shared by the estimators: largest component, region mean, Estimate building."""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from ._mask import Mask
from ._types import Estimate

__all__ = ["EIGHT_CONNECTED", "estimate_from_region", "largest_component"]

#: Connectivity used for "the largest connected region": 8-neighbour.
EIGHT_CONNECTED = np.ones((3, 3), dtype=bool)


def check_image(image, name: str = "image") -> np.ndarray:
    """A 2-D boolean image from array_like of bools (or 0 / 1); a copy, never the input.

    Examples
    --------
    >>> check_image([[0, 1], [1, 0]]).dtype
    dtype('bool')
    >>> check_image([[0, 2]])
    Traceback (most recent call last):
    ...
    ValueError: image must hold booleans (or 0 / 1), got the value 2
    """
    if isinstance(image, (str, bytes)) or image is None:
        raise TypeError(f"{name} must be a 2-D boolean array, got {type(image).__name__}")
    try:
        arr = np.array(image)
    except (TypeError, ValueError) as e:  # ragged nested lists
        raise TypeError(f"{name} must be a 2-D boolean array; {e}") from e
    if arr.ndim != 2:
        raise ValueError(f"{name} must be a 2-D boolean array, got shape {arr.shape}")
    if arr.dtype != bool:
        if arr.dtype.kind not in "biuf":
            raise TypeError(f"{name} must be a 2-D boolean array, got dtype {arr.dtype}")
        bad = (arr != 0) & (arr != 1)
        if bad.any():
            raise ValueError(
                f"{name} must hold booleans (or 0 / 1), got the value {arr[bad].flat[0]}"
            )
        arr = arr.astype(bool)
    return arr


def largest_component(image) -> np.ndarray:
    """The largest 8-connected component of a boolean image (ties: lowest label).

    Parameters
    ----------
    image : array_like of bool, shape (H, W)
        Booleans (or 0 / 1 numbers); not modified.

    Returns
    -------
    numpy.ndarray of bool, shape (H, W)
        A new array (a copy of ``image`` when it has at most one component).

    Raises
    ------
    ValueError
        If ``image`` is not 2-D or holds values other than 0 and 1.
    TypeError
        If ``image`` is not an array of booleans or numbers.

    Examples
    --------
    >>> img = np.array([[1, 1, 0, 1], [0, 0, 0, 1], [0, 0, 0, 1]], bool)
    >>> largest_component(img).astype(int)
    array([[0, 0, 0, 1],
           [0, 0, 0, 1],
           [0, 0, 0, 1]])
    >>> largest_component([1, 0, 1])
    Traceback (most recent call last):
    ...
    ValueError: image must be a 2-D boolean array, got shape (3,)
    """
    image = check_image(image)
    labels, n = ndimage.label(image, structure=EIGHT_CONNECTED)
    if n <= 1:
        return image.copy()
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
