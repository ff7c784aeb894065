"""Object outlines: primitives, polygons, image silhouettes (MPEG-7), hand-drawn strokes.

Every outline is a closed, simple, counter-clockwise polygon as an
``(n_points, 2)`` float array, the first point not repeated at the end.
"""

from ._images import from_mask, load_mpeg7, read_silhouette
from ._outline import (
    as_outline,
    circle,
    polygon,
    rectangle,
    regular_polygon,
    signed_area,
    square,
    triangle,
)
from ._stroke import from_stroke

__all__ = [
    "as_outline",
    "circle",
    "from_mask",
    "from_stroke",
    "load_mpeg7",
    "polygon",
    "read_silhouette",
    "rectangle",
    "regular_polygon",
    "signed_area",
    "square",
    "triangle",
]
