"""Helpers shared by the estimators: largest component, region mean, Estimate building."""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from .._mask import Mask
from .._status import Status
from .._types import Estimate
from ..conventions import check_image_size

__all__ = [
    "EIGHT_CONNECTED",
    "best_component",
    "estimate_from_region",
    "label_components",
    "largest_component",
]

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
        arr = np.asarray(image)
    except (TypeError, ValueError) as e:  # ragged nested lists
        raise TypeError(f"{name} must be a 2-D boolean array; {e}") from e
    if arr.ndim != 2:
        raise ValueError(f"{name} must be a 2-D boolean array, got shape {arr.shape}")
    check_image_size(arr.shape, name)  # before the copy: a huge view asks for gigabytes
    arr = arr.copy()
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


def label_components(image) -> tuple[np.ndarray, int]:
    """The 8-connected components of a boolean image: ``(labels, n)``, labels 1..n.

    Examples
    --------
    >>> labels, n = label_components([[1, 0, 1], [1, 0, 0]])
    >>> n, labels.tolist()
    (2, [[1, 0, 2], [1, 0, 0]])
    """
    labels, n = ndimage.label(check_image(image), structure=EIGHT_CONNECTED)
    return labels, int(n)


def best_component(labels: np.ndarray, keys) -> np.ndarray:
    """The component whose ``keys`` are best (highest, compared in order).

    Ties after every key go to the larger component, then to the lowest label;
    with no keys this is :func:`largest_component`.

    Parameters
    ----------
    labels : numpy.ndarray of int, shape (H, W)
        Component labels 1..n, 0 for the background (:func:`label_components`).
    keys : array_like, shape (n, k)
        Row ``c - 1`` scores component ``c``; column 0 is compared first.

    Returns
    -------
    numpy.ndarray of bool, shape (H, W)

    Examples
    --------
    The smaller component on the right wins on its score:

    >>> labels, n = label_components([[1, 1, 0, 1], [1, 1, 0, 0]])
    >>> best_component(labels, [[2], [3]]).astype(int)
    array([[0, 0, 0, 1],
           [0, 0, 0, 0]])
    >>> best_component(labels, [[3], [3]]).astype(int)
    array([[1, 1, 0, 0],
           [1, 1, 0, 0]])
    """
    n = int(labels.max(initial=0))
    keys = np.asarray(keys, dtype=float).reshape(n, -1)
    if n == 0:
        return np.zeros(labels.shape, dtype=bool)
    index = np.arange(1, n + 1)
    sizes = np.bincount(labels.ravel(), minlength=n + 1)[1:]
    # np.lexsort sorts by its last key first: the keys in order, then size, then label
    order = np.lexsort((index, -sizes, *(-keys[:, j] for j in range(keys.shape[1] - 1, -1, -1))))
    return labels == int(index[order[0]])


def estimate_from_region(mask: Mask, region: np.ndarray, **fields) -> Estimate:
    """An :class:`Estimate` whose CoM is the mean of ``region``'s pixels.

    An empty region falls back to the mask's centroid and the whole mask, with
    ``status`` set to ``"empty_region"`` unless the caller gave a status.
    """
    if not region.any():
        fields.setdefault("status", Status.EMPTY_REGION)
        region = mask.data
    rows, cols = np.nonzero(region)
    com = (float(cols.mean()), float(rows.mean()))
    return Estimate(com=com, com_m=mask.to_metres(com), region=region, **fields)
