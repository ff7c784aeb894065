"""Python's ``round(x, digits)`` of whole arrays, bit for bit, without a Python call per value."""

from __future__ import annotations

import numba as nb
import numpy as np

__all__ = ["rounded"]


def rounded(values: np.ndarray, digits: int) -> np.ndarray:
    """``[round(v, digits) for v in values]`` as a float array, the same bits.

    Python rounds the exact binary value of ``v`` to ``digits`` decimals
    (halves to even) and returns the float nearest that decimal, which is
    the correctly rounded ``m / 10**digits`` for the integer ``m``. Here
    ``m = rint(v * 10**digits)``; the product's own rounding can only move
    ``m`` when ``v * 10**digits`` lies within an ulp of a half-integer (or
    is too large for the fraction to matter), and those few values are
    rounded by Python.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([0.1234565, 2.675, -0.5e-6, 1 / 3, 7.0])
    >>> rounded(v, 6).tolist() == [round(x, 6) for x in v.tolist()]
    True
    """
    x = np.asarray(values, dtype=np.float64)
    out, near = _round_scaled(np.ascontiguousarray(x).ravel(), 10.0**digits)
    if near.any():
        idx = np.flatnonzero(near)
        out[idx] = [round(v, digits) for v in x.ravel()[idx].tolist()]
    return out.reshape(x.shape)


@nb.njit(cache=True, nogil=True)
def _round_scaled(x, scale):
    """``rint(x * scale) / scale`` of each value, and where Python's ``round`` may differ.

    Those are the finite values whose scaled product lies within two ulps of a
    half-integer, or is at least ``2**52`` (numpy's arithmetic, the same bits).
    """
    out = np.empty(x.shape[0])
    near = np.zeros(x.shape[0], dtype=np.bool_)
    for i in range(x.shape[0]):
        y = x[i] * scale
        m = np.rint(y)
        out[i] = m / scale
        ay = abs(y)
        if np.isfinite(x[i]) and (
            abs(abs(y - m) - 0.5) <= 2.0 * (np.nextafter(ay, np.inf) - ay) or ay >= 2.0**52
        ):
            near[i] = True
    return out, near
