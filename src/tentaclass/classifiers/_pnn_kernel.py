"""Compiled ``exp`` and row sums of the PNN's kernel tiles (numba).

NumPy's float64 ``exp`` calls the C library one value at a time unless the
CPU has AVX-512, and it is then the largest cost of a PNN prediction (several
times the matrix product per kernel value). Here ``exp`` is a polynomial that
the compiler vectorises, fused with the frame and the row sum, so each tile
is read once after the product: no ``exp`` pass writing the tile back and no
second pass summing it. The tiles of a float32 prediction are exponentiated
in float32 at twice the SIMD width, with arguments clamped so that no result
is a subnormal number (slow on x86), and summed in float64. A class's first
tile is read once more, before, for each row's maximum (which sets the
frame): a SIMD reduction too, about a tenth of the cost of the ``exp``.

Imported only by large predictions (:mod:`tentaclass.classifiers._pnn_core`),
so reading a model file and scoring a few arrays never loads numba.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from llvmlite import ir
from numba.core import types
from numba.extending import intrinsic

__all__ = ["framed_exp_sums", "vexp"]

_LOG2E = 1.4426950408889634
# ln 2 in two parts: n * _LN2_HI is exact for the |n| <= 1100 used here
_LN2_HI = 6.93147180369123816490e-01
_LN2_LO = 1.90821492927058770002e-10
# 1.5 * 2^52 + 1023: adding it rounds to an integer kept in the low mantissa
# bits, already carrying the exponent bias of 2^n
_SHIFTER = 6755399441055744.0 + 1023.0
# exp(r) = 1 + r + r^2 q(r) on |r| <= ln2 / 2: q is the minimax polynomial
# (weighted Remez, relative error of exp(r), coefficients rounded to double
# one at a time with the rest refitted): 5.6e-18 relative, 0.025 ulp of 1
_Q = (
    0.5000000000000011,
    0.16666666666666433,
    0.04166666666652672,
    0.008333333333477879,
    0.0013888888944604445,
    0.00019841269549815283,
    2.4801492023551522e-05,
    2.7557541347558077e-06,
    2.763065328787771e-07,
    2.5016302325763605e-08,
)
# arguments are clamped to +-_EXP_BOUND, where exp and 2^n stay normal numbers
_EXP_BOUND = 708.0


def _bitcast(source, target, ir_type):
    """A compiled function reinterpreting a ``source`` scalar's bits as ``target``."""

    @intrinsic
    def cast(typingctx, x):
        def codegen(context, builder, signature, args):
            return builder.bitcast(args[0], ir_type)

        return target(source), codegen

    return cast


_bits_as_float = _bitcast(types.int64, types.float64, ir.DoubleType())
_float_as_bits = _bitcast(types.float64, types.int64, ir.IntType(64))
_bits_as_float32 = _bitcast(types.int32, types.float32, ir.FloatType())
_float32_as_bits = _bitcast(types.float32, types.int32, ir.IntType(32))


_FLAGS = {"contract"}  # fused multiply-adds; no reassociation (it would undo the reduction)


@nb.njit(cache=True, nogil=True, fastmath=_FLAGS)
def _exp(x):
    """``exp(x)`` within 1 ulp for |x| <= 708; ``x`` beyond is clamped to +-708.

    ``x = n ln2 + r`` with ``|r| <= ln2 / 2``; ``exp(r)`` is a polynomial of
    degree 11 (minimax: error below 6e-18 relative, against 2e-16 for a
    Taylor polynomial of the same degree) in Horner's form, the fewest
    operations (the loop is bound by their throughput, not their latency),
    and ``2^n`` is built from its exponent bits.
    """
    x = min(max(x, -_EXP_BOUND), _EXP_BOUND)
    kd = x * _LOG2E + _SHIFTER
    n = kd - _SHIFTER
    r = (x - n * _LN2_HI) - n * _LN2_LO
    p = _Q[9]
    p = p * r + _Q[8]
    p = p * r + _Q[7]
    p = p * r + _Q[6]
    p = p * r + _Q[5]
    p = p * r + _Q[4]
    p = p * r + _Q[3]
    p = p * r + _Q[2]
    p = p * r + _Q[1]
    p = p * r + _Q[0]
    p = p * r + 1.0
    p = p * r + 1.0
    return p * _bits_as_float(_float_as_bits(kd) << 52)


_F32 = np.float32
_LOG2E_32 = _F32(_LOG2E)
_LN2_HI_32 = _F32(0.693359375)  # 9 bits: n * _LN2_HI_32 is exact for |n| < 2^15
_LN2_LO_32 = _F32(-2.12194440e-4)
_SHIFTER_32 = _F32(12582912.0)  # 1.5 * 2^23
_EXP_BOUND_32 = _F32(87.0)
_BIAS_32 = np.int32(127)
_C32 = tuple(_F32(1.0 / c) for c in (5040.0, 720.0, 120.0, 24.0, 6.0, 2.0, 1.0, 1.0))


