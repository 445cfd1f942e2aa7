"""The exception hierarchy of comcore: one base, a few specific errors."""

from __future__ import annotations

__all__ = ["ComcoreError", "ImageError", "PushFailedError", "SessionError"]


class ComcoreError(Exception):
    """Base class of every error that comcore raises on its own account.

    Input validation errors are plain :class:`ValueError` / :class:`TypeError`
    (they name the argument and what was expected); this base is for failures
    that are not about the shape of the input.
    """


class ImageError(ComcoreError, ValueError):
    """A camera image or mask that does not show one whole object.

    Raised by :func:`comcore.mask_from_image` (an all-dark or all-bright image,
    an object touching the image border, a speckled or empty result) and by
    :func:`comcore.measure_motion` (a mask touching the image border: part of
    the object may be out of view). The message says what was seen.
    """


class PushFailedError(ComcoreError, RuntimeError):
    """A caller-supplied ``push`` callable failed or returned an invalid motion.

    Attributes
    ----------
    index : int
        Zero-based number of the push that failed.
    action : comcore.Action
        The action that was being executed.
    partial : object
        What the estimator had learned before the failure (an
        :class:`comcore.Estimate`), or ``None``.
    """

    def __init__(self, message: str, *, index: int, action, partial=None):
        super().__init__(message)
        self.index = index
        self.action = action
        self.partial = partial


class SessionError(ComcoreError, RuntimeError):
    """A :class:`comcore.ActiveSession` method called out of turn.

    ``observe()`` before ``next_push()`` (or twice for one push),
    ``next_push()`` after the session is done. The session is unchanged.
    """
