"""Cases the fuzz profile found in the wrap generator, kept as explicit tests."""

import pytest
from test_wrap import OUTLINES, check_geometry

from tentaclass.wrapping import wrap
from wrap_checks import link_length


@pytest.mark.xfail(
    strict=True,
    reason="generator limitation: on the comb, a taut chain whose links (3.4) are longer "
    "than the slots are wide places its first link from a tooth's top across the hull to "
    "the bottom edge, through the object",
)
def test_taut_comb_wrap_with_links_longer_than_the_slots():
    outline = OUTLINES["comb"]
    ln = link_length(outline, 0.140625)
    w = wrap(outline, 6, ln, start=0.8125, direction="ccw", mode="taut")
    check_geometry(outline, w, ln)


@pytest.mark.xfail(
    strict=True,
    reason="generator limitation: on the L (arms 1 wide), a clockwise taut chain of six "
    "2.85-long links with half a link of stand-off folds back on itself (joints 2 and 4 "
    "coincide) and its last link, in the air, runs through the L's foot",
)
def test_taut_l_wrap_with_links_nearly_as_long_as_the_object():
    outline = OUTLINES["L"]
    ln = link_length(outline, 0.25)
    w = wrap(outline, 6, ln, start=0.03125, direction="cw", mode="taut", offset=0.5 * ln)
    check_geometry(outline, w, ln)


@pytest.mark.xfail(
    strict=True,
    reason="generator limitation: on the L (arms 1 wide), a hugging chain of 2.85-long "
    "links started at the inner corner begins in the notch, off the outline, and its "
    "first link runs through the L's foot (any number of links, either direction)",
)
@pytest.mark.parametrize("n, direction", [(1, "ccw"), (6, "cw")])
def test_hug_l_wrap_from_the_inner_corner_with_links_nearly_as_long_as_the_object(n, direction):
    outline = OUTLINES["L"]
    ln = link_length(outline, 0.25)
    w = wrap(outline, n, ln, start=0.5, direction=direction, mode="hug")
    check_geometry(outline, w, ln)
