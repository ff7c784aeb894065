"""Dynamics kernels of a planar serial chain: RNEA, CRBA, energy.

Every kernel takes clean float arrays broadcast to ``(..., n)`` (validated by
:class:`~.chain.PlanarChain`) and is vectorised over the leading axes. The
recursions over the links are written as prefix sums (``np.cumsum`` runs the
recursion ``s_i = s_{i-1} + t_i`` in C), so each kernel costs O(n) per
configuration (O(n^2) for the mass matrix, which has n^2 entries) with no Python
loop over links or configurations.

Notation as in :mod:`.kinematics`; ``m_i`` is the mass of link ``i``, ``I_i``
its inertia about its centre of mass and ``G`` the gravitational acceleration
(gravity points along -y).
"""

from __future__ import annotations

import numpy as np

from .._typing import FloatArray
from .kinematics import cumsum_excl, link_vectors, rcumsum, rcumsum_excl

__all__: list[str] = []


def rnea(
    q: FloatArray,
    qd: FloatArray | None,
    qdd: FloatArray | None,
    lengths: FloatArray,
    com_lengths: FloatArray,
    masses: FloatArray,
    inertia: FloatArray,
    gravity: float,
) -> FloatArray:
    """Planar recursive Newton-Euler algorithm: ``tau = H qdd + h + g``.

    ``qd=None`` or ``qdd=None`` stand for zeros (their terms are skipped).

    Forward recursion (base to tip), with gravity folded in as an upward
    acceleration ``(0, G)`` of the base::

        w_i  = w_{i-1} + qd_i,        al_i = al_{i-1} + qdd_i
        a_i  = a_{i-1} + al_{i-1} perp(r_{i-1}) - w_{i-1}^2 r_{i-1},  a_1 = (0, G)
        ac_i = a_i + al_i perp(c_i) - w_i^2 c_i

    (``a_i`` the acceleration of joint ``i``, ``ac_i`` of the centre of mass).
    Backward recursion (tip to base) for the force ``f_i`` and the moment
    ``tau_i`` that link ``i - 1`` exerts on link ``i`` at joint ``i``::

        f_i   = f_{i+1} + m_i ac_i
        tau_i = tau_{i+1} + I_i al_i + c_i x (m_i ac_i) + r_i x f_{i+1}

    with ``f_{n+1} = 0``, ``tau_{n+1} = 0`` and ``a x b = a_x b_y - a_y b_x``.
    """
    _, rx, ry, cx, cy = link_vectors(q, lengths, com_lengths)
    # Per link: acceleration of its tip (t) and of its centre of mass (u)
    # relative to its start joint.
    tx = np.zeros_like(rx)
    ty = np.zeros_like(ry)
    ux = np.zeros_like(rx)
    uy = np.zeros_like(ry)
    torque = np.zeros_like(rx)
    if qd is not None:
        w2 = np.cumsum(qd, axis=-1) ** 2
        tx -= w2 * rx
        ty -= w2 * ry
        ux -= w2 * cx
        uy -= w2 * cy
    if qdd is not None:
        al = np.cumsum(qdd, axis=-1)
        tx -= al * ry
        ty += al * rx
        ux -= al * cy
        uy += al * cx
        torque += inertia * al
    acx = cumsum_excl(tx) + ux
    acy = cumsum_excl(ty) + uy + gravity
    fx = masses * acx
    fy = masses * acy
    # Forces from the links beyond link i: f_{i+1}.
    fnx = rcumsum_excl(fx)
    fny = rcumsum_excl(fy)
    torque = torque + (cx * fy - cy * fx) + (rx * fny - ry * fnx)
    return rcumsum(torque)


