"""Mason's Voting Theorem as one force line per push and friction value.

The Voting Theorem's three rays all leave the contact point, so each vote
depends only on the direction from the contact to the CoM, and the majority of
three monotone votes is the vote of the median ray: the push direction clipped
to the friction cone, i.e. the direction of the contact force. The sense of
rotation is the side of that force line the CoM lies on (tested against
:func:`comcore.vt.predicted_sense`). The signed distance of a pixel to the line
is linear in the pixel, so all pushes x frictions x pixels are one matrix
product. The likelihood (:mod:`comcore.active._likelihood`) and the push choice
(:mod:`comcore.active._choice`) both read the lines made here.
"""

from __future__ import annotations

import numpy as np

from ..conventions import ccw_cross, rotate_vectors

__all__ = [
    "LINE_SCALE_PX",
    "force_line_distances",
    "force_lines",
    "push_force_lines",
    "side_probability",
]

#: Scale (pixels) of the soft edge of a force line at the default 2.5 mm/px and
#: an exact pusher (the estimators derive it from metres: ``LINE_BLUR_M`` and
#: ``pusher_error`` in :mod:`comcore.active._likelihood`). The Voting Theorem's sense
#: is taken to be wrong for a CoM at distance d from the line with probability
#: ``1 / (1 + exp(|d| / scale))`` (plus ``flip_prob``): pixel outlines, the
#: smoothed normal, the pusher's radius and the object turning during the push
#: blur the line (how often the sense is wrong at each distance, measured against
#: the simulator: docs/explanation/likelihood.md, "The line is soft").
LINE_SCALE_PX = 1.2


def push_force_lines(con, actions, mus) -> np.ndarray:
    """Force lines (n, m, 3) of pushes that hit, from their contacts, for each friction value."""
    actions = np.asarray(actions, dtype=float)
    direction = actions[:, 2:] - actions[:, :2]
    direction = direction / np.hypot(direction[:, 0], direction[:, 1])[:, None]
    return force_lines(con.point, con.normal, direction, np.arctan(mus))


def force_lines(contact, normal, direction, alphas) -> np.ndarray:
    """Coefficients ``(a, b, k)`` of each push's force line for each cone half-angle.

    The signed distance of a point ``p`` is ``a p_x + b p_y + k``, positive on
    the counter-clockwise side (a CoM there turns the object counter-clockwise).

    Parameters
    ----------
    contact, normal, direction : numpy.ndarray, shape (n, 2)
        Contact points, unit inward normals and unit push directions.
    alphas : numpy.ndarray, shape (m,)
        Friction cone half-angles ``atan(mu)``.

    Returns
    -------
    numpy.ndarray, shape (n, m, 3)

    Examples
    --------
    A push to the right along the normal at (0, 5): points above it (smaller
    row) are on its counter-clockwise side.

    >>> lines = force_lines(np.array([[0.0, 5.0]]), np.array([[1.0, 0.0]]),
    ...                     np.array([[1.0, 0.0]]), np.array([0.3]))
    >>> force_line_distances(np.array([[5.0, 3.0], [5.0, 7.0]]), lines)[:, 0, 0].tolist()
    [2.0, -2.0]
    """
    beta = np.arctan2(ccw_cross(normal, direction), np.einsum("ij,ij->i", normal, direction))
    delta = np.clip(beta[:, None], -alphas[None, :], alphas[None, :])  # (n, m)
    n_b = np.broadcast_to(normal[:, None, :], (*delta.shape, 2))
    force = rotate_vectors(n_b, delta)  # (n, m, 2)
    a, b = force[..., 1], -force[..., 0]
    k = -(a * contact[:, None, 0] + b * contact[:, None, 1])
    return np.stack([a, b, k], axis=-1)


def force_line_distances(points, lines) -> np.ndarray:
    """Signed distances, shape (n_points, *lines.shape[:-1])."""
    pts = np.asarray(points, dtype=lines.dtype)
    flat = lines.reshape(-1, 3)
    out = pts @ flat[:, :2].T + flat[:, 2]
    return out.reshape(len(pts), *lines.shape[:-1])


def side_probability(distance, scale: float = LINE_SCALE_PX):
    """Probability of the positive sense at a signed distance from the force line.

    The logistic ``1 / (1 + exp(-d / scale)) = 0.5 + 0.5 tanh(d / (2 scale))``.

    Examples
    --------
    >>> side_probability(np.array([-100.0, 0.0, 1.2]), 1.2).round(3)
    array([0.   , 0.5  , 0.731])
    """
    return 0.5 + 0.5 * np.tanh(np.asarray(distance, dtype=float) / (2 * scale))
