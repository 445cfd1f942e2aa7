"""Frames, signs and numeric tolerances: the one place that defines them.

Everything in comcore (and in ``predictors`` and ``simulators``) that needs a
frame convention calls a helper from this module instead of re-deriving it.

Conventions
-----------
* **Pixel frame.** ``x`` is the column, ``y`` is the row, and ``y`` points
  DOWN the screen. Pixel ``(row, col)`` has its centre at ``(x=col, y=row)``
  and covers ``[col - 0.5, col + 0.5] x [row - 0.5, row + 0.5]``.
* **Metres in the mask frame.** ``(x_m, y_m) = resolution * (x, y)``: the same
  axes as the pixel frame (``y_m`` down), origin at the centre of pixel (0, 0).
* **Rotation sign.** ``theta > 0`` is counter-clockwise *as seen on screen*
  (row 0 at the top). Seen from above a table whose world ``y`` axis points up
  the screen, this is the usual counter-clockwise. Because the pixel frame is
  left-handed on screen, the rotation matrix that turns pixel coordinates by
  ``theta`` counter-clockwise on screen is ``[[cos, sin], [-sin, cos]]``.
  A rotation's sense (+1, -1, or 0 inside a dead band) is
  :func:`rotation_sense`. Vectors are turned by :func:`rotation_matrix`,
  :func:`rotate_vectors` (checked) or :func:`rotate_components` (for inner
  loops; its ``inverse`` turn is the counter-clockwise one in a frame whose
  ``y`` points up, such as the table's metres).
* **Units.** What a user sets from their robot is in metres and radians;
  :data:`PLAUSIBLE` holds the range in which each such value is believable,
  and :func:`check_plausible` refuses one outside it with a guess at the unit
  it was typed in (millimetres for metres, degrees for radians).
* **Robot defaults.** What a user sets from their robot has one default, here:
  the round pusher's radius :data:`DEFAULT_PUSHER_RADIUS` and how far a push
  travels past first contact :data:`DEFAULT_TRAVEL_M` (metres).
* **Moments.** :func:`ccw_cross` is the 2-D cross product with the sign that
  makes ``+1`` counter-clockwise on screen; the raw ``a_x b_y - a_y b_x`` in
  pixel coordinates is positive for *clockwise* on screen.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ._checks import check_finite, check_point, check_points, refuse_complex

__all__ = [
    "ANGLE_EPS",
    "DEFAULT_PUSHER_RADIUS",
    "DEFAULT_RESOLUTION",
    "DEFAULT_TRAVEL_M",
    "LENGTH_EPS",
    "MAX_IMAGE_PIXELS",
    "PLAUSIBLE",
    "Plausible",
    "apply_motion",
    "ccw_cross",
    "check_image_size",
    "check_plausible",
    "object_motion_from_camera",
    "pixel_centres",
    "quarter_turn_ccw",
    "rotate_components",
    "rotate_vectors",
    "rotation_matrix",
    "rotation_sense",
]

#: Default camera resolution in metres per pixel (2.5 mm, as in the simulator).
DEFAULT_RESOLUTION = 0.0025
#: The most pixels an image (a mask, a camera frame) may have: 8192 x 8192, twice an 8K
#: camera's. Beyond it comcore refuses the image by its shape instead of asking numpy for
#: gigabytes (a broadcast view, a mask drawn in millimetres read as metres).
MAX_IMAGE_PIXELS = 8192 * 8192


class Plausible(NamedTuple):
    """The believable range of a value a user sets from their robot (see :data:`PLAUSIBLE`)."""

    low: float
    """Smallest believable value (0: any positive value, or zero where zero is allowed)."""
    high: float
    """Largest believable value."""
    typical: float
    """A usual value: among the units a wrong value may have been typed in, the guess is the
    one that brings it nearest this (on a log scale)."""
    unit: str
    """The unit the value must be given in, as messages write it."""


#: Believable values of what a user sets from their robot, in metres or radians: the one
#: place these ranges live (docs/explanation/conventions.md lists them). A value outside its range
#: is refused by :func:`check_plausible` with a guess at the unit it was typed in.
PLAUSIBLE = {
    # a camera over a table: 10 micrometres to 5 cm a pixel
    "resolution": Plausible(1e-5, 0.05, DEFAULT_RESOLUTION, "m per pixel"),
    # a round pusher: a point (0) to a disc 10 cm across
    "pusher_radius": Plausible(0.0, 0.05, 0.004, "m"),
    # a push's travel: no push goes further than half a metre
    "push_length": Plausible(0.0, 0.5, 0.03, "m"),
    # the credible region's radius a session stops at
    "target_radius": Plausible(0.0, 0.5, 0.006, "m"),
    # a standard deviation or error scale of a position (pusher, tracker, model)
    "length_noise": Plausible(0.0, 0.05, 0.001, "m"),
    # a standard deviation of a measured rotation: under about 29 degrees
    "angle_noise": Plausible(0.0, 0.5, 0.01, "rad"),
}

#: Units a length may have been typed in, with their size in metres.
_LENGTH_UNITS = (("millimetres", 1e-3), ("centimetres", 1e-2), ("micrometres", 1e-6))


def check_plausible(value: float, name: str, kind: str) -> float:
    """``value`` if it is believable as a :data:`PLAUSIBLE` ``kind``, else a ValueError.

    The message gives the range and, where converting the value from another
    unit brings it into the range, the likeliest such unit (the one nearest
    the typical value): millimetres or centimetres typed for metres, degrees
    for radians, pixels per metre for metres per pixel.

    Parameters
    ----------
    value : float
        A finite number, already checked for its sign.
    name : str
        The argument's name in the message.
    kind : str
        A key of :data:`PLAUSIBLE`.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If ``value`` lies outside the range.

    Examples
    --------
    >>> check_plausible(0.0025, "resolution", "resolution")
    0.0025
    >>> check_plausible(2.5, "resolution", "resolution")
    Traceback (most recent call last):
    ...
    ValueError: resolution 2.5 m per pixel is implausible (expected 1e-05 to 0.05 m per pixel): did you mean millimetres, 0.0025?
    >>> check_plausible(0.5, "motion_noise's rotation", "angle_noise")
    0.5
    >>> check_plausible(5.0, "pusher_radius", "pusher_radius")
    Traceback (most recent call last):
    ...
    ValueError: pusher_radius 5 m is implausible (expected at most 0.05 m): did you mean millimetres, 0.005?
    """  # noqa: E501
    if kind not in PLAUSIBLE:
        raise ValueError(f"kind must be one of {', '.join(sorted(PLAUSIBLE))}, got {kind!r}")
    rule = PLAUSIBLE[kind]
    v = float(value)
    if rule.low <= v <= rule.high:
        return v
    expected = (
        f"{rule.low:g} to {rule.high:g} {rule.unit}"
        if rule.low > 0
        else f"at most {rule.high:g} {rule.unit}"
    )
    message = f"{name} {v:g} {rule.unit} is implausible (expected {expected})"
    guess = _unit_guess(v, rule)
    raise ValueError(message + (f": did you mean {guess[0]}, {guess[1]:.3g}?" if guess else ""))


def _unit_guess(value: float, rule: Plausible) -> tuple[str, float] | None:
    """The likeliest unit ``value`` was typed in, and the value in ``rule``'s unit, or None."""
    if rule.unit == "rad":
        options = [("degrees", math.radians(value))]
    else:
        options = [(unit, value * size) for unit, size in _LENGTH_UNITS]
        if rule.unit == "m per pixel" and value > 0:
            options.append((f"{value:g} pixels per metre", 1.0 / value))
    fits = [(u, v) for u, v in options if max(rule.low, 1e-300) <= v <= rule.high]
    if not fits or rule.typical <= 0:
        return None
    return min(fits, key=lambda uv: abs(math.log(uv[1] / rule.typical)))

