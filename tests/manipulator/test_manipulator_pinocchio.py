"""Agreement with Pinocchio on random chains."""

import numpy as np
import pytest
from manipulator_refs import pinocchio_model, random_chain

pin = pytest.importorskip("pinocchio")

N_CONFIGS = 5


def _assert_close(ours, ref):
    scale = np.max(np.abs(ref))
    np.testing.assert_allclose(ours, ref, rtol=1e-9, atol=1e-9 * scale)


@pytest.fixture(params=[1, 2, 3, 16, 64], ids=lambda n: f"n{n}")
def case(request):
    n = request.param
    rng = np.random.default_rng(1000 + n)
    chain = random_chain(rng, n)
    model, data = pinocchio_model(chain)
    q = rng.uniform(-np.pi, np.pi, (N_CONFIGS, n))
    qd = rng.normal(0.0, 2.0, (N_CONFIGS, n))
    qdd = rng.normal(0.0, 2.0, (N_CONFIGS, n))
    return chain, model, data, q, qd, qdd


def test_mass_matrix(case):
    chain, model, data, q, _, _ = case
    ours = chain.mass_matrix(q)
    for k in range(N_CONFIGS):
        upper = pin.crba(model, data, q[k])
        ref = np.triu(upper) + np.triu(upper, 1).T  # crba fills the upper triangle
        _assert_close(ours[k], ref)


def test_coriolis(case):
    chain, model, data, q, qd, _ = case
    ours = chain.coriolis(q, qd)
    for k in range(N_CONFIGS):
        ref = pin.computeCoriolisMatrix(model, data, q[k], qd[k]) @ qd[k]
        _assert_close(ours[k], ref)


def test_gravity_torques(case):
    chain, model, data, q, _, _ = case
    ours = chain.gravity_torques(q)
    for k in range(N_CONFIGS):
        _assert_close(ours[k], pin.computeGeneralizedGravity(model, data, q[k]))


def test_bias_torques(case):
    chain, model, data, q, qd, _ = case
    ours = chain.bias_torques(q, qd)
    for k in range(N_CONFIGS):
        _assert_close(ours[k], pin.nonLinearEffects(model, data, q[k], qd[k]))


def test_inverse_dynamics(case):
    chain, model, data, q, qd, qdd = case
    ours = chain.inverse_dynamics(q, qd, qdd)
    for k in range(N_CONFIGS):
        _assert_close(ours[k], pin.rnea(model, data, q[k], qd[k], qdd[k]))


def test_forward_dynamics(case):
    chain, model, data, q, qd, _ = case
    tau = np.random.default_rng(7).normal(size=q.shape)
    ours = chain.forward_dynamics(q, qd, tau)
    for k in range(N_CONFIGS):
        ref = pin.aba(model, data, q[k], qd[k], tau[k])
        # qdd inherits the conditioning of H (cond ~ 5e6 at n = 64): errors ~ 1e-11.
        _assert_close(ours[k], ref)


def test_end_point_and_jacobian(case):
    chain, model, data, q, _, _ = case
    frame = model.addFrame(
        pin.Frame(
            "tip",
            model.njoints - 1,
            pin.SE3(np.eye(3), np.array([chain.link_lengths[-1], 0.0, 0.0])),
            pin.FrameType.OP_FRAME,
        )
    )
    data = model.createData()
    fk = chain.forward_kinematics(q)
    jac = chain.jacobian(q)
    for k in range(N_CONFIGS):
        pin.computeJointJacobians(model, data, q[k])
        pin.updateFramePlacements(model, data)
        ref_pos = data.oMf[frame].translation[:2]
        ref_jac = pin.getFrameJacobian(model, data, frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        np.testing.assert_allclose(fk.joints[k, -1], ref_pos, rtol=1e-12, atol=1e-12)
        ref_jac = np.reshape(ref_jac, (6, chain.n_links))[:2]  # Pinocchio drops the axis at n=1
        np.testing.assert_allclose(
            jac[k], ref_jac, rtol=1e-12, atol=1e-12 * np.max(np.abs(ref_jac))
        )
