"""Cases the fuzz profile found in the wrap generator, kept as explicit tests."""

import numpy as np
import shapely
from test_wrap import OUTLINES, check_geometry

from tentaclass.wrapping import wrap


def test_taut_comb_wrap_with_links_longer_than_the_slots():
    # the first link, from a tooth's top, must not cut across the hull through the object
    outline = OUTLINES["comb"]
    ln = min(0.140625 * shapely.LinearRing(outline).length, 0.95 * np.ptp(outline, axis=0).max())
    w = wrap(outline, 6, ln, start=0.8125, direction="ccw", mode="taut")
    check_geometry(outline, w, ln)