#: Lengths (pixels) below this are treated as zero (e.g. zero-length actions).
LENGTH_EPS = 1e-9
#: Angles (radians) whose magnitude is at most this count as "no rotation".
ANGLE_EPS = 1e-12
#: Radius (metres) of the round pusher where none is given: an 8 mm dowel, a typical
#: fingertip, and the simulators' pusher.
DEFAULT_PUSHER_RADIUS = 0.004
#: How far (metres) a push travels past first contact where none is given: the paper's
#: 3 cm pushes.
DEFAULT_TRAVEL_M = 0.03


def _finite_array(value, name: str) -> np.ndarray:
    """``value`` as a float array if it holds only finite real numbers, else a clear error."""
    if isinstance(value, (str, bytes)) or value is None:
        raise TypeError(f"{name} must be array_like of real numbers, got {type(value).__name__}")
    refuse_complex(value, name)
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be array_like of real numbers; {e}") from e
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} must be finite, got NaN or inf")
    return arr


def _vectors(value, name: str) -> np.ndarray:
    """Finite pixel vectors, shape (..., 2)."""
    arr = _finite_array(value, name)
    if arr.ndim == 0 or arr.shape[-1] != 2:
        raise ValueError(f"{name} must have shape (..., 2) (pixel vectors), got {arr.shape}")
    return arr


