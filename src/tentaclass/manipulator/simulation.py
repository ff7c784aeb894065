"""Fixed-step time integration of the chain's equations of motion."""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from .._typing import FloatArray
from ..errors import InputError

__all__ = ["Trajectory"]

#: ``accel(t, q, qd) -> qdd``, every array of shape ``(..., n)``.
Acceleration = Callable[[float, FloatArray, FloatArray], FloatArray]


class Trajectory(NamedTuple):
    """Joint angles and velocities at the requested times.

    Attributes
    ----------
    q : ndarray of shape (n_times, ..., n_links)
        Joint angles; ``q[k]`` is the state at ``t[k]``.
    qd : ndarray of shape (n_times, ..., n_links)
        Joint velocities.
    """

    q: FloatArray
    qd: FloatArray


def _euler_step(
    accel: Acceleration, t: float, dt: float, q: FloatArray, qd: FloatArray
) -> tuple[FloatArray, FloatArray]:
    qdd = accel(t, q, qd)
    return q + dt * qd, qd + dt * qdd


def _rk4_step(
    accel: Acceleration, t: float, dt: float, q: FloatArray, qd: FloatArray
) -> tuple[FloatArray, FloatArray]:
    half = 0.5 * dt
    a1 = accel(t, q, qd)
    q2, v2 = q + half * qd, qd + half * a1
    a2 = accel(t + half, q2, v2)
    q3, v3 = q + half * v2, qd + half * a2
    a3 = accel(t + half, q3, v3)
    q4, v4 = q + dt * v3, qd + dt * a3
    a4 = accel(t + dt, q4, v4)
    sixth = dt / 6.0
    return (
        q + sixth * (qd + 2.0 * v2 + 2.0 * v3 + v4),
        qd + sixth * (a1 + 2.0 * a2 + 2.0 * a3 + a4),
    )


STEPPERS = {"rk4": _rk4_step, "euler": _euler_step}


def integrate(
    accel: Acceleration, q0: FloatArray, qd0: FloatArray, t: FloatArray, method: str
) -> Trajectory:
    """One step of ``method`` between each pair of consecutive times in ``t``."""
    step = STEPPERS[method]
    q_out = np.empty((t.shape[0], *q0.shape))
    qd_out = np.empty_like(q_out)
    q_out[0], qd_out[0] = q0, qd0
    q, qd = q0, qd0
    for k in range(t.shape[0] - 1):
        with np.errstate(over="ignore", invalid="ignore"):
            q, qd = step(accel, float(t[k]), float(t[k + 1] - t[k]), q, qd)
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(qd))):
            raise InputError(
                f"the simulation diverged between t = {t[k]:g} and {t[k + 1]:g}: the state "
                "overflowed float64 (time steps too long for this chain, or torques too large)"
            )
        q_out[k + 1], qd_out[k + 1] = q, qd
    return Trajectory(q=q_out, qd=qd_out)
