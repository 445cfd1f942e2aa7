"""Mason's Voting Theorem (public module): ``comcore.vt.rotation_sense``, ``comcore.vt.region``.

See :mod:`comcore._voting` for the conventions and the choices made where the
paper is silent.
"""

from ._voting import consistent, region, rotation_sense

__all__ = ["consistent", "region", "rotation_sense"]
