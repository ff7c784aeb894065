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

Threads: the matrix-product path uses as many threads as the BLAS library is
set to; set them with threadpoolctl, e.g. ``with threadpool_limits(1,
user_api="blas"):``. It cuts a batch into tiles of ``_TILE_ROWS`` rows, small
enough that a tile's product stays in the core's cache while its magnitudes
are taken, and hands the tiles out to that many threads, each running BLAS on
one thread. Chains of up to 32 joints, and batches too small to pay for a
second thread, run on one. The tiles are the same whatever the number of
threads, and so are the results, to the bit.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Iterable
from contextlib import nullcontext
from functools import lru_cache
from typing import Any

import numpy as np

from .._dask import blockwise
from .._deprecation import UNSET, renamed
from .._typing import ArrayLike, FloatArray
from .._validation import (
    as_angle_array,
    check_angle_values,
    check_choice,
    check_flag,
    check_positive_float,
    check_positive_int,
    check_total,
)
from ..errors import InputError

__all__ = ["dft_layer", "fourier_features"]

#: Chains up to this many joints use the folded matrix product; longer ones the FFT.
#: Chosen by measurement (benchmarks/bench_fourier.py).
MATMUL_MAX_JOINTS = 128

#: Rows per tile of the matrix-product path and per block of the FFT path. A
#: tile's angles and product (1024 x 64 doubles each at n = 64, 512 KiB) stay in
#: the core's L2 cache from the first reading to the magnitudes, and a product of
#: 1024 rows is as fast per row on one BLAS thread as one of 16384. Measured for
#: n = 16, 64 and 128: tiles of 512 to 2048 rows took within a few per cent of
#: each other, 4096 and more up to a fifth longer at n = 16. The FFT path's
#: blocks of 1024 rows took 0.5-0.85 x the time of blocks of 16384 at n = 130 to
#: 1024 (one thread, the same bits).
_TILE_ROWS = 1024

#: Chains up to this many joints run on one thread whatever the setting: a tile's
#: product is thin, and NumPy's calls and the handing of the GIL from thread to
#: thread cost more than a second thread gains (0.7-0.99 x at n = 16, 0.94 x at
#: n = 32, measured with 131 072 and 65 536 arrays).
_ONE_THREAD_MAX_JOINTS = 32

#: A batch whose product has fewer multiply-adds than this runs on one thread:
#: handing out its tiles costs more than a second thread gains (at n = 64, 0.9 x
#: for 4096 arrays and 1.3 x for 8192; at n = 128, 1.5 x for 2048).
_THREADED_MIN_WORK = 2**25

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

    Raises
    ------
    InputError
        ``n`` not a positive integer, or the two matrices larger than
        ``MAX_VALUES`` (1e9) values (``n`` above 22,360).

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
    check_total(2 * n * n, f"the DFT layer of n = {n:,} (2 matrices of n x n)")
    phase = 2 * np.pi * (np.outer(np.arange(n), np.arange(n)) % n) / n
    return np.cos(phase), -np.sin(phase)


