"""Time integration: energy conservation, driven motion and integrator order."""

import numpy as np
import pytest
from manipulator_refs import random_chain

from tentaclass.manipulator import PlanarChain, Trajectory


def test_free_chain_conserves_energy_with_rk4():
    rng = np.random.default_rng(0)
    chain = random_chain(rng, 3)
    q0 = rng.uniform(-np.pi, np.pi, (4, 3))  # a batch of four swings
    qd0 = rng.normal(0.0, 1.0, (4, 3))
    t = np.linspace(0.0, 1.0, 2001)  # RK4 with a 0.5 ms step
    traj = chain.simulate(q0, qd0, None, t)
    assert isinstance(traj, Trajectory)
    assert traj.q.shape == traj.qd.shape == (2001, 4, 3)
    np.testing.assert_array_equal(traj.q[0], q0)
    energy = chain.energy(traj.q, traj.qd)
    assert energy.shape == (2001, 4)
    scale = np.max(np.abs(energy), axis=0)
    drift = np.max(np.abs(energy - energy[0]), axis=0) / scale
    assert np.all(drift < 1e-6), drift
    # The chain does move: this is not a trivially resting state.
    assert np.all(np.max(np.abs(traj.q - q0), axis=0) > 0.1)


def test_explicit_euler_gains_energy_and_converges_to_rk4():
    chain = PlanarChain([1.0, 0.8])
    q0, qd0 = [-0.5, 1.0], [0.0, 0.0]
    t = np.linspace(0.0, 0.5, 501)
    reference = chain.simulate(q0, qd0, None, t, method="rk4")
    euler = chain.simulate(q0, qd0, None, t, method="euler")
    coarse = chain.simulate(q0, qd0, None, t[::5], method="euler")
    energy = chain.energy(euler.q, euler.qd)
    assert energy[-1] > energy[0]  # explicit Euler pumps energy into an oscillator
    err_fine = np.max(np.abs(euler.q[-1] - reference.q[-1]))
    err_coarse = np.max(np.abs(coarse.q[-1] - reference.q[-1]))
    assert err_fine < 1e-2
    assert 3.0 < err_coarse / err_fine < 7.0  # first order: 5x the step, about 5x the error


def test_gravity_compensation_holds_the_chain():
    rng = np.random.default_rng(1)
    chain = random_chain(rng, 4)
    q0 = rng.uniform(-np.pi, np.pi, 4)
    traj = chain.simulate(q0, np.zeros(4), lambda t, q, qd: chain.gravity_torques(q), [0, 0.1, 0.2])
    np.testing.assert_allclose(traj.q, np.broadcast_to(q0, (3, 4)), atol=1e-12)
    # Without the torques it falls.
    free = chain.simulate(q0, np.zeros(4), None, [0, 0.1, 0.2])
    assert np.max(np.abs(free.q[-1] - q0)) > 1e-3


def test_constant_torque_matches_power_balance():
    # dE/dt = tau . qd: energy gained equals the work of the torques.
    chain = PlanarChain([1.0, 1.0], gravity=9.81)
    tau = np.array([2.0, -1.0])
    t = np.linspace(0.0, 0.5, 501)
    traj = chain.simulate([0.2, 0.3], [0.0, 0.0], lambda t, q, qd: tau, t)
    work = tau @ (traj.q[-1] - traj.q[0])
    energy = chain.energy(traj.q, traj.qd)
    np.testing.assert_allclose(energy[-1] - energy[0], work, rtol=1e-8)


def test_single_time_returns_the_initial_state():
    chain = PlanarChain([1.0, 1.0])
    traj = chain.simulate([[0.1, 0.2]], [[0.0, 0.0]], None, [0.0])
    assert traj.q.shape == (1, 1, 2)
    np.testing.assert_array_equal(traj.q[0], [[0.1, 0.2]])


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"t": [0.0, 0.1, 0.1]}, "t must be strictly increasing"),
        ({"t": [[0.0, 0.1]]}, "t must be a non-empty 1-D"),
        ({"t": [0.0, np.nan]}, "t contains"),
        ({"method": "leapfrog"}, "method must be one of"),
        ({"torque_fn": 3.0}, "torque_fn must be callable"),
        ({"torque_fn": lambda t, q, qd: np.zeros(3)}, r"torque_fn\(t, q, qd\) returned shape"),
        ({"torque_fn": lambda t, q, qd: [np.nan, 0.0]}, r"torque_fn\(t, q, qd\) contains"),
    ],
)
def test_bad_simulation_arguments(kwargs, match):
    from tentaclass.errors import InputError

    chain = PlanarChain([1.0, 1.0])
    args = {"q0": [0.0, 0.0], "qd0": [0.0, 0.0], "torque_fn": None, "t": [0.0, 0.1], **kwargs}
    with pytest.raises(InputError, match=match):
        chain.simulate(**args)
