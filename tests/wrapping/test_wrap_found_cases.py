"""Cases the fuzz profile found in the wrap generator, kept as explicit tests.

Each is checked by ``check_geometry`` and by the independent contact-model
check of ``chain_check`` (no link meets the outline outside the stretch
between its own joints), and pinned to the corner a physical chain rests on.
"""

import numpy as np
import pytest
import shapely
from chain_check import object_violations
from test_wrap import OUTLINES, check_geometry

from tentaclass.wrapping import wrap
from wrap_checks import link_length


def check_rests(name, frac, n, link, corner, offset_links=0.0, **kw):
    """Wrap ``OUTLINES[name]``, check it, and check that link ``link`` passes ``corner``.

    Every link must pass the contact-model check. Returns the wrap.
    """
    outline = OUTLINES[name]
    ln = link_length(outline, frac)
    w = wrap(outline, n, ln, offset=offset_links * ln, **kw)
    check_geometry(outline, w, ln)
    line = shapely.LineString(w.joints[link : link + 2])
    assert shapely.distance(shapely.Point(corner), line) < 1e-9
    assert not object_violations(outline, w.joints, w.direction).any()
    return w


def test_taut_comb_wrap_with_links_longer_than_the_slots():
    # the links (3.375) reach from a tooth's top across the hull to the bottom edge,
    # through the object: the first one rests on the comb's top-left corner instead;
    # the fourth, a chord across the bottom-right corner that would run through the
    # last slot, rests on that corner
    check_rests("comb", 0.140625, 6, 0, (0, 3), start=0.8125, mode="taut")
    check_rests("comb", 0.140625, 6, 3, (5, 0), start=0.8125, mode="taut")


def test_taut_l_wrap_with_links_nearly_as_long_as_the_object():
    # clockwise round the L (arms 1 wide) with six 2.85-long links and half a link of
    # stand-off: from the hull's diagonal, in the air over the notch, the chain can
    # reach no point of the hull; it folds back, and its last link, heading through
    # the L's foot towards the foot's far corner, rests on the foot's near corner
    check_rests("L", 0.25, 6, 5, (3, 1), offset_links=0.5, start=0.03125, direction="cw",
                mode="taut")  # fmt: skip


@pytest.mark.parametrize(
    "n, direction, corner", [(1, "ccw", (1, 3)), (6, "ccw", (1, 3)), (6, "cw", (3, 1))]
)
def test_hug_l_wrap_from_the_inner_corner_with_links_nearly_as_long_as_the_object(
    n, direction, corner
):
    # started in the notch, where the support bridges the inner corner, a 2.85-long link
    # reaches no point of the support: it turns away from the object until it rests on
    # the end of the arm it heads for, tip in the air (not through the L's foot)
    check_rests("L", 0.25, n, 0, corner, start=0.5, direction=direction, mode="hug")


def test_taut_comb_wrap_from_a_joint_in_the_air():
    # a link from a joint in the air above the comb (after the chain folded back)
    # towards the hull's bottom edge would run down through the teeth, which the
    # outline under the hull edges its cursor spans does not show: it is tested
    # against the whole outline, and rests on the comb's top-left corner
    check_rests("comb", 0.25, 6, 5, (0, 3), offset_links=0.5, start=0.203125, mode="taut")


@pytest.mark.parametrize("mode", ["taut", "hug"])
def test_a_vanishing_thickness_is_no_thickness(mode):
    # a lap offset by 1e-150 is empty in shapely's buffer: a thickness below what a
    # buffer resolves counts as none
    square = OUTLINES["square"]
    thin = wrap(square, 30, 0.9, mode=mode, thickness=1e-150)
    none = wrap(square, 30, 0.9, mode=mode)
    np.testing.assert_array_equal(thin.angles, none.angles)
    assert thin.complete and thin.laps > 2


def test_taut_l_wrap_started_a_hair_past_the_corner():
    # clockwise round the L from 1.2e-7 of the perimeter past (0, 0) along the bottom
    # edge, half a link (2.85 long) of stand-off below it: the link to the next edge
    # would cut a sliver 7e-7 wide off the L's foot; it rests on the corner (0, 0)
    # instead, its tip in the air left of the L
    w = check_rests("L", 0.25, 1, 0, (0, 0), offset_links=0.5, start=1.192092896e-07,
                    direction="cw", mode="taut")  # fmt: skip
    assert w.joints[0, 0] > 0 and w.joints[1, 0] < 0


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize("corner", range(4))
def test_taut_square_wrap_started_a_hair_before_each_corner(corner, direction):
    # the same at every corner of the square, walking either way: started 1.2e-7 of
    # the perimeter before the corner, the first link rests on it
    before = 1.2e-7 if direction == "ccw" else -1.2e-7
    start = (corner / 4 - before) % 1.0
    check_rests("square", 0.13, 6, 0, OUTLINES["square"][corner], offset_links=0.5,
                start=start, direction=direction, mode="taut")  # fmt: skip


def test_taut_comb_chord_over_a_corner_does_not_run_through_a_slot():
    # eight 4.75-long links, 2.7 links of stand-off: a tip in the air 0.04 left of the
    # comb's top-left corner lies on the left edge (within the slack); the chord
    # from it round the bottom-left corner to the bottom edge would run through the
    # first tooth, the first slot and the second tooth. The link rests on the
    # corner (0, 0) instead, tip in the air below the comb, and the next link
    # reaches up onto the bottom edge
    comb = OUTLINES["comb"]
    ln = link_length(comb, 0.25)
    w = wrap(comb, 8, ln, start=0.96875, offset=2.7 * ln, mode="taut")
    check_geometry(comb, w, ln)
    line = shapely.LineString(w.joints[6:8])
    assert shapely.distance(shapely.Point(0, 0), line) < 1e-9
    assert w.lap[6] == 0 and w.lap[7] == -1 and w.joints[7, 1] < 0 and w.lap[8] == 1
    # (link 5, from above the comb over its top-left corner, spans more than half
    # the outline, which the independent check reads as spanning nothing)
    assert not object_violations(comb, w.joints, w.direction)[6:].any()