@nb.njit(cache=True, nogil=True, fastmath=_FLAGS)
def _exp32(x):
    """float32 ``exp(x)`` within 1 ulp for |x| <= 87; ``x`` beyond is clamped to +-87.

    The clamp keeps every result a normal float32 (subnormal arithmetic is
    slow on x86); the Taylor polynomial of ``exp(r)``, ``|r| <= ln2 / 2``,
    has degree 7 (truncation error below 6e-9).
    """
    x = min(max(x, -_EXP_BOUND_32), _EXP_BOUND_32)
    kd = x * _LOG2E_32 + _SHIFTER_32
    n = kd - _SHIFTER_32
    r = (x - n * _LN2_HI_32) - n * _LN2_LO_32
    p = _C32[0]
    p = p * r + _C32[1]
    p = p * r + _C32[2]
    p = p * r + _C32[3]
    p = p * r + _C32[4]
    p = p * r + _C32[5]
    p = p * r + _C32[6]
    p = p * r + _C32[7]
    return p * _bits_as_float32(np.int32((_float32_as_bits(kd) + _BIAS_32) << 23))


@nb.njit(cache=True, nogil=True, fastmath={"reassoc", "contract"})
def _exp_sum(row, shift, scratch):
    """``sum(exp(row - shift))`` in float64 (reassociated: vectorised partial sums).

    A float32 row is exponentiated in float32 into ``scratch`` (a loop of its
    own, so it runs at float32's SIMD width) and then summed in float64.
    """
    acc = 0.0
    if row.itemsize == 4:
        s32 = _F32(shift)
        for j in range(row.size):
            scratch[j] = _exp32(_F32(row[j]) - s32)
        for j in range(row.size):
            acc += np.float64(scratch[j])
    else:
        for j in range(row.size):
            acc += _exp(np.float64(row[j]) - shift)
    return acc


@intrinsic
def _fmax(typingctx, a, b):
    """``max(a, b)`` of two floats of one type, free to be vectorised as a reduction.

    LLVM's ``maxnum`` with the no-NaN flag: a loop of them becomes a SIMD
    maximum (a ``max`` of numba's is a compare and select that LLVM keeps
    scalar, one value per cycle or two). Kernel tiles are NaN-free products
    of finite arrays.
    """
    if a != b or a not in (types.float32, types.float64):
        return None

    def codegen(context, builder, signature, args):
        ty = context.get_value_type(a)
        fn = builder.module.declare_intrinsic("llvm.maxnum", [ty], ir.FunctionType(ty, [ty, ty]))
        return builder.call(fn, args, fastmath=("nnan", "nsz"))

    return a(a, b), codegen


@nb.njit(cache=True, nogil=True)
def _row_max(row):
    """The largest value of a non-empty row, in float64 (a SIMD reduction in the row's dtype)."""
    m = row[0]
    for j in range(1, row.size):
        m = _fmax(m, row[j])
    return np.float64(m)


@nb.njit(cache=True, nogil=True)
def framed_exp_sums(t, frame, sums, first, low, big):
    """Add ``sum_j exp(t[i, j] - frame[i])`` to ``sums[i]`` for each row ``i``.

    Parameters
    ----------
    t : ndarray of shape (n_rows, n_cols), float64 or float32
        Log-kernel values of one tile (one class's patterns).
    frame, sums : ndarray of shape (n_rows,), float64
        Each row's log frame and its class sum relative to it, updated in place.
    first : bool
        The class's first tile: the frame is set, to 0 where the tile's
        largest value exceeds ``low`` (no shift), else to that value, and
        the sums start from 0.
    low, big : float
        The frame's threshold, and the tile sum above which the frame is
        raised to the tile's maximum and the sum recomputed (a near pattern
        after far ones).
    """
    scratch = np.empty(t.shape[1], dtype=np.float32)
    for i in range(t.shape[0]):
        row = t[i]
        if first:
            m = _row_max(row)
            frame[i] = 0.0 if m > low else m
            sums[i] = 0.0
        f = frame[i]
        acc = _exp_sum(row, f, scratch)
        if not acc <= big:
            new = max(f, _row_max(row))
            sums[i] *= math.exp(f - new)  # exact, to 0 if need be: unclamped
            acc = _exp_sum(row, new, scratch)
            frame[i] = new
        sums[i] += acc


@nb.njit(cache=True, nogil=True)
def vexp(x, out):
    """``out[:] = exp(x)`` by the kernels' ``exp`` of ``x``'s dtype (clamped), for tests."""
    for j in range(x.size):
        out[j] = _exp32(x[j]) if x.itemsize == 4 else _exp(x[j])
