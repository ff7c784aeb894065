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
        ({"link_lengths": "long"}, "link_lengths must hold numbers, got dtype <U4"),
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
        # a KeyError before
        ({"masses": None}, "masses must be a number or one per link, got None"),
        ({"com": None}, "com must be a number or one per link, got None"),
        ({"link_lengths": None}, "link_lengths must be a number or one per link, got None"),
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


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"link_lengths": [1e200, 1e200]}, r"mass matrix of scale inf .* express them in other"),
        ({"masses": 1e308}, r"mass matrix of scale inf"),
        ({"link_lengths": [1e-200, 1e-200]}, r"scale 0 .* outside \[1e-200, 1e\+200\]"),
        ({"gravity": 1e300}, r"gravity 1e\+300 gives gravity torques of scale 4e\+300"),
    ],
)
def test_dynamics_refuse_parameters_beyond_float64(kwargs, match):
    chain = PlanarChain(**({"link_lengths": [1.0, 1.0]} | kwargs))
    chain.forward_kinematics([0.1, 0.2])  # kinematics take any lengths
    with pytest.raises(InputError, match=match):
        chain.forward_dynamics([0.1, 0.2], [0.0, 0.0], [0.0, 0.0])


@pytest.mark.parametrize(
    ("method", "args", "what"),
    [
        ("coriolis", ([0.0, 0.0], [1e300, 0.0]), "the Coriolis torques"),
        ("bias_torques", ([0.0, 0.0], [1e300, 0.0]), "the bias torques"),
        ("inverse_dynamics", ([0.0, 0.0], [0.0, 0.0], [1e308, -1e308]), "the joint torques"),
        ("forward_dynamics", ([0.0, 0.0], [0.0, 0.0], [1e308, -1e308]), "the joint accelerations"),
        ("energy", ([0.0, 0.0], [1e200, 0.0]), "the energies"),
    ],
)
def test_results_that_overflow_are_refused(method, args, what):
    chain = PlanarChain([1.0, 1.0])
    with pytest.raises(InputError, match=rf"^{what} overflow float64"):
        getattr(chain, method)(*args)


def test_singular_mass_matrix_names_the_point_masses():
    chain = PlanarChain([1.0, 1.0, 1.0], inertia=0.0, com=[0.0, 0.5, 0.5])
    with pytest.raises(InputError, match=r"mass matrix is singular .* point-mass links"):
        chain.forward_dynamics([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])


def test_a_diverging_simulation_is_refused_not_returned_as_nan():
    chain = PlanarChain([1.0, 1.0, 1.0])
    # steps of 2 s: RK4 on a pendulum chain blows up within a few steps
    with pytest.raises(InputError, match=r"simulation diverged between t = 4.08163 and 6.12245"):
        chain.simulate([1.0, 0.0, 0.0], [0.0, 0.0, 0.0], None, np.linspace(0.0, 100.0, 50))
    with pytest.raises(InputError, match="torques too large"):
        chain.simulate([0.0] * 3, [0.0] * 3, lambda t, q, qd: 1e308, [0.0, 1.0])
    # small steps of the same motion stay finite
    q, qd = chain.simulate([1.0, 0.0, 0.0], [0.0] * 3, None, np.linspace(0.0, 1.0, 201))
    assert np.all(np.isfinite(q)) and np.all(np.isfinite(qd))


def test_torque_function_returning_none_is_named():
    chain = PlanarChain([1.0, 1.0])
    with pytest.raises(InputError, match=r"^torque_fn\(t, q, qd\) returned None"):
        chain.simulate([0.0, 0.0], [0.0, 0.0], lambda t, q, qd: None, [0.0, 0.1])
