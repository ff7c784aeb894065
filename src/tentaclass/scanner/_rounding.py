"""Python's ``round(x, digits)`` of whole arrays, bit for bit, without a Python call per value."""

from __future__ import annotations

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
    if x.size <= 16:  # fewer calls than the array operations below
        return np.array([round(v, digits) for v in x.ravel().tolist()]).reshape(x.shape)
    scale = 10.0**digits
    with np.errstate(over="ignore", invalid="ignore"):
        y = x * scale
        m = np.rint(y)
        out = m / scale
        near = np.abs(np.abs(y - m) - 0.5) <= 2.0 * np.spacing(np.abs(y))
        near |= np.abs(y) >= 2.0**52
    near &= np.isfinite(x)
    if near.any():
        idx = np.flatnonzero(near)
        out[idx] = [round(v, digits) for v in x[idx].tolist()]
    return out