def rotation_matrix(theta: float) -> np.ndarray:
    """Return the 2 x 2 matrix turning pixel vectors by ``theta`` (CCW on screen).

    Parameters
    ----------
    theta : float
        Rotation in radians, positive counter-clockwise on screen.

    Returns
    -------
    numpy.ndarray, shape (2, 2)
        ``R`` such that ``R @ v`` is the vector ``v`` (pixel frame, y down)
        turned counter-clockwise on screen by ``theta``.

    Examples
    --------
    The +x axis (pointing right) turned a quarter turn counter-clockwise on
    screen points up the screen, i.e. towards -y in the pixel frame:

    >>> import numpy as np
    >>> np.round(rotation_matrix(np.pi / 2) @ [1.0, 0.0], 12) + 0.0
    array([ 0., -1.])
    >>> rotation_matrix(float("inf"))
    Traceback (most recent call last):
    ...
    ValueError: theta must be a finite angle in radians, got inf
    """
    try:
        if isinstance(theta, (str, bytes)):
            raise TypeError("text")
        refuse_complex(theta, "theta")
        angle = np.asarray(theta, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"theta must be an angle in radians, got {type(theta).__name__}") from e
    if angle.ndim != 0:
        raise ValueError(
            f"theta must be one angle in radians, got shape {angle.shape} "
            "(rotate_vectors turns each vector by its own angle)"
        )
    if not np.isfinite(angle):
        raise ValueError(f"theta must be a finite angle in radians, got {float(angle)}")
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, s], [-s, c]])


def rotate_vectors(vectors, theta) -> np.ndarray:
    """Turn pixel vectors counter-clockwise on screen, each by its own angle.

    Parameters
    ----------
    vectors : array_like, shape (n, 2)
    theta : float or array_like, shape (n,)
        Angles in radians (CCW on screen), broadcast against the vectors.

    Returns
    -------
    numpy.ndarray, shape (n, 2)

    Raises
    ------
    ValueError
        If ``vectors`` is not of shape (..., 2), ``theta`` does not broadcast
        against ``vectors[..., 0]``, or either holds NaN or inf.
    TypeError
        If either is not numeric.

    Examples
    --------
    >>> rotate_vectors([[1.0, 0.0], [1.0, 0.0]], [np.pi / 2, -np.pi / 2]).round(12) + 0.0
    array([[ 0., -1.],
           [ 0.,  1.]])
    >>> rotate_vectors([1.0, 2.0, 3.0], 0.1)
    Traceback (most recent call last):
    ...
    ValueError: vectors must have shape (..., 2) (pixel vectors), got (3,)
    """
    v = _vectors(vectors, "vectors")
    theta = _finite_array(theta, "theta")
    try:
        np.broadcast_shapes(theta.shape, v.shape[:-1])
    except ValueError:
        raise ValueError(
            f"theta must broadcast against the vectors: got shape {theta.shape} "
            f"for vectors of shape {v.shape}"
        ) from None
    return np.stack(rotate_components(v[..., 0], v[..., 1], np.cos(theta), np.sin(theta)), axis=-1)


