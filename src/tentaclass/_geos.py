"""GEOS's distance arithmetic as numba kernels, shared by the compiled code.

The wrap generator and the scanner compare their distances with those of
shapely (GEOS) to the last bit, so they round as GEOS does. The module imports
numba and numpy only, so the scanner does not load the wrapping package.
"""

from __future__ import annotations

import numba as nb
import numpy as np


@nb.njit(cache=True, nogil=True, inline="always")
def point_segment_distance(x, y, ax, ay, bx, by):
    """GEOS's ``Distance::pointToSegment`` from ``(x, y)`` to the segment a-b (same roundings)."""
    if ax == bx and ay == by:
        return np.sqrt((x - ax) * (x - ax) + (y - ay) * (y - ay))
    len2 = (bx - ax) * (bx - ax) + (by - ay) * (by - ay)
    r = ((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / len2
    if r <= 0.0:
        return np.sqrt((x - ax) * (x - ax) + (y - ay) * (y - ay))
    if r >= 1.0:
        return np.sqrt((x - bx) * (x - bx) + (y - by) * (y - by))
    s = ((ay - y) * (bx - ax) - (ax - x) * (by - ay)) / len2
    return abs(s) * np.sqrt(len2)
