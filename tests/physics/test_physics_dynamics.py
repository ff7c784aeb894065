"""PlanarChain's dynamics against MuJoCo's (mj_fullM, mj_rne, mj_inverse) on random states."""

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")

from tentaclass import PlanarChain  # noqa: E402
from tentaclass.physics import build_model  # noqa: E402


def _chain(rng, n, gravity):
    return PlanarChain(
        rng.uniform(0.3, 1.5, n), masses=rng.uniform(0.2, 3.0, n), com=rng.uniform(0.0, 1.0, n),
        inertia=rng.uniform(0.01, 0.5, n), gravity=gravity,
    )  # fmt: skip


def _full_mass(m, d):
    out = np.zeros((m.nv, m.nv))
    try:
        mujoco.mj_fullM(m, d, out)  # MuJoCo >= 3.3
    except TypeError:
        mujoco.mj_fullM(m, out, d.qM)
    return out


@pytest.mark.parametrize("n", [1, 2, 5, 12])
@pytest.mark.parametrize("gravity", [False, True])
def test_dynamics_agree_with_mujoco(n, gravity, rng):
    chain = _chain(rng, n, 9.81)
    cm = build_model(chain, gravity=gravity)
    m = cm.model
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER  # mj_inverse without implicit terms
    d = mujoco.MjData(m)
    g = chain.gravity if gravity else 0.0
    ref = PlanarChain(chain.link_lengths, chain.masses, chain.com, chain.inertia, gravity=g)
    for _ in range(5):
        q, qd, qdd = rng.normal(0, 2, (3, n))
        d.qpos[:], d.qvel[:] = q, qd
        mujoco.mj_forward(m, d)
        np.testing.assert_allclose(_full_mass(m, d), ref.mass_matrix(q), rtol=0, atol=1e-9)
        bias = np.zeros(n)
        mujoco.mj_rne(m, d, 0, bias)  # C(q, qd) qd + g(q)
        np.testing.assert_allclose(bias, ref.bias_torques(q, qd), rtol=0, atol=1e-9)
        np.testing.assert_allclose(
            bias, ref.coriolis(q, qd) + ref.gravity_torques(q), rtol=0, atol=1e-9
        )
        d.qvel[:] = 0.0
        mujoco.mj_forward(m, d)
        mujoco.mj_rne(m, d, 0, bias)
        np.testing.assert_allclose(bias, ref.gravity_torques(q), rtol=0, atol=1e-9)
        d.qvel[:], d.qacc[:] = qd, qdd  # mj_forward overwrote qacc
        mujoco.mj_inverse(m, d)
        np.testing.assert_allclose(
            d.qfrc_inverse, ref.inverse_dynamics(q, qd, qdd), rtol=0, atol=1e-9
        )
        if not gravity:
            np.testing.assert_allclose(bias, 0.0, atol=1e-12)  # no gravity: rne at rest is 0


def test_coriolis_is_rne_without_gravity(rng):
    chain = _chain(rng, 6, 0.0)
    m = build_model(chain).model
    d = mujoco.MjData(m)
    q, qd = rng.normal(0, 2, (2, 6))
    d.qpos[:], d.qvel[:] = q, qd
    mujoco.mj_forward(m, d)
    out = np.zeros(6)
    mujoco.mj_rne(m, d, 0, out)
    np.testing.assert_allclose(out, chain.coriolis(q, qd), rtol=0, atol=1e-9)


def test_model_geometry(rng):
    chain = PlanarChain([1.0, 2.0, 0.5])
    cm = build_model(chain, base=(1.0, -1.0), heading=0.3, thickness=0.2, joint_range=(-1, 1))
    m = cm.model
    assert m.nv == 3 and m.opt.gravity.tolist() == [0.0, 0.0, 0.0]
    assert np.all(m.jnt_limited) and np.allclose(m.jnt_range, [[-1, 1]] * 3)
    d = mujoco.MjData(m)
    d.qpos[:] = [0.2, -0.4, 1.0]
    mujoco.mj_forward(m, d)
    q_abs = d.qpos + np.array([0.3, 0.0, 0.0])  # the base frame turned by the heading
    fk = chain.forward_kinematics(q_abs).joints + np.array([1.0, -1.0])
    np.testing.assert_allclose(d.xanchor[:, :2], fk[:3], atol=1e-12)
    assert np.allclose(m.geom_size[cm.link_geoms, 0], 0.1)
