"""Fourier features of the periodic turning signal (thesis chapter 4).

The thesis's feature vector is ``|DFT(E)|`` at frequencies ``1..floor(n/2)``,
where ``E`` is the periodic signal of eq 4.5. Dropping the DC term makes it
invariant to rotation, taking magnitudes makes it invariant to the start
point (a cyclic shift of ``q``), and equal link lengths make it invariant to
scale.

Everything from ``q`` to the complex coefficients is linear, so for short
chains the whole transform - cumulative sum, ramp and DFT - folds into one
``(n, 2 * n_harmonics)`` weight matrix: a batch costs one matrix product plus a
magnitude, which beats ``numpy.fft`` on the batch for small ``n``
(see ``benchmarks/bench_fourier.py``). Long chains use the FFT.

Threads: the product uses as many BLAS threads as the BLAS library is set to;
set them with threadpoolctl, e.g. ``with threadpool_limits(1, user_api="blas"):``.
Chains of up to 32 joints always use one thread: such a thin product runs at
memory speed and extra threads only cost (ten times, measured, on a busy
two-core machine).
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

from .._dask import blockwise
from .._deprecation import UNSET, renamed
from .._typing import ArrayLike, FloatArray
from .._validation import as_angle_array, check_choice, check_positive_float, check_positive_int
from ..errors import InputError

__all__ = ["dft_layer", "fourier_features"]

#: Chains up to this many joints use the folded matrix product; longer ones the FFT.
#: Chosen by measurement (benchmarks/bench_fourier.py).
MATMUL_MAX_JOINTS = 128

#: Rows per block in the matrix-product path: large enough that a multi-threaded
#: BLAS pays off (with 2048-row blocks two OpenBLAS threads made it 7 x slower
#: than one on a loaded machine), small enough to bound the temporary.
_BLOCK_ROWS = 16384

#: Up to this many joints the product runs on one BLAS thread (see _features_matmul).
_ONE_THREAD_MAX_JOINTS = 32

#: Fewer rows than this make a product OpenBLAS runs on one thread anyway (it
#: splits products of more than 2**18 multiply-adds), so no limit is set for them:
#: setting one first scans the loaded libraries (about 0.1 s, once per process).
_THREADED_MIN_ROWS = 128


def dft_layer(n: int) -> tuple[FloatArray, FloatArray]:
    """Fixed weights of the thesis's linear two-layer "MLP": a DFT as matrices.

    Parameters
    ----------
    n : int
        Signal length.

    Returns
    -------
    w_cos : ndarray of shape (n, n)
        ``w_cos[k, j] = cos(2 pi k j / n)``.
    w_minus_sin : ndarray of shape (n, n)
        ``w_minus_sin[k, j] = -sin(2 pi k j / n)``.

    Notes
    -----
    For a real signal ``x`` of shape ``(..., n)``,
    ``numpy.fft.fft(x) == x @ w_cos.T + 1j * (x @ w_minus_sin.T)``: the network
    is not trained, it computes the real and imaginary parts of the DFT. The
    phases are reduced with ``(k * j) % n`` in integers, so the weights are exact
    to the last bit of the sine and cosine.

    Examples
    --------
    >>> import numpy as np
    >>> w_cos, w_sin = dft_layer(8)
    >>> x = np.arange(8.0)
    >>> bool(np.allclose(x @ w_cos.T + 1j * (x @ w_sin.T), np.fft.fft(x)))
    True
    """
    n = check_positive_int(n, "n")
    phase = 2 * np.pi * (np.outer(np.arange(n), np.arange(n)) % n) / n
    return np.cos(phase), -np.sin(phase)


@lru_cache(maxsize=32)
def _folded_weights(
    n: int, n_harmonics: int, detrend: bool, period: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Folded weights of the whole transform, for one chain length.

    Returns ``weights`` (n, 2K + 1), ``flipped`` (n, 2K) and ``offset`` (2K,) such
    that ``[Re | Im]`` of ``DFT(E)`` at ``k = 1..K`` is ``q @ weights[:, :-1] - offset``
    for a counter-clockwise row and ``q @ flipped - offset`` for the canonical
    form ``-q[::-1]`` of a clockwise one; the last column of ``weights`` is all
    ones, so the same product also yields each row's total turn.
    """
    k = np.arange(1, n_harmonics + 1)
    j = np.arange(n)
    phase = 2 * np.pi * (np.outer(j, k) % n) / n
    dft = np.concatenate([np.cos(phase), -np.sin(phase)], axis=1)  # (n, 2K): E @ dft
    cumsum = np.triu(np.ones((n, n)))  # t = q @ cumsum
    ramp = np.arange(1, n + 1) / n
    if detrend:
        # E = t - t_n * ramp = q @ (cumsum - 1 ramp^T): linear, no offset.
        linear = (cumsum - ramp[None, :]) @ dft
        offset = np.zeros(2 * n_harmonics)
    else:
        linear = cumsum @ dft
        offset = (period * ramp) @ dft
    weights = np.concatenate([linear, np.ones((n, 1))], axis=1)
    flipped = -linear[::-1].copy()  # (-q[::-1]) @ linear == q @ -linear[::-1]
    for a in (weights, flipped, offset):
        a.setflags(write=False)
    return weights, flipped, offset


