"""The quasi-static grasp: geometry only, the patterns of the simulated chain."""

import numpy as np
import pytest
import shapely

from tentaclass import PlanarChain, Wrap, angles_to_points, grasp_state
from tentaclass.errors import InputError
from tentaclass.physics import PhysicalGrasp, grasp_many, quasi_static_grasp
from tentaclass.shapes import circle, polygon, square, triangle

C_SHAPE = polygon([(0, 0), (6, 0), (6, 1), (2, 1), (2, 3), (4, 3), (4, 4), (0, 4)])


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize("offset", [0.0, 2.0])
def test_result_is_a_wrap_resting_on_the_object(direction, offset):
    g = quasi_static_grasp(square(3.0), PlanarChain([0.5] * 24), start=0.3, direction=direction,
                           offset=offset)  # fmt: skip
    assert isinstance(g, Wrap) and isinstance(g, PhysicalGrasp)
    assert g.complete, g.reason
    rebuilt = angles_to_points(g.angles, 0.5, base=g.joints[0], heading=g.heading)
    np.testing.assert_allclose(rebuilt, g.joints, atol=1e-9)
    assert np.sign(g.angles.sum()) == (1 if direction == "ccw" else -1)
    if not offset:  # laps count from the start point's tangent
        np.testing.assert_allclose(abs(g.angles.sum()), 2 * np.pi * g.laps, atol=1e-9)
    # links are capsules 0.05 thick: every link's axis stays about 0.025 off the object
    # (near a joint, where a contact does not stop its turn, a link may sink in a little)
    body = shapely.Polygon(square(3.0))
    first = g.offset_links
    links = shapely.linestrings(np.stack([g.joints[first:-1], g.joints[first + 1 :]], axis=1))
    d = shapely.distance(links, body)
    assert np.median(d) == pytest.approx(0.98 * 0.025, rel=0.01) and np.all(d >= 0.5 * 0.025)
    assert g.contact.sum() >= 8
    if offset:
        assert np.allclose(g.angles[:3], 0.0)  # the approach stays straight
        assert grasp_state(g.angles).offset_links.item() == 4


def test_a_corner_is_passed_then_turned_back_to():
    # a link lying along an edge runs past the corner; the next joint turns by more than
    # the corner (until the link leans on the next edge), the one after turns back
    g = quasi_static_grasp(square(4), PlanarChain([1.0] * 16), start=0.1)
    corner = g.angles[3:5]
    assert corner[0] > np.pi / 2 + 0.3 and corner[1] < -0.3
    np.testing.assert_allclose(corner.sum(), np.pi / 2, atol=0.05)
    # the chain loses length at every corner: 0.75 laps where a hug wrap closes one
    assert g.laps == pytest.approx(0.75, abs=0.01)
    assert grasp_state(g.angles).state.item() == "partial"


def test_circle_lap_turns_once():
    g = quasi_static_grasp(circle(16 / (2 * np.pi)), PlanarChain([1.0] * 16), start=0.1)
    assert g.complete and g.laps == pytest.approx(1.0, abs=0.05)
    assert np.all(g.angles > -0.3)  # never turns away on a convex object


def test_c_shape_opening_entered_only_when_a_link_fits():
    slot = shapely.Polygon([(6, 1), (2, 1), (2, 3), (4, 3)])  # behind the lip line

    def joints_in_opening(ln, n):
        g = quasi_static_grasp(C_SHAPE, PlanarChain([ln] * n), start=0.02)
        assert g.complete, g.reason
        return int(np.sum(shapely.contains_xy(slot, *g.joints.T)))

    assert joints_in_opening(0.5, 30) >= 5
    assert joints_in_opening(3.5, 6) == 0


def test_agrees_with_the_simulated_grasp():
    pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")
    from tentaclass.physics import grasp

    for outline in (square(4.0), triangle(side=16 / 3)):
        q = quasi_static_grasp(outline, PlanarChain([1.0] * 16), start=0.1)
        g = grasp(outline, PlanarChain([1.0] * 16), start=0.1)
        assert q.laps == pytest.approx(g.laps, abs=0.005)
        dq = np.abs(np.angle(np.exp(1j * (q.angles - g.angles))))
        assert dq.max() < 0.01


def test_simulated_chain_on_a_lobed_object_rests_where_the_quasi_static_one_does():
    # 40 links, one and a half laps round a five-lobed flower: the braked joints must not
    # give way while the later links are driven onto them (a servo pressing as hard as the
    # brakes bent every joint behind it by hundredths of a radian: the chain unwound)
    pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")
    from tentaclass.physics import grasp

    th = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    rad = 3.0 * (1 + 0.15 * np.sin(5 * th))
    flower = polygon(np.c_[rad * np.cos(th), rad * np.sin(th)])
    chain = PlanarChain([1.0] * 40)
    g = grasp(flower, chain, start=0.3)
    q = quasi_static_grasp(flower, chain, start=0.3)
    assert g.complete and q.complete, g.reason
    assert g.laps == pytest.approx(q.laps, abs=0.02) and 1.4 < q.laps < 1.7
    dq = np.abs(np.angle(np.exp(1j * (q.angles - g.angles))))
    assert np.median(dq) < 0.02


def test_unreachable_is_flagged_and_bad_input_raises():
    g = quasi_static_grasp(square(1.0), PlanarChain([1.0] * 6), offset=8.0)
    assert not g.complete and "approach" in g.reason
    with pytest.raises(InputError, match="start"):
        quasi_static_grasp(square(1.0), PlanarChain([1.0] * 6), start=1.5)
    with pytest.raises(InputError, match="method"):
        grasp_many(square(1.0), PlanarChain([1.0] * 6), [0.0], method="rigid")


def test_grasp_many_quasi_static_matches_single_calls():
    chain = PlanarChain([0.5] * 12)
    outs = [square(2.0), triangle(side=3.0)]
    many = grasp_many(outs, chain, [0.1, 0.6], direction=["ccw", "cw"], method="quasi-static")
    for o, s, d, g in zip(outs, [0.1, 0.6], ["ccw", "cw"], many, strict=True):
        one = quasi_static_grasp(o, chain, start=s, direction=d)
        np.testing.assert_allclose(g.angles, one.angles)


def test_a_thickness_too_thin_to_build_is_refused():
    with pytest.raises(InputError, match=r"thickness 1e-300 is too thin for an object of diameter"):
        quasi_static_grasp(square(4.0), PlanarChain([1.0] * 8), thickness=1e-300)