@lru_cache(maxsize=32)
def _folded_weights(
    n: int, n_harmonics: int, detrend: bool, period: float
) -> tuple[FloatArray, FloatArray, FloatArray | None]:
    """Folded weights of the whole transform, for one chain length.

    Returns ``weights`` (n, 2K), ``flipped`` (n, 2K) and ``offset`` (2K,) such
    that ``Re, Im`` of ``DFT(E)`` at ``k = 1..K``, interleaved
    (``Re_1, Im_1, Re_2, ...``), are ``q @ weights - offset`` for a
    counter-clockwise row and ``q @ flipped - offset`` for the canonical form
    ``-q[::-1]`` of a clockwise one. ``offset`` is None with ``detrend`` (the
    transform is linear then).
    """
    k = np.arange(1, n_harmonics + 1)
    j = np.arange(n)
    phase = 2 * np.pi * (np.outer(j, k) % n) / n
    dft = np.empty((n, 2 * n_harmonics))  # E @ dft, Re and Im interleaved
    dft[:, 0::2] = np.cos(phase)
    dft[:, 1::2] = -np.sin(phase)
    cumsum = np.triu(np.ones((n, n)))  # t = q @ cumsum
    ramp = np.arange(1, n + 1) / n
    offset = None
    if detrend:
        # E = t - t_n * ramp = q @ (cumsum - 1 ramp^T): linear, no offset.
        weights = (cumsum - ramp[None, :]) @ dft
    else:
        weights = cumsum @ dft
        offset = (period * ramp) @ dft
        offset.setflags(write=False)
    flipped = -weights[::-1].copy()  # (-q[::-1]) @ weights == q @ -weights[::-1]
    for a in (weights, flipped):
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
    *,
    extremes: bool = False,
) -> tuple[float, float] | None:
    """Features of the rows of ``q`` into ``out``; with ``extremes``, ``(q.min(), q.max())``.

    With ``extremes`` the values of ``q`` are unchecked (the caller checks the
    least and greatest, found tile by tile while the tile is in the cache), so
    NaN, infinity or overflow in the arithmetic are no warning.
    """
    weights, flipped, offset = _folded_weights(q.shape[1], n_harmonics, detrend, period)
    rows = q.shape[0]
    tile = min(_TILE_ROWS, rows)
    # the offset repeated over a tile's rows: one contiguous pass takes it off
    # (a (2K,) row broadcast over the tile is a loop call per row, three times slower)
    offsets = None
    if offset is not None:
        offsets = np.empty((tile, offset.shape[0]))
        offsets[:] = offset
    starts = range(0, rows, _TILE_ROWS)
    bounds = np.empty((2, len(starts))) if extremes else None
    args = (q, weights, flipped, offsets, canonicalize, out, bounds)
    if rows < _THREADED_MIN_ROWS:
        _matmul_tiles(starts, *args)
    else:
        # multiply-adds of the whole product
        work = q.size * weights.shape[1]
        thin = q.shape[1] <= _ONE_THREAD_MAX_JOINTS or work < _THREADED_MIN_WORK
        with _one_blas_thread() as threads:
            _run_threads(
                1 if thin else min(threads, len(starts)),
                lambda tiles: _matmul_tiles(tiles, *args),
                starts,
            )
    return None if bounds is None else (float(bounds[0].min()), float(bounds[1].max()))


@lru_cache(maxsize=1)
def _blas_controller() -> Any:
    """One threadpoolctl controller per process: creating it scans the loaded libraries."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


@lru_cache(maxsize=1)
def _blas_libraries() -> tuple[Any, ...]:
    """The BLAS libraries' threadpoolctl controllers (found once)."""
    return tuple(lib for lib in _blas_controller().lib_controllers if lib.user_api == "blas")


class _OneBlasThread:
    """BLAS held to one thread while any caller is inside; its setting kept for them.

    Counted, so that callers on several threads neither read each other's
    limit as the user's setting nor restore it while another still runs.
    A context manager: ``with _one_blas_thread() as threads:`` gives the
    number of threads BLAS was set to. The libraries' threads are read and
    set directly (a few microseconds; a threadpoolctl limit costs some 15 us
    per use, paid by every batch of a line scanner), and only those not on
    one thread already are changed.
    """

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.users = 0
        self.threads = 1
        self.changed: list[tuple[Any, int]] = []

    def __enter__(self) -> int:
        with self.lock:
            if self.users == 0:
                found = [(lib, lib.get_num_threads()) for lib in _blas_libraries()]
                self.threads = max([1, *(n for _, n in found if n is not None)])
                self.changed = [(lib, n) for lib, n in found if n is not None and n != 1]
                for lib, _ in self.changed:
                    lib.set_num_threads(1)
            self.users += 1
            return self.threads

    def __exit__(self, *exc: object) -> None:
        with self.lock:
            self.users -= 1
            if self.users == 0:
                for lib, n in self.changed:
                    lib.set_num_threads(n)
                self.changed = []


_BLAS_STATE = _OneBlasThread()


def _one_blas_thread() -> _OneBlasThread:
    """Limit BLAS to one thread; entering yields the number of threads it was set to.

    The limit is the process's: BLAS calls from other threads meanwhile run on
    one thread too.
    """
    return _BLAS_STATE


@lru_cache(maxsize=1)
def _executor(workers: int) -> Any:
    """A persistent pool of ``workers`` threads (made on first use)."""
    from concurrent.futures import ThreadPoolExecutor

    return ThreadPoolExecutor(workers, thread_name_prefix="tentaclass-fourier")


