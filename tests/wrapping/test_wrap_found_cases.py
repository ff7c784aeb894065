"""Cases the fuzz profile found in the wrap generator, kept as explicit tests."""

import numpy as np
import pytest
import shapely
from chain_check import chain_problems
from test_wrap import OUTLINES, check_geometry
from test_wrap_chain import MPEG7, needs_mpeg7, random_star

from tentaclass import shapes
from tentaclass.wrapping import wrap, wrap_many


def test_taut_comb_wrap_with_links_longer_than_the_slots():
    # the first link, from a tooth's top, must not cut across the hull through the object
    outline = OUTLINES["comb"]
    ln = min(0.140625 * shapely.LinearRing(outline).length, 0.95 * np.ptp(outline, axis=0).max())
    w = wrap(outline, 6, ln, start=0.8125, direction="ccw", mode="taut")
    check_geometry(outline, w, ln)


#: Hug wraps of MPEG-7 silhouettes (centred, rotated by ``angle``, in units of
#: ``link``) that crossed the object before: a chord from a joint resting just
#: off the outline (on the closing) cut the outline behind that joint, a link
#: resting in the air touched the outline behind its joints, or a later lap
#: climbed onto the line from the start point to the first joint on the
#: object, which cut through the object's cap where the approach had passed.
HUG_CASES = [
    ("bat-14.png", 1, -1.4387075836236012, 23.058967190896237, 0.49416177862830957, "cw",
     1.995348986344379),
    ("beetle-1.png", 1, 2.448966554881877, 32.152553461711676, 0.13164839559325658, "cw",
     0.16480274087729918),
    ("deer-5.png", 1, 2.231277743793632, 59.90140982350949, 0.6367367070354333, "cw",
     0.6477710585438621),
    ("fork-1.png", 1, 0.3661494984872571, 22.90772284200214, 0.2580290481250599, "ccw",
     0.26058458917040195),
    ("apple-1.png", 2, 4.06417878774685, 21.649833639634473, 0.6639199713794128, "ccw",
     0.35566268467515005),
    ("car-01.png", 2, 2.66037399931446, 14.23721520234692, 0.3228911980251664, "ccw",
     1.3727594748206609),
    ("cattle-1.png", 2, 2.2604075897546534, 41.57608889478302, 0.05826732686352465, "cw",
     1.320893510796195),
]  # fmt: skip


@needs_mpeg7
@pytest.mark.parametrize(("name", "laps", "angle", "link", "start", "direction", "offset"),
                         HUG_CASES)  # fmt: skip
def test_hug_wraps_that_crossed_the_object(name, laps, angle, link, start, direction, offset):
    outlines, _, names = shapes.load_mpeg7(MPEG7, max_vertices=1000)
    o = outlines[names.index(name)]
    rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    o = (o - o.mean(axis=0)) @ rot.T / link
    w = wrap_many(o, 64, 1.0, starts=start, direction=direction, offset=offset, mode="hug")[0]
    found = chain_problems(o, w)
    assert (found["object"], found["self_on_laps"], found["incomplete"]) == (0, 0, 0)
    assert w.laps > 0.25 * laps  # it went round, not stuck


def test_hug_link_resting_in_the_air_moves_on_instead_of_folding_back():
    # from a joint on a spike's flank the chord ahead cuts the spike: the link
    # rests in the air, and the next one must not reach back to the joint before
    outline = random_star(4)
    w = wrap(outline, 142, 0.07537700532570804, start=0.450339366649287, direction="cw",
             offset=0.08692559507827383, mode="hug", thickness=0.003921209887382264)  # fmt: skip
    found = chain_problems(outline, w)
    assert (found["object"], found["self_on_laps"]) == (0, 0)
    assert not np.any(np.all(np.isclose(w.joints[2:], w.joints[:-2], atol=1e-9), axis=1))
    assert w.laps > 1.0  # stuck folding back and forth, it stopped at half a lap
