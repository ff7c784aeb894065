"""Kinematics: forward kinematics, Jacobians and their derivatives."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from manipulator_refs import random_chain

from strategies import examples
from tentaclass.geometry import angles_to_points
from tentaclass.manipulator import ChainKinematics, PlanarChain

EPS = 1e-6


def _central_diff(f, q, direction):
    return (f(q + EPS * direction) - f(q - EPS * direction)) / (2 * EPS)


@pytest.mark.parametrize("n", [1, 2, 5, 16])
def test_forward_kinematics_matches_geometry(n):
    rng = np.random.default_rng(n)
    chain = random_chain(rng, n)
    q = rng.uniform(-np.pi, np.pi, (4, n))
    fk = chain.forward_kinematics(q)
    assert isinstance(fk, ChainKinematics)
    np.testing.assert_allclose(fk.joints, angles_to_points(q, chain.link_lengths), atol=1e-12)
    np.testing.assert_allclose(fk.angles, np.cumsum(q, axis=-1), atol=1e-12)
    # Each centre of mass lies on its link at the fraction com.
    start, end = fk.joints[..., :-1, :], fk.joints[..., 1:, :]
    expected = start + chain.com[:, None] * (end - start)
    np.testing.assert_allclose(fk.com, expected, atol=1e-12)


def test_forward_kinematics_is_frozen():
    fk = PlanarChain([1.0, 1.0]).forward_kinematics([0.1, 0.2])
    with pytest.raises(AttributeError):
        fk.joints = np.zeros((3, 2))


def test_two_link_closed_form():
    chain = PlanarChain([1.5, 0.7])
    q1, q2 = 0.4, -1.1
    s1, c1 = np.sin(q1), np.cos(q1)
    s12, c12 = np.sin(q1 + q2), np.cos(q1 + q2)
    np.testing.assert_allclose(
        chain.forward_kinematics([q1, q2]).joints[-1],
        [1.5 * c1 + 0.7 * c12, 1.5 * s1 + 0.7 * s12],
        atol=1e-14,
    )
    np.testing.assert_allclose(
        chain.jacobian([q1, q2]),
        [[-1.5 * s1 - 0.7 * s12, -0.7 * s12], [1.5 * c1 + 0.7 * c12, 0.7 * c12]],
        atol=1e-14,
    )
    qd1, qd2 = 0.8, -0.3
    w12 = qd1 + qd2
    np.testing.assert_allclose(
        chain.jacobian_dot([q1, q2], [qd1, qd2]),
        [
            [-1.5 * c1 * qd1 - 0.7 * c12 * w12, -0.7 * c12 * w12],
            [-1.5 * s1 * qd1 - 0.7 * s12 * w12, -0.7 * s12 * w12],
        ],
        atol=1e-14,
    )


@pytest.mark.parametrize("n", [1, 3, 8])
def test_jacobian_matches_finite_differences(n):
    rng = np.random.default_rng(10 + n)
    chain = random_chain(rng, n)
    q = rng.uniform(-np.pi, np.pi, n)
    end = lambda x: chain.forward_kinematics(x).joints[-1]  # noqa: E731
    fd = np.stack([_central_diff(end, q, e) for e in np.eye(n)], axis=-1)
    np.testing.assert_allclose(chain.jacobian(q), fd, atol=1e-8)


@pytest.mark.parametrize("n", [1, 3, 8])
def test_jacobian_dot_matches_finite_differences(n):
    rng = np.random.default_rng(20 + n)
    chain = random_chain(rng, n)
    q = rng.uniform(-np.pi, np.pi, n)
    qd = rng.normal(size=n)
    # dJ/dt = dJ/dq . qd: a directional derivative along qd (eq. 2.9).
    fd = _central_diff(chain.jacobian, q, qd)
    np.testing.assert_allclose(chain.jacobian_dot(q, qd), fd, atol=1e-8)
    # And xdd = J qdd + Jd qd (eq. 2.3): the end point's acceleration along a path.
    qdd = rng.normal(size=n)
    end = lambda t: chain.forward_kinematics(q + qd * t + 0.5 * qdd * t**2).joints[-1]  # noqa: E731
    h = 1e-4
    acc = (end(h) - 2 * end(0.0) + end(-h)) / h**2
    np.testing.assert_allclose(
        chain.jacobian(q) @ qdd + chain.jacobian_dot(q, qd) @ qd, acc, atol=1e-5
    )


@pytest.mark.parametrize("n", [1, 3, 8])
def test_com_jacobians_match_finite_differences(n):
    rng = np.random.default_rng(30 + n)
    chain = random_chain(rng, n)
    q = rng.uniform(-np.pi, np.pi, n)

    def pose(x):
        fk = chain.forward_kinematics(x)
        return np.concatenate([fk.com, fk.angles[:, None]], axis=-1)  # (n, 3)

    fd = np.stack([_central_diff(pose, q, e) for e in np.eye(n)], axis=-1)  # (n, 3, n)
    jc = chain.com_jacobians(q)
    assert jc.shape == (n, 3, n)
    np.testing.assert_allclose(jc, fd, atol=1e-8)
    # Angle rows: phi_i = q_1 + ... + q_i.
    np.testing.assert_array_equal(jc[..., 2, :], np.tril(np.ones((n, n))))


@settings(deadline=None, max_examples=examples(40))
@given(
    n=st.integers(1, 6),
    seed=st.integers(0, 2**32 - 1),
    scale=st.floats(0.01, 10.0),
)
def test_velocity_of_end_point_is_j_qd(n, seed, scale):
    rng = np.random.default_rng(seed)
    chain = PlanarChain(rng.uniform(0.1, 3.0, n) * scale)
    q = rng.uniform(-np.pi, np.pi, n)
    qd = rng.uniform(-2, 2, n)
    # Velocity of the end point along q(t) = q + qd t, by central differences.
    end = lambda x: chain.forward_kinematics(x).joints[-1]  # noqa: E731
    fd = _central_diff(end, q, qd)
    np.testing.assert_allclose(chain.jacobian(q) @ qd, fd, atol=1e-7 * scale * n)