def rotate_components(x, y, cos, sin, *, inverse: bool = False, origin=None):
    """Turn vectors given as component arrays, with the angle's cosine and sine given: no checks.

    The one hand-written 2-D rotation in comcore, for inner loops that turn many
    vectors by angles whose cosines and sines they already hold (``predictors``
    and ``simulators`` use it too). Everything broadcasts; nothing is validated
    (:func:`rotate_vectors` is the checked way).

    Parameters
    ----------
    x, y : array_like
        The vectors' components.
    cos, sin : array_like
        Cosine and sine of each rotation angle ``theta``.
    inverse : bool, optional
        False (default): turn by ``theta``, counter-clockwise on screen in the
        pixel frame, ``(cos x + sin y, -sin x + cos y)``. True: turn by
        ``-theta``, ``(cos x - sin y, sin x + cos y)``; in a frame whose ``y``
        points up (table metres) this is the counter-clockwise turn by
        ``theta``, i.e. body to world.
    origin : (array_like, array_like), optional
        ``(ox, oy)`` added to the turned vectors. The sums are evaluated left
        to right, ``ox + cos x + sin y``, as code that writes them out does.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        The turned vectors' components.

    Examples
    --------
    A quarter turn counter-clockwise on screen takes +x (right) up the
    screen (-y); the inverse turn takes it down:

    >>> c, s = np.cos(np.pi / 2), np.sin(np.pi / 2)
    >>> [np.round(v, 12) + 0.0 for v in rotate_components(1.0, 0.0, c, s)]
    [np.float64(0.0), np.float64(-1.0)]
    >>> [np.round(v, 12) + 0.0 for v in rotate_components(1.0, 0.0, c, s, inverse=True)]
    [np.float64(0.0), np.float64(1.0)]
    >>> rotate_components(np.array([1.0, 2.0]), 0.0, 1.0, 0.0, origin=(10.0, 20.0))
    (array([11., 12.]), array([20., 20.]))
    """
    if inverse:
        if origin is None:
            return cos * x - sin * y, sin * x + cos * y
        return origin[0] + cos * x - sin * y, origin[1] + sin * x + cos * y
    if origin is None:
        return cos * x + sin * y, -sin * x + cos * y
    return origin[0] + cos * x + sin * y, origin[1] - sin * x + cos * y


def pixel_centres(image) -> np.ndarray:
    """Centres ``(x, y) = (column, row)`` of an image's true pixels, shape (m, 2), row-major.

    Parameters
    ----------
    image : array_like of bool, shape (H, W)
        A boolean image (or one of 0 and 1 numbers), not empty: a
        :class:`comcore.Mask`'s ``data``, not the Mask itself.

    Returns
    -------
    numpy.ndarray, shape (m, 2)
        One row per true pixel, ``m`` >= 0.

    Raises
    ------
    TypeError
        If ``image`` is not an array of booleans or numbers (a string, an
        object array, ragged lists, a Mask).
    ValueError
        If ``image`` is not 2-D, is empty, or holds numbers other than 0 and 1
        (a grey-level image: threshold it, or use :func:`comcore.mask_from_image`).

    Examples
    --------
    >>> pixel_centres([[False, True], [True, False]])
    array([[1., 0.],
           [0., 1.]])
    >>> pixel_centres([0, 1, 1])
    Traceback (most recent call last):
    ...
    ValueError: image must be a 2-D (H, W) boolean image, got 1-D shape (3,)
    >>> pixel_centres([[0, 255]])
    Traceback (most recent call last):
    ...
    ValueError: image must hold booleans (or 0 and 1), got the value 255: threshold a grey-level image first (comcore.mask_from_image)
    """  # noqa: E501
    if not (isinstance(image, np.ndarray) and image.dtype == bool and image.ndim == 2):
        image = _bool_image(image, "image")
    check_image_size(image.shape, "image")
    if image.size == 0:
        raise ValueError(f"image must not be empty, got shape {image.shape}")
    rows, cols = np.nonzero(image)
    return np.column_stack([cols, rows]).astype(float)


