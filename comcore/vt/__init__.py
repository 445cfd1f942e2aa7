"""Mason's Voting Theorem: the sense of a push's rotation and the region of CoMs it leaves.

:func:`predicted_sense` votes each pixel of a mask by the side of the push's force
lines it lies on; :func:`region` intersects the votes of several pushes;
:func:`consistent` says whether an observed sense agrees. The force lines
(``_force_lines``) and the tally of senses a hypothesis leaves unexplained
(``_senses``) live here too. See :mod:`comcore.vt._voting` for the conventions and
the choices made where the paper is silent. May import the base modules and
:mod:`comcore.geometry`.
"""

from ._voting import consistent, predicted_sense, region

__all__ = ["consistent", "predicted_sense", "region"]