def _canonical_block(q: FloatArray, canonicalize: bool) -> FloatArray:
    """Reverse and negate the clockwise rows of one block (a new array if any)."""
    if canonicalize:
        cw = q.sum(axis=1) < 0
        if cw.any():
            return np.where(cw[:, None], -q[:, ::-1], q)
    return q


def _features_matmul(
    q: FloatArray,
    n_harmonics: int,
    detrend: bool,
    period: float,
    canonicalize: bool,
    out: FloatArray,
) -> None:
    weights, flipped, offset = _folded_weights(q.shape[1], n_harmonics, detrend, period)
    if q.shape[1] <= _ONE_THREAD_MAX_JOINTS and q.shape[0] >= _THREADED_MIN_ROWS:
        # A product this thin runs at memory speed; BLAS threads only add overhead
        # (at n = 16, two OpenBLAS threads made it 10 x slower on a busy machine).
        with _blas_controller().limit(limits=1, user_api="blas"):
            _matmul_blocks(q, weights, flipped, offset, n_harmonics, canonicalize, out)
    else:
        _matmul_blocks(q, weights, flipped, offset, n_harmonics, canonicalize, out)


@lru_cache(maxsize=1)
def _blas_controller() -> Any:
    """One threadpoolctl controller per process: creating it scans the loaded libraries."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


def _matmul_blocks(
    q: FloatArray,
    weights: FloatArray,
    flipped: FloatArray,
    offset: FloatArray,
    n_harmonics: int,
    canonicalize: bool,
    out: FloatArray,
) -> None:
    # one buffer for every block's product: a fresh 8 MiB array per block is
    # mapped anew by malloc and its pages faulted in, which costs as much as the
    # product's arithmetic
    buf = np.empty((min(_BLOCK_ROWS, q.shape[0]), weights.shape[1]))
    for lo in range(0, q.shape[0], _BLOCK_ROWS):
        block = q[lo : lo + _BLOCK_ROWS]
        z = np.matmul(block, weights, out=buf[: block.shape[0]])
        if canonicalize:
            cw = z[:, -1] < 0
            if cw.any():
                z[cw, :-1] = block[cw] @ flipped
        # |re + i im| with the offset taken off
        _magnitudes(z, offset, n_harmonics, out[lo : lo + _BLOCK_ROWS])


def _magnitudes(z: FloatArray, offset: FloatArray, k: int, out: FloatArray) -> None:
    """``out = |(z[:, :k] - offset[:k]) + i (z[:, k:2k] - offset[k:])|``; overwrites ``z[:, :2k]``.

    sqrt of the sum of squares: np.hypot is several times slower and the
    overflow it guards against cannot happen with angles in range. In place on
    ``z`` (a temporary of the caller), so no array is allocated: as fast as a
    compiled loop, without loading a compiler into the process.
    """
    parts = z[:, : 2 * k]
    parts -= offset[: 2 * k]
    parts *= parts
    np.add(parts[:, :k], parts[:, k:], out=out)
    np.sqrt(out, out=out)


def _features_fft(
    q: FloatArray,
    n_harmonics: int,
    detrend: bool,
    period: float,
    canonicalize: bool,
    out: FloatArray,
) -> None:
    n = q.shape[1]
    ramp = np.arange(1, n + 1) / n
    for lo in range(0, q.shape[0], _BLOCK_ROWS):
        t = np.cumsum(_canonical_block(q[lo : lo + _BLOCK_ROWS], canonicalize), axis=1)
        t -= (t[:, -1:] if detrend else period) * ramp
        out[lo : lo + _BLOCK_ROWS] = np.abs(np.fft.rfft(t, axis=1)[:, 1 : n_harmonics + 1])


@blockwise
def fourier_features(
    q: ArrayLike,
    n_harmonics: int | None = None,
    *,
    detrend: bool = False,
    normalize: bool = False,
    canonicalize: bool = True,
    period: float = 2 * np.pi,
    method: str = "auto",
    n_coeffs: Any = UNSET,
) -> FloatArray:
    """Magnitudes of the DFT of the periodic turning signal: the feature vector.

    Parameters
    ----------
    q : array_like of shape (..., n_joints)
        Relative joint angles in radians, at least 2 (two links out and back
        are the smallest closed chain), each at most ``2**20`` turns in
        magnitude. Leading axes are a batch.
    n_harmonics : int, optional
        Keep frequencies ``1..n_harmonics``; default all of ``1..floor(n_joints/2)``.
    detrend : bool, default=False
        Use the measured total turn for the ramp (see :func:`periodic_signal`).
        Recommended for noisy joint angles.
    normalize : bool, default=False
        Divide by ``n_joints`` so that chains of different lengths give features
        on one scale.
    canonicalize : bool, default=True
        Map clockwise wraps (negative total turn) to counter-clockwise ones,
        ``q -> -q[::-1]``, first (:func:`canonical_direction`), so that a wrap
        either way round gives the same features.
    period : float, default=2*pi
        One full turn in the units of ``q``.
    method : {"auto", "matmul", "fft"}, default="auto"
        ``"matmul"``: one product with precomputed weights (cumulative sum, ramp
        and DFT folded together); ``"fft"``: cumulative sum then ``rfft``.
        ``"auto"`` takes the matrix product up to ``MATMUL_MAX_JOINTS`` joints.
    n_coeffs : int, optional
        Deprecated alias of ``n_harmonics``.

    Returns
    -------
    features : ndarray of shape (..., n_harmonics)
        ``|DFT(E)|_k`` for ``k = 1..n_harmonics``, with
        ``E_k = t_k - period * k / n`` (eq 4.5).

    Raises
    ------
    tentaclass.errors.InputError
        A ``ValueError``: ``q`` is ragged, empty, holds NaN or infinity, or an
        angle beyond ``2**20`` turns (not radians), or an option is out of range.

    Notes
    -----
    Invariant to a cyclic shift of ``q`` (start point), to rotation (DC is
    dropped) and, with ``canonicalize``, to the direction of the wrap.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.tile([0, 0, 0, np.pi / 2], 4)
    >>> f = fourier_features(square)
    >>> f.shape
    (8,)
    >>> bool(np.allclose(f, fourier_features(np.roll(square, 5))))
    True
    >>> bool(np.allclose(f, fourier_features(-square[::-1])))
    True
    """
    q = as_angle_array(q, "q", min_joints=2)
    period = check_positive_float(period, "period")
    n_harmonics = renamed("n_harmonics", n_harmonics, "n_coeffs", n_coeffs)
    n = q.shape[-1]
    if n_harmonics is None:
        n_harmonics = n // 2
    n_harmonics = check_positive_int(n_harmonics, "n_harmonics")
    if n_harmonics > n // 2:
        raise InputError(
            f"n_harmonics must be at most floor(n_joints / 2) = {n // 2} "
            f"for {n} joints, got {n_harmonics}"
        )
    check_choice(method, "method", ("auto", "matmul", "fft"))
    if method == "auto":
        method = "matmul" if n <= MATMUL_MAX_JOINTS else "fft"
    batch = q.shape[:-1]
    flat = np.ascontiguousarray(q.reshape(-1, n))
    out = np.empty((flat.shape[0], n_harmonics))
    kernel = _features_matmul if method == "matmul" else _features_fft
    kernel(flat, n_harmonics, bool(detrend), period, bool(canonicalize), out)
    if normalize:
        out /= n
    return out.reshape(*batch, n_harmonics)