def _motion_values(motion, name: str) -> np.ndarray:
    """``motion`` as 3 finite numbers ``(theta, tx, ty)``, or an error naming ``name``."""
    arr = _finite_array(motion, name).reshape(-1)
    if arr.shape != (3,):
        raise ValueError(f"{name} must be 3 numbers (theta, tx, ty), got shape {np.shape(motion)}")
    return arr


def check_image_size(shape, name: str) -> None:
    """A ValueError naming ``name`` if an image of ``shape`` (H, W) has over :data:`MAX_IMAGE_PIXELS`.

    Examples
    --------
    >>> check_image_size((720, 1280), "frame")
    >>> check_image_size((100_000, 100_000), "mask data")
    Traceback (most recent call last):
    ...
    ValueError: mask data of 100000 x 100000 pixels is larger than MAX_IMAGE_PIXELS (67108864, 8192 x 8192): crop it to the object's neighbourhood, or check the resolution's unit
    """  # noqa: E501
    h, w = (int(v) for v in shape[:2])
    if h * w > MAX_IMAGE_PIXELS:
        raise ValueError(
            f"{name} of {h} x {w} pixels is larger than MAX_IMAGE_PIXELS ({MAX_IMAGE_PIXELS}, "
            "8192 x 8192): crop it to the object's neighbourhood, or check the resolution's unit"
        )


def _bool_image(image, name: str) -> np.ndarray:
    """``image`` as a 2-D bool array, or an error naming ``name`` and what arrived."""
    want = f"{name} must be a 2-D (H, W) boolean image"
    if hasattr(image, "data") and hasattr(image, "resolution"):  # a comcore.Mask
        raise TypeError(f"{want}, got a {type(image).__name__}: pass its .data")
    if image is None or isinstance(image, (str, bytes)):
        raise TypeError(f"{want}, got {type(image).__name__}")
    try:
        arr = np.asarray(image)
    except ValueError as e:  # ragged nested lists
        raise TypeError(f"{want}, got ragged rows ({e})") from e
    if arr.dtype.kind not in "biuf":
        raise TypeError(f"{want}, got dtype {arr.dtype}")
    if arr.ndim != 2:
        raise ValueError(f"{want}, got {arr.ndim}-D shape {arr.shape}")
    check_image_size(arr.shape, name)
    if arr.dtype != bool:
        bad = (arr != 0) & (arr != 1)
        if bad.any():
            raise ValueError(
                f"{name} must hold booleans (or 0 and 1), got the value {arr[bad].flat[0]:g}: "
                "threshold a grey-level image first (comcore.mask_from_image)"
            )
        arr = arr != 0
    return arr