def composite_inertias(
    q: FloatArray,
    lengths: FloatArray,
    com_lengths: FloatArray,
    masses: FloatArray,
    inertia: FloatArray,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Composite bodies ``i..n`` about joint ``i`` (backward CRBA recursion).

    Returns joint positions ``(px, py)`` of joints ``1..n``, the first moment
    ``s_i = sum_{k>=i} m_k (x_ck - p_{i-1})`` as ``(sx, sy)`` and the composite
    inertia ``K_i = sum_{k>=i} I_k + m_k |x_ck - p_{i-1}|^2`` about joint ``i``,
    from the parallel-axis recursion::

        M_i = M_{i+1} + m_i
        s_i = s_{i+1} + M_{i+1} r_i + m_i c_i
        K_i = K_{i+1} + 2 r_i . s_{i+1} + M_{i+1} l_i^2 + I_i + m_i |c_i|^2
    """
    phi = np.cumsum(q, axis=-1)
    cos, sin = np.cos(phi), np.sin(phi)
    rx, ry = lengths * cos, lengths * sin
    # M_{i+1} and the per-link constants of the recursion, shape (n,).
    m_beyond = rcumsum_excl(np.broadcast_to(masses, lengths.shape))
    lever = m_beyond * lengths + masses * com_lengths  # M_{i+1} r_i + m_i c_i = lever_i (cos, sin)
    own = m_beyond * lengths**2 + inertia + masses * com_lengths**2
    sx = rcumsum(lever * cos)
    sy = rcumsum(lever * sin)
    terms = np.array(np.broadcast_to(own, rx.shape))
    terms[..., :-1] += 2.0 * (rx[..., :-1] * sx[..., 1:] + ry[..., :-1] * sy[..., 1:])
    return cumsum_excl(rx), cumsum_excl(ry), sx, sy, rcumsum(terms)


def crba(
    q: FloatArray,
    lengths: FloatArray,
    com_lengths: FloatArray,
    masses: FloatArray,
    inertia: FloatArray,
) -> FloatArray:
    """Mass matrix by the composite-rigid-body algorithm, shape ``(..., n, n)``.

    A unit acceleration of joint ``j`` (all else at rest, no gravity) spins the
    composite body ``j..n`` about joint ``j``; the moment it needs about joint
    ``i <= j`` is ``H_ij = K_j + (p_{j-1} - p_{i-1}) . s_j`` (the RNEA backward
    pass for ``qdd = e_j``), and ``H_ji = H_ij``.
    """
    px, py, sx, sy, k = composite_inertias(q, lengths, com_lengths, masses, inertia)
    n = q.shape[-1]
    # upper[..., i, j] = (K_j + p_j . s_j) - p_i . s_j, valid for i <= j: one
    # batched (n, 3) @ (3, n) product, then the lower triangle mirrored.
    left = np.empty((*k.shape, 3))
    left[..., 0] = 1.0
    np.negative(px, out=left[..., 1])
    np.negative(py, out=left[..., 2])
    right = np.empty((*k.shape[:-1], 3, n))
    right[..., 0, :] = k + px * sx + py * sy
    right[..., 1, :] = sx
    right[..., 2, :] = sy
    mass = np.matmul(left, right)
    if n > 32:  # one masked pass beats n strided copies once the matrices are large
        return np.where(np.triu(np.ones((n, n), dtype=bool)), mass, np.swapaxes(mass, -1, -2))
    for i in range(n - 1):
        mass[..., i + 1 :, i] = mass[..., i, i + 1 :]
    return mass


def energy(
    q: FloatArray,
    qd: FloatArray,
    lengths: FloatArray,
    com_lengths: FloatArray,
    masses: FloatArray,
    inertia: FloatArray,
    gravity: float,
) -> FloatArray:
    """Kinetic plus potential energy, from the link velocities directly.

    ``T = sum_i (m_i |v_ci|^2 + I_i w_i^2) / 2`` with
    ``v_ci = sum_{k<i} w_k perp(r_k) + w_i perp(c_i)``, and ``V = G sum_i m_i y_ci``.
    """
    _, rx, ry, cx, cy = link_vectors(q, lengths, com_lengths)
    w = np.cumsum(qd, axis=-1)
    vx = -cumsum_excl(w * ry) - w * cy
    vy = cumsum_excl(w * rx) + w * cx
    kinetic = 0.5 * (masses * (vx**2 + vy**2) + inertia * w**2)
    yc = cumsum_excl(ry) + cy
    return np.asarray(np.sum(kinetic + gravity * masses * yc, axis=-1))
