"""Input checks for :class:`~.chain.PlanarChain` (on top of :mod:`tentaclass._validation`)."""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validation import as_angle_array, as_float_array
from ..errors import InputError, ShapeError


def link_parameters(**params: ArrayLike | None) -> tuple[int, dict[str, FloatArray]]:
    """Scalars or 1-D arrays of one common length ``n``, at least one array.

    Returns ``n`` and read-only float copies of shape ``(n,)`` (``None`` skipped).
    """
    arrays: dict[str, FloatArray] = {}
    n = None
    for name, value in params.items():
        if value is None:
            continue
        arr = as_float_array(value, name)
        if arr.ndim > 1:
            raise ShapeError(f"{name} must be a number or a 1-D array, got shape {arr.shape}")
        if arr.ndim == 1:
            if arr.size == 0:
                raise ShapeError(f"{name} is empty")
            if n is None:
                n = arr.size
            elif arr.size != n:
                sizes = {k: v.size for k, v in arrays.items() if v.ndim == 1}
                raise ShapeError(
                    f"{name} has {arr.size} entries but the chain has {n} links (from {sizes})"
                )
        arrays[name] = arr
    if n is None:
        raise InputError(
            "link_lengths must list one length per link (e.g. [1.0] * n_links) "
            "unless masses, com or inertia do"
        )
    out = {}
    for name, arr in arrays.items():
        out[name] = np.array(np.broadcast_to(arr, (n,)))
        out[name].flags.writeable = False
    return n, out


def joint_arrays(n: int, **arrays: ArrayLike) -> list[FloatArray]:
    """Finite arrays of shape ``(..., n)``, broadcast to their common batch shape."""
    out = []
    for name, value in arrays.items():
        arr = as_angle_array(value, name, min_joints=1)
        if arr.shape[-1] != n:
            raise ShapeError(
                f"{name} must have {n} entries along its last axis (one per link of the "
                f"chain), got shape {arr.shape}"
            )
        out.append(arr)
    try:
        shape = np.broadcast_shapes(*(a.shape for a in out))
    except ValueError:
        shapes = ", ".join(f"{k} {a.shape}" for k, a in zip(arrays, out, strict=True))
        raise ShapeError(f"the batch shapes of {shapes} do not broadcast") from None
    return [np.broadcast_to(a, shape) for a in out]


def times(t: ArrayLike) -> FloatArray:
    """A non-empty, strictly increasing 1-D array of finite times."""
    arr = as_float_array(t, "t", min_ndim=1)
    if arr.ndim != 1 or arr.size == 0:
        raise ShapeError(f"t must be a non-empty 1-D array of times, got shape {arr.shape}")
    if np.any(np.diff(arr) <= 0):
        raise InputError("t must be strictly increasing")
    return arr


def torques(value: ArrayLike, shape: tuple[int, ...]) -> FloatArray:
    """The output of a torque function, broadcast to the state's shape."""
    tau = as_float_array(value, "torque_fn(t, q, qd)")
    try:
        return np.broadcast_to(tau, shape)
    except ValueError:
        raise ShapeError(
            f"torque_fn(t, q, qd) returned shape {tau.shape}, which does not broadcast "
            f"to the state's shape {shape}"
        ) from None
