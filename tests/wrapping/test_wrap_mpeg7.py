"""A spread of MPEG-7 outlines, both modes: links never cross the object, contacts on it.

All 1400 are checked by ``benchmarks/wrap_crossings.py`` (BENCHMARKS.md).
"""

import numpy as np
import pytest
import shapely

from tentaclass.errors import InputError
from tentaclass.shapes import load_mpeg7
from tentaclass.wrapping import wrap_many
from wrap_checks import MPEG7, crossing_links, needs_mpeg7


@pytest.fixture(scope="module")
def mpeg7():
    return load_mpeg7(MPEG7, max_vertices=1000)


@pytest.mark.mpeg7
@needs_mpeg7
@pytest.mark.parametrize("mode", ["taut", "hug"])
def test_every_20th_outline(mpeg7, mode):
    outlines, _, names = mpeg7
    outlines, names = outlines[::20], names[::20]
    rng = np.random.default_rng(7)
    crossing, bad_contact, bad_length, jammed, refused = [], [], [], 0, 0
    for outline, name in zip(outlines, names, strict=True):
        ring = shapely.LinearRing(outline)
        ln = ring.length / 64 * rng.uniform(0.3, 2.0)
        kw = {"starts": rng.uniform(0, 1), "mode": mode,
              "direction": str(rng.choice(["ccw", "cw"]))}  # fmt: skip
        offset = rng.choice([0.0, rng.uniform(0, 3 * ln)])
        try:
            w = wrap_many(outline, 64, ln, offset=offset, **kw)[0]
        except InputError as e:  # a stand-off in a concavity, behind another part
            assert "passes through the object" in str(e)
            refused += 1
            w = wrap_many(outline, 64, ln, **kw)[0]
        jammed += not w.complete
        j = w.joints
        scale = np.ptp(outline, axis=0).max()
        on = shapely.distance(shapely.points(j[w.contact]), ring)
        if on.size and on.max() > 1e-9 * scale:
            bad_contact.append(name)
        if not np.allclose(np.hypot(*np.diff(j, axis=0).T), ln, rtol=1e-9, atol=0):
            bad_length.append(name)
        # links that leave the support (approach, bridges, overhangs) are tested
        # strictly; links between two joints resting on the object's own edges
        # are chords that may cut the cap they span (the sampling limit).
        air = (w.lap[:-1] < 0) | (w.lap[1:] < 0)
        if air.any() and (crossing_links(outline, j) & air).any():
            crossing.append(name)
    # Links in the air (approach, bridges, overhangs, links folded in where the
    # support offers nothing) should never cross the object. In taut mode none
    # do here; in hug mode some folded links still do (3 of these 70 wraps).
    # The bound keeps that from growing; the goal is 0.
    assert len(crossing) <= (0 if mode == "taut" else 3), ("crossing", len(crossing),
                                                           crossing[:10])  # fmt: skip
    assert not bad_contact, ("contact", len(bad_contact), bad_contact[:10])
    assert not bad_length, bad_length[:10]
    # every link is placed: no wrap stops early
    assert jammed == 0, jammed
    # an approach along the hull's outward normal never meets the object
    assert refused <= (0 if mode == "taut" else 0.02 * len(outlines)), refused
