"""Dynamics: mass matrix, Coriolis, gravity, inverse and forward dynamics."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from manipulator_refs import double_pendulum, random_chain

from strategies import examples
from tentaclass.manipulator import PlanarChain


@st.composite
def chains_and_states(draw, max_links=6):
    n = draw(st.integers(1, max_links))
    floats = lambda lo, hi: st.lists(  # noqa: E731
        st.floats(lo, hi, allow_nan=False, allow_infinity=False), min_size=n, max_size=n
    )
    chain = PlanarChain(
        link_lengths=draw(floats(0.1, 3.0)),
        masses=draw(floats(0.1, 5.0)),
        com=draw(floats(0.0, 1.0)),
        inertia=draw(floats(0.01, 1.0)),  # > 0 keeps H definite everywhere
        gravity=draw(st.floats(0.0, 20.0)),
    )
    q = np.array(draw(floats(-np.pi, np.pi)))
    qd = np.array(draw(floats(-5.0, 5.0)))
    qdd = np.array(draw(floats(-5.0, 5.0)))
    return chain, q, qd, qdd


def test_double_pendulum_known_values():
    # Unit rods, centres of mass at the middle: H(0) = [[8/3, 5/6], [5/6, 1/3]].
    chain = PlanarChain([1.0, 1.0], gravity=10.0)
    np.testing.assert_allclose(
        chain.mass_matrix([0.0, 0.0]), [[8 / 3, 5 / 6], [5 / 6, 1 / 3]], rtol=1e-14
    )
    # Horizontal: g = (10 (0.5 + 1) + 10 * 0.5, 10 * 0.5).
    np.testing.assert_allclose(chain.gravity_torques([0.0, 0.0]), [20.0, 5.0], rtol=1e-14)
    # Elbow at 90 degrees, only joint 1 turning: h = (0, m2 l1 lc2 qd1^2).
    np.testing.assert_allclose(chain.coriolis([0.0, np.pi / 2], [2.0, 0.0]), [0.0, 2.0], atol=1e-14)


@pytest.mark.parametrize("seed", range(5))
def test_double_pendulum_closed_form(seed):
    rng = np.random.default_rng(seed)
    chain = random_chain(rng, 2)
    q = rng.uniform(-np.pi, np.pi, 2)
    qd = rng.normal(size=2)
    qdd = rng.normal(size=2)
    mass, cor, grav = double_pendulum(chain, q, qd)
    np.testing.assert_allclose(chain.mass_matrix(q), mass, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(chain.coriolis(q, qd), cor, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(chain.gravity_torques(q), grav, rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(
        chain.inverse_dynamics(q, qd, qdd), mass @ qdd + cor + grav, rtol=1e-12, atol=1e-13
    )


@settings(deadline=None, max_examples=examples(60))
@given(chains_and_states())
def test_mass_matrix_is_symmetric_positive_definite(case):
    chain, q, _, _ = case
    mass = chain.mass_matrix(q)
    np.testing.assert_array_equal(mass, mass.T)
    assert np.all(np.linalg.eigvalsh(mass) > 0)
    # H = sum_i m_i J_Li^T J_Li + I_i J_Ai^T J_Ai (eqs 2.11-2.12).
    jc = chain.com_jacobians(q)
    lin, ang = jc[:, :2, :], jc[:, 2, :]
    expected = np.einsum("i,ikj,ikl->jl", chain.masses, lin, lin) + np.einsum(
        "i,ij,il->jl", chain.inertia, ang, ang
    )
    np.testing.assert_allclose(mass, expected, rtol=1e-10, atol=1e-10 * np.max(expected))


@settings(deadline=None, max_examples=examples(60))
@given(chains_and_states())
def test_inverse_dynamics_is_h_qdd_plus_h_plus_g(case):
    chain, q, qd, qdd = case
    tau = chain.inverse_dynamics(q, qd, qdd)
    parts = chain.mass_matrix(q) @ qdd + chain.coriolis(q, qd) + chain.gravity_torques(q)
    np.testing.assert_allclose(tau, parts, rtol=1e-10, atol=1e-10 * (1 + np.max(np.abs(tau))))
    np.testing.assert_allclose(
        chain.bias_torques(q, qd), chain.coriolis(q, qd) + chain.gravity_torques(q), atol=1e-9
    )
    # Forward dynamics inverts inverse dynamics.
    np.testing.assert_allclose(
        chain.forward_dynamics(q, qd, tau), qdd, atol=1e-6 * (1 + np.max(np.abs(qdd)))
    )


@settings(deadline=None, max_examples=examples(40))
@given(chains_and_states())
def test_kinetic_energy_is_quadratic_form(case):
    chain, q, qd, _ = case
    free = PlanarChain(chain.link_lengths, chain.masses, chain.com, chain.inertia, gravity=0.0)
    kinetic = 0.5 * qd @ chain.mass_matrix(q) @ qd
    np.testing.assert_allclose(free.energy(q, qd), kinetic, rtol=1e-10, atol=1e-12)
    potential = chain.gravity * chain.masses @ chain.forward_kinematics(q).com[:, 1]
    np.testing.assert_allclose(chain.energy(q, qd), kinetic + potential, rtol=1e-10, atol=1e-9)


@pytest.mark.parametrize("n", [1, 3, 7])
def test_gravity_follows_thesis_recursion(n):
    """Eq. 2.15: g_i = g_{i+1} + G (m_i l_ci + l_i sum_{k>i} m_k) cos(phi_i)."""
    rng = np.random.default_rng(40 + n)
    chain = random_chain(rng, n)
    q = rng.uniform(-np.pi, np.pi, n)
    phi = np.cumsum(q)
    lc = chain.com * chain.link_lengths
    expected = np.zeros(n + 1)
    for i in reversed(range(n)):
        lever = chain.masses[i] * lc[i] + chain.link_lengths[i] * chain.masses[i + 1 :].sum()
        expected[i] = expected[i + 1] + chain.gravity * lever * np.cos(phi[i])
    np.testing.assert_allclose(chain.gravity_torques(q), expected[:n], rtol=1e-12, atol=1e-12)
    # g is the gradient of the potential energy.
    eps = 1e-6
    potential = lambda x: chain.energy(x, np.zeros(n))  # noqa: E731
    grad = [(potential(q + eps * e) - potential(q - eps * e)) / (2 * eps) for e in np.eye(n)]
    np.testing.assert_allclose(chain.gravity_torques(q), grad, rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize("n", [2, 4, 6])
def test_coriolis_from_christoffel_symbols(n):
    """Eqs 2.13-2.14: h_i = sum_jk (dH_ij/dq_k - dH_jk/dq_i / 2) qd_j qd_k."""
    rng = np.random.default_rng(50 + n)
    chain = random_chain(rng, n)
    q = rng.uniform(-np.pi, np.pi, n)
    qd = rng.normal(size=n)
    eps = 1e-6
    # dmass[k] = dH/dq_k
    dmass = np.stack(
        [
            (chain.mass_matrix(q + eps * e) - chain.mass_matrix(q - eps * e)) / (2 * eps)
            for e in np.eye(n)
        ]
    )
    h_ijk = np.einsum("kij->ijk", dmass) - 0.5 * dmass  # dmass[i, j, k] = dH_jk/dq_i
    expected = np.einsum("ijk,j,k->i", h_ijk, qd, qd)
    np.testing.assert_allclose(chain.coriolis(q, qd), expected, rtol=1e-6, atol=1e-7)
    # Coriolis torques do no work: qd . h = qd^T Hdot qd / 2.
    hdot = np.einsum("kij,k->ij", dmass, qd)
    np.testing.assert_allclose(qd @ chain.coriolis(q, qd), 0.5 * qd @ hdot @ qd, atol=1e-6)


def test_mass_matrix_columns_are_unit_acceleration_torques():
    rng = np.random.default_rng(3)
    chain = random_chain(rng, 5, gravity=0.0)
    q = rng.uniform(-np.pi, np.pi, 5)
    columns = chain.inverse_dynamics(q, np.zeros(5), np.eye(5))  # batch of unit accelerations
    np.testing.assert_allclose(chain.mass_matrix(q), columns.T, rtol=1e-12, atol=1e-12)


def test_gravity_scales_linearly_and_vanishes_when_hanging():
    chain = PlanarChain([1.0, 2.0, 0.5], masses=[1.0, 2.0, 3.0], gravity=9.81)
    hanging = [-np.pi / 2, 0.0, 0.0]
    np.testing.assert_allclose(chain.gravity_torques(hanging), 0.0, atol=1e-13)
    light = PlanarChain([1.0, 2.0, 0.5], masses=[1.0, 2.0, 3.0], gravity=1.0)
    q = [0.3, -0.2, 0.9]
    np.testing.assert_allclose(chain.gravity_torques(q), 9.81 * light.gravity_torques(q))
