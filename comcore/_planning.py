"""Candidate pushes of :class:`comcore.ActiveSession`, planned on the object where it is.

Candidates are drawn (or given) once, on the first mask: in the object's
frame. Their force lines are fixed there too, so the posterior (which lives
on the object) is scored with them whatever the pose. What moves with the
object is where the robot must push: :meth:`Candidates.offerable` maps each
candidate through the pose and keeps the ones that start outside the object
as it is now, stay in the image and hit it.
"""

from __future__ import annotations

import math

import numpy as np

from ._active_setup import ActiveOptions
from ._geometry import contacts
from ._mask import Mask
from ._motion import model_gains
from ._posterior import GridPosterior, force_lines, sense_information
from ._sampling import sample_pushes
from ._session_pose import IDENTITY, actions_in_pose
from ._types import Motion
from ._validation import check_actions

__all__ = ["Candidates", "push_force_lines"]


def push_force_lines(con, actions, mus) -> np.ndarray:
    """Force lines (n, m, 3) of pushes that hit, from their contacts, for each friction value."""
    actions = np.asarray(actions, dtype=float)
    direction = actions[:, 2:] - actions[:, :2]
    direction = direction / np.hypot(direction[:, 0], direction[:, 1])[:, None]
    return force_lines(con.point, con.normal, direction, np.arctan(mus))


class Candidates:
    """Object-frame candidate pushes with their force lines (internal, mutable).

    Parameters
    ----------
    mask : Mask
        The first mask.
    candidates : array_like, shape (n, 4), or None
        Given pushes (each must start outside the first mask and hit it), or
        None to draw ``options.n_candidates`` with :func:`comcore.sample_pushes`.
    options : ActiveOptions
    rng : numpy.random.Generator
    name : str, optional
        The argument's name in error messages.
    """

    def __init__(self, mask: Mask, candidates, options: ActiveOptions, rng, name="candidates"):
        if candidates is None:
            actions = sample_pushes(
                mask, options.n_candidates, cone=options.cone, travel=options.travel_m, rng=rng
            )
        else:
            actions = check_actions(candidates, name, allow_empty=False)
        con = contacts(mask, actions)
        con.require_hits(name)
        self.mask = mask
        self.actions = np.array(actions, dtype=float)
        self.actions.setflags(write=False)
        self.lines = push_force_lines(con, actions, options.mus)
        self.available = np.ones(len(actions), dtype=bool)
        self._centroid = np.asarray(mask.centroid, dtype=float)
        self._in_view = self._inside_image(self.actions)

    def __len__(self) -> int:
        return len(self.actions)

    def made(self, index: int) -> None:
        """Mark a candidate made: neither it nor an identical candidate is offered again."""
        self.available &= ~np.all(self.actions == self.actions[index], axis=1)

    def in_pose(self, pose: Motion, index=None) -> np.ndarray:
        """The candidates (or those at ``index``) in the camera frame at ``pose``."""
        acts = self.actions if index is None else self.actions[index]
        return actions_in_pose(acts, pose, self._centroid)

    def _inside_image(self, actions) -> np.ndarray:
        h, w = self.mask.shape
        x, y = actions[:, 0::2], actions[:, 1::2]
        inside = (x >= -0.5) & (x <= w - 0.5) & (y >= -0.5) & (y <= h - 0.5)
        return inside.all(axis=1)

    def offerable(self, pose: Motion, mask_now: Mask | None) -> np.ndarray:
        """Candidates not yet made that can be pushed on the object at ``pose``.

        ``mask_now`` is the object as seen now (an observed mask, or the first
        mask moved to ``pose``; None when it left the image). A candidate is
        offered when, mapped through the pose, it starts and ends inside the
        image, starts outside the object and hits it.
        """
        ok = self.available.copy()
        if mask_now is None:
            return np.zeros_like(ok)
        if pose == IDENTITY and mask_now is self.mask:
            return ok & self._in_view  # every candidate hits the first mask
        idx = np.flatnonzero(ok)
        if len(idx):
            moved = self.in_pose(pose, idx)
            con = contacts(mask_now, moved)
            ok[idx] = self._inside_image(moved) & con.hit & ~con.starts_inside
        return ok

    def choose(self, post: GridPosterior, offered, options: ActiveOptions):
        """The most informative offered candidate: ``(index, gain_bits)``, or ``(None, best)``.

        ``None`` when no candidate is offered (``best`` is then None) or none
        is expected to teach more than ``options.min_information`` bits.
        """
        idx = np.flatnonzero(offered)
        if len(idx) == 0:
            return None, None
        if options.selection == "model":
            gains = model_gains(
                options.models,
                self.mask,
                post,
                self.actions[idx],
                self.lines[idx],
                options.theta_noise,
                options.translation_noise,
                options.near_px,
            ) / math.log(2)
        else:
            gains = sense_information(
                post.pixels,
                post.sense_weights,
                self.lines[idx],
                options.flip_prob,
                options.line_scale_px,
            )
        best = int(np.argmax(gains))
        if not gains[best] > options.min_information:
            return None, float(gains[best])
        return int(idx[best]), float(gains[best])
