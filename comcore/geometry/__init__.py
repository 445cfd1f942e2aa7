"""Contact geometry on a mask: where a push touches, which side of a line, outlines, pixels.

Holds the pusher's contact with an outline (a point pusher, :func:`contacts`; a disc,
:func:`disc_contacts`), lines through the mask (:func:`signed_line_distance`,
:func:`split_by_line`), outlines in metres and their rasters (:func:`mask_from_outline`,
:func:`rasterise_polygon`), the outline's smoothed distance field (:func:`outline_field`),
connected regions (:func:`largest_component`) and seeded push sampling
(:func:`sample_pushes`). May import the base modules of :mod:`comcore` only.
"""

from ._contacts import Contacts, contacts, signed_line_distance, split_by_line
from ._disc_contacts import OutlineField, disc_contacts, outline_field
from ._outline import mask_from_outline
from ._raster import rasterise_polygon
from ._regions import largest_component
from ._sampling import sample_pushes

__all__ = [
    "Contacts",
    "OutlineField",
    "contacts",
    "disc_contacts",
    "largest_component",
    "mask_from_outline",
    "outline_field",
    "rasterise_polygon",
    "sample_pushes",
    "signed_line_distance",
    "split_by_line",
]