def quarter_turn_ccw(vectors) -> np.ndarray:
    """Turn pixel vectors a quarter turn counter-clockwise on screen, exactly.

    Equal to ``rotate_vectors(vectors, pi / 2)`` without rounding error:
    ``(x, y) -> (y, -x)`` in the pixel frame.

    Raises
    ------
    ValueError
        If the vectors do not come in ``(x, y)`` pairs or hold NaN or inf.

    Examples
    --------
    >>> quarter_turn_ccw([[1.0, 0.0]])  # right -> up the screen
    array([[ 0., -1.]])
    >>> quarter_turn_ccw([[1.0, 0.0], [float("nan"), 2.0]])
    Traceback (most recent call last):
    ...
    ValueError: vectors must be finite pixel vectors (x, y); vector 1 is (nan, 2.0)
    """
    refuse_complex(vectors, "vectors")
    try:
        v = np.asarray(vectors, dtype=float)
    except (TypeError, ValueError) as e:
        raise ValueError(f"vectors must be pixel vectors (x, y): {e}") from e
    if v.ndim == 0 or v.shape[-1] != 2:
        raise ValueError(f"vectors must be pixel vectors (x, y), shape (..., 2), got {v.shape}")
    bad = ~np.isfinite(v).all(axis=-1)
    if bad.any():
        i = int(np.flatnonzero(bad.reshape(-1))[0])
        x, y = v.reshape(-1, 2)[i]
        raise ValueError(f"vectors must be finite pixel vectors (x, y); vector {i} is ({x}, {y})")
    return np.stack([v[..., 1], -v[..., 0]], axis=-1)


def apply_motion(points, theta, translation, center) -> np.ndarray:
    """Move pixel points rigidly: rotate by ``theta`` about ``center``, then translate.

    This is the single definition of how a :class:`comcore.Motion` acts on the
    object: the object turns by ``theta`` (CCW on screen) about its area
    centroid ``center`` and the centroid then moves by ``translation``.

    Parameters
    ----------
    points : array_like, shape (n, 2) or (2,)
        Pixel coordinates ``(x, y)``.
    theta : float
        Rotation in radians, positive counter-clockwise on screen.
    translation : array_like, shape (2,)
        Displacement ``(tx, ty)`` of ``center`` in pixels.
    center : array_like, shape (2,)
        Centre of rotation ``(x, y)`` in pixels (the mask's area centroid).

    Returns
    -------
    numpy.ndarray
        The moved points, same shape as ``points``.

    Raises
    ------
    ValueError
        If ``points`` is not of shape (n, 2) or (2,), ``translation`` or
        ``center`` is not a single 2-vector, or any of them (or ``theta``) is
        not finite.
    TypeError
        If ``theta`` is not a real number.

    Examples
    --------
    A point to the right of the centre, turned a quarter turn CCW on screen,
    ends up above the centre (smaller row):

    >>> apply_motion([[11.0, 5.0]], np.pi / 2, (0.0, 0.0), (10.0, 5.0)).round(12) + 0.0
    array([[10.,  4.]])
    """
    pts = check_points(points)
    theta = check_finite(theta, "theta")
    t = check_point(translation, "translation")
    c = check_point(center, "center")
    moved = (pts - c) @ rotation_matrix(theta).T + c + t
    return moved[0] if np.shape(points) == (2,) else moved


def object_motion_from_camera(motion, pose_theta: float) -> np.ndarray:
    """A motion seen by the camera, as the object's own motion from its first pose.

    The object sits at a pose (rotation ``pose_theta`` and a translation,
    relative to the first mask) and a push moves it by ``motion`` =
    ``(theta, tx, ty)``: in the camera frame, about its current area centroid
    (the image of the first mask's centroid). The same push made on the
    object in its first pose would have moved it by ``(theta, R(-pose_theta)
    (tx, ty))`` about the first mask's centroid: the rotation is the same and
    the displacement is turned back into the first mask's frame.

    Parameters
    ----------
    motion : array_like, shape (3,)
        ``(theta, tx, ty)`` in the camera frame (radians, pixels).
    pose_theta : float
        Rotation (radians, CCW on screen) of the object's pose before the push.

    Returns
    -------
    numpy.ndarray, shape (3,)
        ``(theta, tx, ty)`` in the first mask's frame.

    Examples
    --------
    An object turned a quarter turn: a push that moves it up the screen moved
    it along its own +x axis.

    >>> np.round(object_motion_from_camera((0.1, 0.0, -2.0), np.pi / 2), 12) + 0.0
    array([0.1, 2. , 0. ])
    """
    theta, tx, ty = (float(v) for v in _motion_values(motion, "motion"))
    t = rotate_vectors(np.array([tx, ty]), -check_finite(pose_theta, "pose_theta"))
    return np.array([theta, t[0], t[1]])


