"""The planar n-link manipulator: kinematics and dynamics, batched.

The chain lies in the x-y plane, its joint axes are z, gravity points along -y
and the joint angles are relative (``q_1`` from the x axis, ``q_i`` between
links ``i - 1`` and ``i``), as in :func:`tentaclass.geometry.angles_to_points`.
Equation numbers refer to chapter 2 of the thesis; its dynamic model is

    tau = H(q) qdd + h(q, qd) + g(q).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validation import (
    as_joint_arrays,
    as_times,
    as_torques,
    check_choice,
    check_link_parameters,
    check_positive_float,
)
from ..errors import InputError
from . import dynamics as _dyn
from . import kinematics as _kin
from .kinematics import ChainKinematics
from .simulation import STEPPERS, Trajectory, integrate

__all__ = ["PlanarChain"]

TorqueFunction = Callable[[float, FloatArray, FloatArray], ArrayLike]

#: Bounds of a chain's mass-matrix scale, ``sum(masses) * sum(link_lengths)**2 +
#: sum(inertia)``, in its dynamics (kinematics take any lengths): beyond them the
#: dynamics under- or overflow float64. A chain in consistent units (kg and m, g
#: and mm) lies many orders of magnitude inside.
MIN_SCALE, MAX_SCALE = 1e-200, 1e200


def _finite(out: FloatArray, what: str) -> FloatArray:
    """``out``, unless its computation overflowed float64 (refused, naming ``what``)."""
    if not np.all(np.isfinite(out)):
        raise InputError(
            f"{what} overflow float64: the joint velocities, accelerations or torques are "
            "too large for this chain"
        )
    return out


class PlanarChain:
    """A planar serial chain of ``n`` rigid links joined by revolute joints.

    Parameters
    ----------
    link_lengths : float or array_like of shape (n_links,)
        Length of each link, > 0.
    masses : float or array_like of shape (n_links,), default=1.0
        Mass of each link, > 0.
    com : float or array_like of shape (n_links,), default=0.5
        Centre of mass of each link as a fraction of its length from its start
        joint, in [0, 1].
    inertia : float or array_like of shape (n_links,), optional
        Moment of inertia of each link about its centre of mass (z axis), >= 0.
        Default: a thin rod, ``m l^2 / 12``.
    gravity : float, default=9.81
        Gravitational acceleration, >= 0, pointing along -y.

    At least one of ``link_lengths``, ``masses``, ``com`` and ``inertia`` must be
    an array; it fixes ``n_links`` and the scalars are repeated.

    Attributes
    ----------
    n_links : int
    link_lengths, masses, com, inertia : ndarray of shape (n_links,)
        The resolved parameters (read-only properties of read-only arrays).
    gravity : float

    Notes
    -----
    With every inertia > 0 (as for the default rods) the mass matrix is positive
    definite in every configuration; point-mass links (``inertia=0``) can make
    it singular in some configurations, and then :meth:`forward_dynamics` and
    :meth:`simulate` fail.

    Every method takes joint arrays of shape ``(..., n_links)`` whose leading
    axes (broadcast against each other) are a batch; results have shape
    ``batch + core shape`` and are never squeezed.

    Examples
    --------
    >>> chain = PlanarChain([1.0, 1.0])
    >>> chain.n_links, chain.inertia
    (2, array([0.0833, 0.0833]))
    >>> chain.forward_kinematics([0.0, np.pi / 2]).joints[-1]
    array([1., 1.])
    """

    def __init__(
        self,
        link_lengths: ArrayLike,
        masses: ArrayLike = 1.0,
        com: ArrayLike = 0.5,
        inertia: ArrayLike | None = None,
        gravity: float = 9.81,
    ) -> None:
        for name, value in (("link_lengths", link_lengths), ("masses", masses), ("com", com)):
            if value is None:  # (only inertia has a default to compute)
                raise InputError(f"{name} must be a number or one per link, got None")
        n, p = check_link_parameters(
            link_lengths=link_lengths, masses=masses, com=com, inertia=inertia
        )
        if np.any(p["link_lengths"] <= 0):
            raise InputError(f"link_lengths must all be > 0, got {p['link_lengths']}")
        if np.any(p["masses"] <= 0):
            raise InputError(f"masses must all be > 0, got {p['masses']}")
        if np.any((p["com"] < 0) | (p["com"] > 1)):
            raise InputError(f"com must lie in [0, 1] (a fraction of each link), got {p['com']}")
        if "inertia" not in p:
            with np.errstate(over="ignore", under="ignore"):  # (the scale is checked below)
                rod = p["masses"] * p["link_lengths"] ** 2 / 12.0
            rod.flags.writeable = False
            p["inertia"] = rod
        elif np.any(p["inertia"] < 0):
            raise InputError(f"inertia must all be >= 0, got {p['inertia']}")
        if p["com"][-1] == 0 and p["inertia"][-1] == 0:
            raise InputError(
                "the last link is a point mass on its own joint (com 0 and inertia 0): "
                "nothing resists that joint and the mass matrix is singular"
            )
        self._n_links = n
        self._link_lengths = p["link_lengths"]
        self._masses = p["masses"]
        self._com = p["com"]
        self._inertia = p["inertia"]
        self._gravity = check_positive_float(gravity, "gravity", allow_zero=True)
        self._com_lengths = self._com * self._link_lengths

    # Read-only: the parameters are checked once, in __init__.

    @property
    def n_links(self) -> int:
        """Number of links."""
        return self._n_links

    @property
    def link_lengths(self) -> FloatArray:
        """Link lengths, shape (n_links,)."""
        return self._link_lengths

    @property
    def masses(self) -> FloatArray:
        """Link masses, shape (n_links,)."""
        return self._masses

    @property
    def com(self) -> FloatArray:
        """Centres of mass as fractions of the link lengths, shape (n_links,)."""
        return self._com

    @property
    def inertia(self) -> FloatArray:
        """Inertias about the centres of mass, shape (n_links,)."""
        return self._inertia

    @property
    def gravity(self) -> float:
        """Gravitational acceleration, along -y."""
        return self._gravity

    def __repr__(self) -> str:
        return (
            f"PlanarChain(link_lengths={self.link_lengths.tolist()}, "
            f"masses={self.masses.tolist()}, com={self.com.tolist()}, "
            f"inertia={self.inertia.tolist()}, gravity={self.gravity})"
        )

    # -- input checks -------------------------------------------------------------

    def _joints(self, **arrays: ArrayLike) -> list[FloatArray]:
        """Validate joint arrays ``(..., n_links)`` and broadcast them together."""
        return as_joint_arrays(self.n_links, **arrays)

    def _params(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """The parameters of the dynamics, refused where float64 cannot hold them."""
        with np.errstate(over="ignore", under="ignore"):
            scale = self.masses.sum() * self.link_lengths.sum() ** 2 + self.inertia.sum()
            weight = self.gravity * self.masses.sum() * self.link_lengths.sum()
        if not MIN_SCALE <= scale <= MAX_SCALE:
            raise InputError(
                f"the chain's masses, lengths and inertias give a mass matrix of scale "
                f"{scale:.3g} (sum(masses) * sum(link_lengths)**2 + sum(inertia)), outside "
                f"[{MIN_SCALE:g}, {MAX_SCALE:g}] where its dynamics fit float64: express "
                "them in other units"
            )
        if not weight <= MAX_SCALE:
            raise InputError(
                f"gravity {self.gravity:g} gives gravity torques of scale {weight:.3g} "
                f"(gravity * sum(masses) * sum(link_lengths)), beyond {MAX_SCALE:g} where "
                "they fit float64: express it in other units"
            )
        return self.link_lengths, self._com_lengths, self.masses, self.inertia

    # -- kinematics ---------------------------------------------------------------

    def forward_kinematics(self, q: ArrayLike) -> ChainKinematics:
        """Joint positions, centres of mass and absolute link angles.

        Parameters
        ----------
        q : array_like of shape (..., n_links)
            Relative joint angles in radians.

        Returns
        -------
        ChainKinematics
            ``joints`` (..., n_links + 1, 2), ``com`` (..., n_links, 2) and
            ``angles`` (..., n_links).

        Notes
        -----
        ``phi_i = q_1 + ... + q_i`` (eq. 2.4); ``p_0 = 0`` and
        ``p_i = p_{i-1} + l_i (cos phi_i, sin phi_i)``, the end point being
        ``x = p(q) = p_n`` (eqs 2.1, 2.5-2.7, summed from the base rather than
        from the tip); the centre of mass of link ``i`` is
        ``x_ci = p_{i-1} + l_ci (cos phi_i, sin phi_i)`` with ``l_ci = com_i l_i``
        (eq. 2.10).

        Examples
        --------
        >>> chain = PlanarChain([2.0, 1.0], com=[0.5, 1.0])
        >>> fk = chain.forward_kinematics([np.pi / 2, -np.pi / 2])
        >>> fk.joints.round(12)
        array([[0., 0.],
               [0., 2.],
               [1., 2.]])
        >>> fk.com.round(12), fk.angles
        (array([[0., 1.],
               [1., 2.]]), array([1.5708, 0.    ]))
        """
        (q,) = self._joints(q=q)
        return _kin.forward_kinematics(q, self.link_lengths, self._com_lengths)

    def jacobian(self, q: ArrayLike) -> FloatArray:
        """Jacobian of the end point, ``J = dp_n/dq``.

        Parameters
        ----------
        q : array_like of shape (..., n_links)

        Returns
        -------
        J : ndarray of shape (..., 2, n_links)

        Notes
        -----
        ``xd = J(q) qd`` (eq. 2.2) with (eq. 2.8)
        ``J[:, j] = (-(y_n - y_{j-1}), x_n - x_{j-1})``, where
        ``p_j = (x_j, y_j)`` are the joint positions of :meth:`forward_kinematics`
        (the thesis measures them from the tip instead, eq. 2.5): joint ``j``
        turns everything beyond it about ``p_{j-1}``.

        Examples
        --------
        >>> PlanarChain([1.0, 1.0]).jacobian([0.0, np.pi / 2])
        array([[-1., -1.],
               [ 1.,  0.]])
        """
        (q,) = self._joints(q=q)
        return _kin.end_jacobian(q, self.link_lengths)

    def jacobian_dot(self, q: ArrayLike, qd: ArrayLike) -> FloatArray:
        """Time derivative of the end-point Jacobian.

        Parameters
        ----------
        q, qd : array_like of shape (..., n_links)
            Joint angles and velocities.

        Returns
        -------
        Jd : ndarray of shape (..., 2, n_links)

        Notes
        -----
        ``xdd = J qdd + Jd qd`` (eq. 2.3) and ``Jd = sum_i dJ/dq_i qd_i`` (eq. 2.9),
        which here is ``Jd[:, j] = -sum_{k>=j} w_k l_k (cos phi_k, sin phi_k)``
        with ``w_k = qd_1 + ... + qd_k``.

        Examples
        --------
        >>> PlanarChain([1.0, 1.0]).jacobian_dot([0.0, 0.0], [1.0, 0.0])
        array([[-2., -1.],
               [-0., -0.]])
        """
        q, qd = self._joints(q=q, qd=qd)
        return _kin.end_jacobian_dot(q, qd, self.link_lengths)

    def com_jacobians(self, q: ArrayLike) -> FloatArray:
        """Jacobians of each link's centre of mass and absolute angle.

        Parameters
        ----------
        q : array_like of shape (..., n_links)

        Returns
        -------
        Jc : ndarray of shape (..., n_links, 3, n_links)
            ``Jc[..., i, :, :]`` is ``d(x_ci, y_ci, phi_i)/dq`` for link ``i``: rows
            x and y form the linear part ``J_L``, row 2 the angular part ``J_A``.

        Notes
        -----
        Eqs 2.11-2.12: column ``j <= i`` is ``(-(y_ci - y_{j-1}), x_ci - x_{j-1}, 1)``,
        columns ``j > i`` are zero.

        Examples
        --------
        >>> PlanarChain([1.0, 1.0]).com_jacobians([0.0, 0.0])[1]
        array([[-0. , -0. ],
               [ 1.5,  0.5],
               [ 1. ,  1. ]])
        """
        (q,) = self._joints(q=q)
        return _kin.com_jacobians(q, self.link_lengths, self._com_lengths)

    # -- dynamics -----------------------------------------------------------------

    def mass_matrix(self, q: ArrayLike) -> FloatArray:
        """Joint-space inertia matrix ``H(q)``, symmetric positive definite.

        Parameters
        ----------
        q : array_like of shape (..., n_links)

        Returns
        -------
        H : ndarray of shape (..., n_links, n_links)

        Notes
        -----
        ``H = sum_i m_i J_Li^T J_Li + I_i J_Ai^T J_Ai`` with the Jacobians of
        eqs 2.11-2.12; ``H_ij`` is the torque at joint ``i`` that a unit
        acceleration of joint ``j`` needs (Newton-Euler with ``qd = 0``,
        ``qdd = e_j``, no gravity). It is computed by the composite-rigid-body
        algorithm: ``H_ij = K_j + (p_{j-1} - p_{i-1}) . s_j`` for ``i <= j``, with
        ``K_j`` the inertia of links ``j..n`` about joint ``j`` and ``s_j`` their
        first moment about it, both by a tip-to-base recursion.

        Examples
        --------
        >>> PlanarChain([1.0, 1.0]).mass_matrix([0.0, 0.0])
        array([[2.6667, 0.8333],
               [0.8333, 0.3333]])
        """
        (q,) = self._joints(q=q)
        return _dyn.crba(q, *self._params())

    def coriolis(self, q: ArrayLike, qd: ArrayLike) -> FloatArray:
        """Coriolis and centrifugal torques ``h(q, qd)``.

        Parameters
        ----------
        q, qd : array_like of shape (..., n_links)

        Returns
        -------
        h : ndarray of shape (..., n_links)

        Notes
        -----
        Eqs 2.13-2.14: ``h_i = sum_{j,k} h_ijk qd_j qd_k`` with
        ``h_ijk = dH_ij/dq_k - (1/2) dH_jk/dq_i``; computed as the Newton-Euler
        torques with ``qdd = 0`` and no gravity.

        Examples
        --------
        >>> PlanarChain([1.0, 1.0]).coriolis([0.0, np.pi / 2], [1.0, 0.0])
        array([-0. ,  0.5])
        """
        q, qd = self._joints(q=q, qd=qd)
        with np.errstate(over="ignore", invalid="ignore"):
            out = _dyn.rnea(q, qd, None, *self._params(), 0.0)
        return _finite(out, "the Coriolis torques")

    def gravity_torques(self, q: ArrayLike) -> FloatArray:
        """Joint torques that hold the chain still against gravity, ``g(q)``.

        Parameters
        ----------
        q : array_like of shape (..., n_links)

        Returns
        -------
        g : ndarray of shape (..., n_links)

        Notes
        -----
        Eq. 2.15, from the last link back:
        ``g_i = g_{i+1} + G (m_i l_ci + l_i sum_{k>i} m_k) cos(phi_i)``,
        ``g_{n+1} = 0``; computed as the Newton-Euler torques at rest.

        Examples
        --------
        >>> PlanarChain([1.0, 1.0], gravity=10.0).gravity_torques([0.0, 0.0])
        array([20.,  5.])
        """
        (q,) = self._joints(q=q)
        return _dyn.rnea(q, None, None, *self._params(), self.gravity)

    def bias_torques(self, q: ArrayLike, qd: ArrayLike) -> FloatArray:
        """Coriolis, centrifugal and gravity torques together, ``h(q, qd) + g(q)``.

        Parameters
        ----------
        q, qd : array_like of shape (..., n_links)

        Returns
        -------
        b : ndarray of shape (..., n_links)

        Notes
        -----
        ``b = h + g`` (eqs 2.13-2.15), the torques needed for ``qdd = 0``:
        one Newton-Euler pass, cheaper than :meth:`coriolis` plus
        :meth:`gravity_torques`.

        Examples
        --------
        >>> PlanarChain([1.0, 1.0], gravity=10.0).bias_torques([0.0, np.pi / 2], [1.0, 0.0])
        array([15. ,  0.5])
        """
        q, qd = self._joints(q=q, qd=qd)
        with np.errstate(over="ignore", invalid="ignore"):
            out = _dyn.rnea(q, qd, None, *self._params(), self.gravity)
        return _finite(out, "the bias torques")

    def inverse_dynamics(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> FloatArray:
        """Joint torques for given motion: ``tau = H(q) qdd + h(q, qd) + g(q)``.

        Parameters
        ----------
        q, qd, qdd : array_like of shape (..., n_links)
            Joint angles, velocities and accelerations.

        Returns
        -------
        tau : ndarray of shape (..., n_links)

        Notes
        -----
        The dynamic model of section 2.3 (terms eqs 2.13-2.15), evaluated by the
        O(n) recursive Newton-Euler algorithm: a base-to-tip pass for the link
        velocities and accelerations (gravity as an upward base acceleration),
        then a tip-to-base pass for the joint forces and torques
        ``tau_i = tau_{i+1} + I_i al_i + c_i x m_i ac_i + r_i x f_{i+1}``.

        Examples
        --------
        >>> chain = PlanarChain([1.0, 1.0], gravity=0.0)
        >>> chain.inverse_dynamics([0.0, 0.0], [0.0, 0.0], [1.0, 0.0])
        array([2.6667, 0.8333])
        """
        q, qd, qdd = self._joints(q=q, qd=qd, qdd=qdd)
        with np.errstate(over="ignore", invalid="ignore"):
            out = _dyn.rnea(q, qd, qdd, *self._params(), self.gravity)
        return _finite(out, "the joint torques")

    def forward_dynamics(self, q: ArrayLike, qd: ArrayLike, tau: ArrayLike) -> FloatArray:
        """Joint accelerations under given torques: ``qdd = H^-1 (tau - h - g)``.

        Parameters
        ----------
        q, qd, tau : array_like of shape (..., n_links)
            Joint angles, velocities and torques.

        Returns
        -------
        qdd : ndarray of shape (..., n_links)

        Notes
        -----
        Solves ``H(q) qdd = tau - h(q, qd) - g(q)`` (section 2.3) for each
        configuration, with ``H`` from :meth:`mass_matrix` and ``h + g`` from one
        Newton-Euler pass.

        Examples
        --------
        >>> chain = PlanarChain([1.0], gravity=10.0)
        >>> chain.forward_dynamics([0.0], [0.0], [0.0])  # a rod about one end: -3 g / (2 l)
        array([-15.])
        """
        q, qd, tau = self._joints(q=q, qd=qd, tau=tau)
        with np.errstate(over="ignore", invalid="ignore"):
            out = self._accel(q, qd, tau)
        return _finite(out, "the joint accelerations")

    def _accel(self, q: FloatArray, qd: FloatArray, tau: FloatArray | None) -> FloatArray:
        rhs = -_dyn.rnea(q, qd, None, *self._params(), self.gravity)
        if tau is not None:
            rhs += tau
        try:
            qdd = np.linalg.solve(_dyn.crba(q, *self._params()), rhs[..., None])[..., 0]
        except np.linalg.LinAlgError:
            raise InputError(
                "the mass matrix is singular in this configuration: with point-mass links "
                "(inertia 0) some motion of the joints moves no mass"
            ) from None
        return np.asarray(qdd, dtype=np.float64)

    def energy(self, q: ArrayLike, qd: ArrayLike) -> FloatArray:
        """Total mechanical energy: kinetic ``qd^T H qd / 2`` plus potential.

        Parameters
        ----------
        q, qd : array_like of shape (..., n_links)

        Returns
        -------
        E : ndarray of shape (...)

        Notes
        -----
        ``E = sum_i (m_i |v_ci|^2 + I_i w_i^2) / 2 + G sum_i m_i y_ci``, with
        ``v_ci = J_Li qd`` and ``w_i = J_Ai qd`` (eqs 2.10-2.12), which equals
        ``qd^T H qd / 2 + V``; ``V`` is zero with every centre of mass at ``y = 0``.

        Examples
        --------
        >>> chain = PlanarChain([1.0, 1.0], gravity=10.0)
        >>> chain.energy([np.pi / 2, 0.0], [0.0, 0.0])  # centres of mass at 0.5 and 1.5
        array(20.)
        """
        q, qd = self._joints(q=q, qd=qd)
        with np.errstate(over="ignore", invalid="ignore"):
            out = _dyn.energy(q, qd, *self._params(), self.gravity)
        return _finite(out, "the energies")

    def simulate(
        self,
        q0: ArrayLike,
        qd0: ArrayLike,
        torque_fn: TorqueFunction | None,
        t: ArrayLike,
        method: str = "rk4",
    ) -> Trajectory:
        """Integrate the equations of motion ``H qdd + h + g = tau`` in time.

        Parameters
        ----------
        q0, qd0 : array_like of shape (..., n_links)
            Initial joint angles and velocities.
        torque_fn : callable or None
            ``torque_fn(t, q, qd)`` returns the joint torques, broadcastable to
            ``(..., n_links)``; ``None`` leaves the joints free (zero torque).
        t : array_like of shape (n_times,)
            Strictly increasing times; ``t[0]`` is the time of the initial state.
            One step is taken between consecutive times.
        method : {"rk4", "euler"}, default="rk4"
            Classical fourth-order Runge-Kutta, or explicit (forward) Euler.

        Returns
        -------
        Trajectory
            Named tuple ``(q, qd)`` of arrays of shape (n_times, ..., n_links).

        Notes
        -----
        The state ``(q, qd)`` follows ``d/dt (q, qd) = (qd, forward_dynamics(q, qd, tau))``
        (section 2.3).

        Examples
        --------
        >>> chain = PlanarChain([1.0, 1.0])
        >>> t = np.linspace(0.0, 1.0, 201)
        >>> q, qd = chain.simulate([-1.0, 0.5], [0.0, 0.0], None, t)
        >>> q.shape
        (201, 2)
        >>> e = chain.energy(q, qd)
        >>> bool(abs(e[-1] - e[0]) < 1e-4 * abs(e[0]))
        True
        """
        q0, qd0 = self._joints(q0=q0, qd0=qd0)
        times = as_times(t)
        check_choice(method, "method", sorted(STEPPERS))
        if torque_fn is not None and not callable(torque_fn):
            raise InputError(f"torque_fn must be callable or None, got {torque_fn!r}")

        def accel(time: float, q: FloatArray, qd: FloatArray) -> FloatArray:
            if torque_fn is None:
                return self._accel(q, qd, None)
            return self._accel(q, qd, as_torques(torque_fn(time, q, qd), q0.shape))

        return integrate(accel, np.array(q0), np.array(qd0), times, method)