# a forked child has none of the parent's pool threads
os.register_at_fork(after_in_child=_executor.cache_clear)


def _run_threads(threads: int, work: Callable[[Iterable[int]], None], starts: range) -> None:
    """Call ``work(items)`` on ``threads`` threads (this one among them), sharing ``starts``.

    Each thread's ``items`` hands out the next item of ``starts`` not yet
    taken: a thread slowed down by other processes takes fewer, and none
    waits for it but at the end.
    """
    if threads <= 1:
        work(starts)
        return
    items = iter(starts)
    lock = threading.Lock()

    def take() -> int | None:
        with lock:
            return next(items, None)

    futures = [_executor(threads - 1).submit(work, iter(take, None)) for _ in range(threads - 1)]
    try:
        work(iter(take, None))
    finally:
        for f in futures:
            # a helper not started yet (its threads busy with another call) is not waited for
            if not f.cancel():
                f.result()


def _matmul_tiles(
    starts: Iterable[int],
    q: FloatArray,
    weights: FloatArray,
    flipped: FloatArray,
    offsets: FloatArray | None,
    canonicalize: bool,
    out: FloatArray,
    bounds: FloatArray | None,
) -> None:
    """Features of the tiles of ``q`` from the rows ``starts`` on, ``_TILE_ROWS`` rows each.

    With ``bounds`` (2, tiles), the least and greatest angle of each tile too.
    """
    # one buffer for every tile's product, small enough to stay in the cache
    buf = np.empty((min(_TILE_ROWS, q.shape[0]), weights.shape[1]))
    turns = np.empty(buf.shape[0])
    ones = np.ones(q.shape[1])
    with nullcontext() if bounds is None else np.errstate(all="ignore"):
        for lo in starts:
            block = q[lo : lo + _TILE_ROWS]
            rows = block.shape[0]
            if bounds is not None:
                bounds[:, lo // _TILE_ROWS] = block.min(), block.max()
            if canonicalize:
                cw = np.matmul(block, ones, out=turns[:rows]) < 0
            z = np.matmul(block, weights, out=buf[:rows])
            if canonicalize and np.count_nonzero(cw):  # (ndarray.any costs a Python call)
                z[cw] = block[cw] @ flipped
            if offsets is not None:
                np.subtract(z, offsets[:rows], out=z)
            _magnitudes(z, out[lo : lo + _TILE_ROWS])


def _magnitudes(z: FloatArray, out: FloatArray) -> None:
    """``out = |re + i im|`` of ``z`` (rows ``re_1, im_1, re_2, ...``); overwrites ``z``.

    sqrt of the sum of squares: np.hypot is several times slower and the
    overflow it guards against cannot happen with angles in range. Every pass
    is one loop over contiguous memory (the pairs are read with stride 2), so
    no array is allocated and NumPy's call per row is not paid: as fast as a
    compiled loop, without loading a compiler into the process.
    """
    np.square(z, out=z)
    pairs = z.reshape(z.shape[0], -1, 2)
    np.add(pairs[..., 0], pairs[..., 1], out=out)
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
    for lo in range(0, q.shape[0], _TILE_ROWS):
        t = np.cumsum(_canonical_block(q[lo : lo + _TILE_ROWS], canonicalize), axis=1)
        t -= (t[:, -1:] if detrend else period) * ramp
        out[lo : lo + _TILE_ROWS] = np.abs(np.fft.rfft(t, axis=1)[:, 1 : n_harmonics + 1])


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
    # the values are checked below: by the matrix-product kernel's own reading of them
    q = as_angle_array(q, "q", min_joints=2, check_values=False)
    period = check_positive_float(period, "period")
    detrend = check_flag(detrend, "detrend")
    normalize = check_flag(normalize, "normalize")
    canonicalize = check_flag(canonicalize, "canonicalize")
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
    args = (flat, n_harmonics, detrend, period, canonicalize, out)
    if method == "matmul" and flat.shape[0] > _TILE_ROWS:
        extremes = _features_matmul(*args, extremes=True)
        assert extremes is not None
        check_angle_values(q, "q", *extremes)
    else:
        check_angle_values(q, "q", float(q.min()), float(q.max()))
        (_features_matmul if method == "matmul" else _features_fft)(*args)
    if normalize:
        out /= n
    return out.reshape(*batch, n_harmonics)