def ccw_cross(a, b) -> np.ndarray:
    """2-D cross product of pixel vectors, positive when ``a`` -> ``b`` turns CCW on screen.

    Parameters
    ----------
    a, b : array_like, shape (..., 2)
        Pixel-frame vectors; broadcast against each other.

    Returns
    -------
    numpy.ndarray, shape (...)
        ``-(a_x b_y - a_y b_x)``. For a force ``b`` applied at offset ``a``
        from a pivot, this is the moment about the pivot, positive when it
        turns the object counter-clockwise on screen.

    Raises
    ------
    ValueError
        If ``a`` or ``b`` is not of shape (..., 2), they do not broadcast, or
        either holds NaN or inf.
    TypeError
        If either is not numeric.

    Examples
    --------
    Pushing right (+x) on a point above the pivot (smaller row) turns the
    object clockwise on screen:

    >>> float(ccw_cross([0.0, -1.0], [1.0, 0.0]))
    -1.0
    >>> ccw_cross([1.0, 2.0, 3.0], [1.0, 2.0])
    Traceback (most recent call last):
    ...
    ValueError: a must have shape (..., 2) (pixel vectors), got (3,)
    """
    a = _vectors(a, "a")
    b = _vectors(b, "b")
    try:
        np.broadcast_shapes(a.shape, b.shape)
    except ValueError:
        raise ValueError(f"a and b must broadcast, got shapes {a.shape} and {b.shape}") from None
    return _ccw_cross(a, b)


def _ccw_cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Unvalidated core of :func:`ccw_cross` for float arrays the caller has checked."""
    return -(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])


def rotation_sense(theta, tol: float = ANGLE_EPS) -> np.ndarray:
    """Sense of rotation: +1 counter-clockwise on screen, -1 clockwise, 0 within ``tol``.

    The one definition of a rotation's sense in comcore: the Voting Theorem's
    side of the force line, :attr:`comcore.Motion.sense`, the likelihood's
    sense term and Alg. 2 all read it from here.

    Parameters
    ----------
    theta : array_like
        Rotations in radians, positive counter-clockwise on screen.
    tol : float, optional
        The dead band: magnitudes at most ``tol`` count as no rotation
        (default :data:`ANGLE_EPS`; ``0`` gives the plain sign, ``inf`` no
        sense at all, as for a rotation that was not observed).

    Returns
    -------
    numpy.ndarray of int
        Same shape as ``theta`` (a 0-d array for a scalar).

    Raises
    ------
    ValueError
        If ``theta`` holds NaN or inf, or ``tol`` is negative or NaN.
    TypeError
        If ``theta`` or ``tol`` is not numeric.

    Examples
    --------
    >>> rotation_sense([0.2, -0.1, 0.0, 1e-13])
    array([ 1, -1,  0,  0])
    >>> rotation_sense([1e-13, 0.01, -0.01], tol=0.0)  # no dead band
    array([ 1,  1, -1])
    >>> int(rotation_sense(-0.3, tol=0.5))
    0
    >>> rotation_sense([float("nan")])
    Traceback (most recent call last):
    ...
    ValueError: theta must be finite, got NaN or inf
    """
    t = _finite_array(theta, "theta")
    if isinstance(tol, bool) or not isinstance(tol, (int, float, np.integer, np.floating)):
        raise TypeError(f"tol must be a number >= 0, got {type(tol).__name__}")
    if not tol >= 0:  # NaN fails too
        raise ValueError(f"tol must be a number >= 0 (inf: no sense), got {tol}")
    return np.where(np.abs(t) <= tol, 0, np.sign(t)).astype(int)
