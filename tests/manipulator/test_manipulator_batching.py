"""Batch contract: output shape = batch shape + core shape; batch == loop over rows."""

import numpy as np
import pytest
from manipulator_refs import random_chain

N = 3
CHAIN = random_chain(np.random.default_rng(0), N)

# method name, number of (..., n) arguments, core output shape
METHODS = [
    ("jacobian", 1, (2, N)),
    ("jacobian_dot", 2, (2, N)),
    ("com_jacobians", 1, (N, 3, N)),
    ("mass_matrix", 1, (N, N)),
    ("coriolis", 2, (N,)),
    ("gravity_torques", 1, (N,)),
    ("bias_torques", 2, (N,)),
    ("inverse_dynamics", 3, (N,)),
    ("forward_dynamics", 3, (N,)),
    ("energy", 2, ()),
]


def _call(name, args):
    if name == "forward_kinematics":
        fk = CHAIN.forward_kinematics(*args)
        return fk.joints, fk.com, fk.angles
    return (getattr(CHAIN, name)(*args),)


def _args(rng, n_args, batch):
    return [rng.uniform(-2, 2, (*batch, N)) for _ in range(n_args)]


@pytest.mark.parametrize("batch", [(), (3,), (2, 4)], ids=str)
@pytest.mark.parametrize(("name", "n_args", "core"), METHODS, ids=[m[0] for m in METHODS])
def test_shape_table(name, n_args, core, batch):
    out = getattr(CHAIN, name)(*_args(np.random.default_rng(1), n_args, batch))
    assert isinstance(out, np.ndarray)
    assert out.shape == (*batch, *core)


@pytest.mark.parametrize("batch", [(), (1,), (3,), (2, 4)], ids=str)
def test_forward_kinematics_shapes(batch):
    fk = CHAIN.forward_kinematics(np.zeros((*batch, N)))
    assert fk.joints.shape == (*batch, N + 1, 2)
    assert fk.com.shape == (*batch, N, 2)
    assert fk.angles.shape == (*batch, N)


@pytest.mark.parametrize(("name", "n_args", "core"), METHODS, ids=[m[0] for m in METHODS])
def test_batch_equals_loop_over_rows(name, n_args, core):
    args = _args(np.random.default_rng(2), n_args, (2, 4))
    batched = getattr(CHAIN, name)(*args)
    for idx in np.ndindex(2, 4):
        row = getattr(CHAIN, name)(*(a[idx] for a in args))
        assert row.shape == core
        np.testing.assert_allclose(batched[idx], row, rtol=1e-13, atol=1e-13)


def test_forward_kinematics_batch_equals_loop():
    q = np.random.default_rng(3).uniform(-2, 2, (5, N))
    fk = CHAIN.forward_kinematics(q)
    for k in range(5):
        row = CHAIN.forward_kinematics(q[k])
        np.testing.assert_allclose(fk.joints[k], row.joints, atol=1e-14)
        np.testing.assert_allclose(fk.com[k], row.com, atol=1e-14)
        np.testing.assert_allclose(fk.angles[k], row.angles, atol=1e-14)


def test_batch_axes_broadcast_against_each_other():
    rng = np.random.default_rng(4)
    q = rng.uniform(-2, 2, (4, 1, N))
    qd = rng.uniform(-2, 2, (5, N))
    qdd = rng.uniform(-2, 2, N)
    tau = CHAIN.inverse_dynamics(q, qd, qdd)
    assert tau.shape == (4, 5, N)
    np.testing.assert_allclose(tau[2, 3], CHAIN.inverse_dynamics(q[2, 0], qd[3], qdd), atol=1e-13)


def test_inputs_are_not_modified():
    rng = np.random.default_rng(5)
    q, qd, qdd = (rng.uniform(-2, 2, (3, N)) for _ in range(3))
    copies = [a.copy() for a in (q, qd, qdd)]
    CHAIN.inverse_dynamics(q, qd, qdd)
    CHAIN.forward_dynamics(q, qd, qdd)
    CHAIN.simulate(q, qd, None, [0.0, 0.01])
    for a, c in zip((q, qd, qdd), copies, strict=True):
        np.testing.assert_array_equal(a, c)
