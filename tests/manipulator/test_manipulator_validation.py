"""Bad input raises InputError (a ValueError) naming the argument."""

import numpy as np
import pytest

from tentaclass.errors import InputError, ShapeError
from tentaclass.manipulator import PlanarChain


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"link_lengths": [1.0, 0.0]}, "link_lengths must all be > 0"),
        ({"link_lengths": [1.0, -2.0]}, "link_lengths must all be > 0"),
        ({"link_lengths": [1.0, np.nan]}, "link_lengths contains 1 NaN"),
        ({"link_lengths": [[1.0, 1.0]]}, "link_lengths must be a number or a 1-D array"),
        ({"link_lengths": []}, "link_lengths is empty"),
        ({"link_lengths": "long"}, "link_lengths must be an array of numbers"),
        ({"link_lengths": 1.0}, "link_lengths must list one length per link"),
        ({"masses": [1.0, 0.0]}, "masses must all be > 0"),
        ({"masses": -1.0}, "masses must all be > 0"),
        ({"masses": [1.0, 1.0, 1.0]}, "masses has 3 entries but the chain has 2 links"),
        ({"com": [0.5, 1.5]}, r"com must lie in \[0, 1\]"),
        ({"com": -0.1}, r"com must lie in \[0, 1\]"),
        ({"com": [0.5, np.inf]}, "com contains 1 NaN or infinite"),
        ({"inertia": [0.1, -0.1]}, "inertia must all be >= 0"),
        ({"inertia": [0.1]}, "inertia has 1 entries but the chain has 2 links"),
        ({"com": [0.5, 0.0], "inertia": [0.1, 0.0]}, "the last link is a point mass"),
        ({"gravity": -9.81}, "gravity must be a finite number >= 0"),
        ({"gravity": np.nan}, "gravity must be a finite number >= 0"),
    ],
)
def test_bad_chain_parameters(kwargs, match):
    args = {"link_lengths": [1.0, 1.0], **kwargs}
    with pytest.raises(InputError, match=match) as info:
        PlanarChain(**args)
    assert isinstance(info.value, ValueError)


def test_scalar_parameters_take_their_length_from_an_array():
    chain = PlanarChain(0.5, masses=[1.0, 2.0, 3.0])
    assert chain.n_links == 3
    np.testing.assert_array_equal(chain.link_lengths, [0.5, 0.5, 0.5])
    np.testing.assert_allclose(chain.inertia, chain.masses * 0.25 / 12)


def test_parameters_are_read_only_copies():
    lengths = np.array([1.0, 2.0])
    chain = PlanarChain(lengths)
    lengths[0] = 5.0
    assert chain.link_lengths[0] == 1.0
    with pytest.raises(ValueError, match="read-only"):
        chain.masses[0] = 2.0


CHAIN = PlanarChain([1.0, 1.0, 1.0])
GOOD = np.zeros(3)


@pytest.mark.parametrize(
    ("method", "args", "name"),
    [
        ("forward_kinematics", ([0.0, 0.0],), "q"),
        ("jacobian", ([0.0, 0.0, 0.0, 0.0],), "q"),
        ("mass_matrix", (np.zeros((4, 2)),), "q"),
        ("jacobian_dot", (GOOD, [0.0, 0.0]), "qd"),
        ("coriolis", ([0.0], GOOD), "q"),
        ("inverse_dynamics", (GOOD, GOOD, np.zeros(4)), "qdd"),
        ("forward_dynamics", (GOOD, GOOD, np.zeros(2)), "tau"),
        ("forward_dynamics", (GOOD, np.zeros(5), GOOD), "qd"),
        ("energy", (GOOD, np.zeros((2, 2))), "qd"),
        ("simulate", (GOOD, np.zeros(2), None, [0.0, 1.0]), "qd0"),
    ],
)
def test_joint_arrays_must_match_the_chain(method, args, name):
    with pytest.raises(ShapeError, match=rf"^{name} must have 3 entries along its last axis"):
        getattr(CHAIN, method)(*args)


@pytest.mark.parametrize(
    ("method", "args", "name"),
    [
        ("forward_kinematics", ([0.0, np.nan, 0.0],), "q"),
        ("gravity_torques", ([0.0, np.inf, 0.0],), "q"),
        ("coriolis", (GOOD, [0.0, np.nan, 0.0]), "qd"),
        ("inverse_dynamics", (GOOD, GOOD, [np.nan, 0.0, 0.0]), "qdd"),
        ("forward_dynamics", (GOOD, GOOD, [np.nan, 0.0, 0.0]), "tau"),
        ("simulate", ([np.nan, 0.0, 0.0], GOOD, None, [0.0, 1.0]), "q0"),
    ],
)
def test_nan_is_refused(method, args, name):
    with pytest.raises(InputError, match=rf"^{name} contains 1 NaN or infinite value"):
        getattr(CHAIN, method)(*args)


@pytest.mark.parametrize("q", [0.0, [], np.zeros((2, 0))])
def test_scalar_or_empty_q_is_refused(q):
    with pytest.raises(ShapeError, match=r"^q "):
        CHAIN.mass_matrix(q)


def test_batch_shapes_that_do_not_broadcast():
    with pytest.raises(ShapeError, match=r"batch shapes of q \(2, 3\), qd \(4, 3\)"):
        CHAIN.coriolis(np.zeros((2, 3)), np.zeros((4, 3)))


def test_parameters_cannot_be_reassigned():
    chain = PlanarChain([1.0, 2.0])
    with pytest.raises(AttributeError):
        chain.masses = [5.0, 5.0]
    with pytest.raises(AttributeError):
        chain.gravity = 0.0
    assert repr(chain) == (
        "PlanarChain(link_lengths=[1.0, 2.0], masses=[1.0, 1.0], com=[0.5, 0.5], "
        "inertia=[0.08333333333333333, 0.3333333333333333], gravity=9.81)"
    )
