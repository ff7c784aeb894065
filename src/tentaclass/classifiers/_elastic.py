"""Elastic matching of closed outlines: height functions aligned by dynamic programming.

Every outline is resampled to ``N`` points equally spaced by arc length. The
descriptor of point ``i`` holds the signed distances ("heights") of the other
points, in contour order starting after ``i``, to the line through ``i``
parallel to the chord of its two neighbours; the heights are averaged in ``M``
consecutive groups (smoothing and shortening at once), each of the ``M``
values is divided by its largest magnitude over the outline (scale), and
weighted so that nearby points count more. Two outlines are compared by an
order-preserving one-to-one alignment of their points (points may be left
unmatched at a fixed price) found by dynamic programming, started at the few
cyclic offsets where a rigid alignment of the descriptors is best, and for the
mirror image too (J. Wang, X. Bai, X. You, W. Liu, L. J. Latecki, "Shape
matching and classification using height functions", Pattern Recognition
Letters 33, 2012). The second outline's descriptors are also taken half-way
between its points (a point of the first is matched with the nearest of three),
so that two outlines sampled from different start points still match closely;
the aligned cost is divided by the two shapes' complexities, as in the paper.
Work: the cost matrix (N x 2N x M) and N_STARTS alignments (N x N) per pair and
direction, each pair of a square matrix once, pairs of rows spread over numba's
threads.

The matcher is written by hand in numba: no maintained library aligns cyclic
sequences of point descriptors order-preservingly with unmatched points (DTW
packages such as tslearn or dtaidistance match open 1-D or N-D series with
repetitions, not closed contours with a free start point and skips).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from .._typing import FloatArray
from ..geometry import resample_closed

#: Points per outline, smoothed height values per point.
N_POINTS, N_HEIGHTS = 100, 20
#: Heights are taken of DENSE times as many points; the tangent of a point is
#: the chord of the points TANGENT_SPAN dense steps before and after it.
DENSE, TANGENT_SPAN = 4, 4
#: Weight of a height value: exp(-distance along the outline / (WEIGHT_SCALE * N)).
WEIGHT_SCALE = 0.25
#: Price of leaving a point unmatched, in units of the mean point cost.
SKIP = 0.6
#: Cyclic offsets tried as start points (the best of a rigid alignment).
N_STARTS = 4


def height_descriptors(outlines: FloatArray, stride: int) -> tuple[FloatArray, FloatArray]:
    """Weighted, normalised height descriptors of counter-clockwise outlines.

    ``outlines`` has shape (n, N * DENSE, 2) (resampled); returns ``(F,
    F_mirror)`` of shape (n, N, M), float32: ``F_mirror`` describes each
    outline's mirror image traversed counter-clockwise (its reverse with
    negated heights).
    """
    F = heights(outlines, stride)
    Fm = -heights(np.roll(outlines[:, ::-1], 1, axis=1), stride)
    return F, Fm


def heights(Q: FloatArray, stride: int) -> FloatArray:
    """The first array of :func:`height_descriptors` alone (no mirror images)."""
    # Q: dense points, DENSE per described point; heights are taken of all dense
    # points so that each smoothed value is an integral along the outline and
    # varies smoothly with the described point's position
    n, K, _ = Q.shape
    N = K // stride
    P = Q[:, ::stride]
    span = TANGENT_SPAN
    t = np.roll(Q, -span, axis=1)[:, ::stride] - np.roll(Q, span, axis=1)[:, ::stride]
    t /= np.maximum(np.linalg.norm(t, axis=2, keepdims=True), 1e-300)
    nx, ny = -t[..., 1], t[..., 0]  # the normal on the left: inwards when CCW
    idx = (stride * np.arange(N)[:, None] + np.arange(1, K)[None, :]) % K  # (N, K-1)
    F = np.empty((n, N, N_HEIGHTS))
    edges = np.linspace(0, K - 1, N_HEIGHTS + 1).round().astype(int)
    Qx, Qy = np.ascontiguousarray(Q[..., 0]), np.ascontiguousarray(Q[..., 1])
    for k in range(n):  # one shape at a time: (N, K-1) stays small
        # the height of every point over each described point's tangent, x and y apart
        h = (Qx[k, idx] - P[k, :, 0, None]) * nx[k, :, None]
        h += (Qy[k, idx] - P[k, :, 1, None]) * ny[k, :, None]
        F[k] = np.add.reduceat(h, edges[:-1], axis=1) / np.diff(edges)
    # scale: by the largest magnitude over the N described points (whatever the stride)
    coarse = F[:, :: DENSE // stride]
    F /= np.maximum(np.abs(coarse).max(axis=1, keepdims=True), 1e-300)
    centre = ((edges[:-1] + edges[1:] - 1) / 2 + 1) / DENSE  # steps along the outline
    n_points = K // DENSE
    w = np.exp(-np.minimum(centre, n_points - centre) / (WEIGHT_SCALE * n_points))
    F *= w / w.sum()
    return np.ascontiguousarray(F, dtype=np.float32)


def resample_outlines(outlines: list[FloatArray]) -> FloatArray:
    """Resample validated counter-clockwise outlines to (n, N_POINTS * DENSE, 2)."""
    return np.stack([resample_closed(o, N_POINTS * DENSE) for o in outlines])


_OPTS = {"cache": True, "nogil": True, "fastmath": True, "boundscheck": False}


@nb.njit(**_OPTS)
def _cost(FX, FY, C, tmp):
    # C[i, j] = C[i, j + N] = L1 distance of descriptor i of X to the nearest of
    # Y's descriptors at j - 1/2, j, j + 1/2 (FY holds them at half steps):
    # this halves the error of sampling the two outlines at different offsets
    N, M = FX.shape
    N2 = FY.shape[0]
    total = 0.0
    for i in range(N):
        for q in range(N2):
            s = nb.float32(0.0)
            for m in range(M):
                s += abs(FX[i, m] - FY[q, m])
            tmp[q] = s
        for j in range(N):
            s = min(tmp[2 * j], tmp[2 * j - 1], tmp[(2 * j + 1) % N2])
            C[i, j] = s
            C[i, j + N] = s
            total += s
    return total / (N * N)


@nb.njit(**_OPTS)
def _dp(C, shift, skip, row, prev):
    # order-preserving one-to-one alignment of X[0..N) with Y[shift..shift+N),
    # each unmatched point costing skip
    N = C.shape[0]
    for j in range(N + 1):
        prev[j] = j * skip
    for i in range(1, N + 1):
        row[0] = i * skip
        ci = C[i - 1]
        for j in range(1, N + 1):
            best = prev[j - 1] + ci[j - 1 + shift]
            other = prev[j] + skip
            if other < best:
                best = other
            other = row[j - 1] + skip
            if other < best:
                best = other
            row[j] = best
        for j in range(N + 1):
            prev[j] = row[j]
    return prev[N]


@nb.njit(**_OPTS)
def _match(FX, FY, C, tmp, score, row, prev, skip_frac, n_starts):
    N = FX.shape[0]
    mean = _cost(FX, FY, C, tmp)
    # rigid alignment: total cost of every cyclic offset
    for s in range(N):
        t = 0.0
        for i in range(N):
            t += C[i, i + s]
        score[s] = t
    skip = skip_frac * mean
    best = np.inf
    for _ in range(n_starts):
        s = int(np.argmin(score))
        if score[s] == np.inf:
            break
        # suppress the neighbouring offsets: the alignment absorbs small ones
        for d in range(-2, 3):
            score[(s + d) % N] = np.inf
        d = _dp(C, s, skip, row, prev)
        if d < best:
            best = d
    return best / N


@nb.njit(parallel=True, **_OPTS)
def _distances(FA, FB, FBm, symmetric, skip_frac, n_starts):
    na, N, _ = FA.shape
    nb_ = FB.shape[0]
    D = np.zeros((na, nb_))
    # rows paired (r, na-1-r) so that every task holds a similar number of pairs
    n_tasks = (na + 1) // 2
    for task in nb.prange(n_tasks):
        C = np.empty((N, 2 * N), dtype=np.float32)
        score = np.empty(N)
        tmp = np.empty(2 * N, dtype=np.float32)
        row = np.empty(N + 1)
        prev = np.empty(N + 1)
        for k in range(2):
            a = np.int64(task) if k == 0 else np.int64(na - 1 - task)
            if k == 1 and a == np.int64(task):
                break
            start = a + 1 if symmetric else 0
            for b in range(start, nb_):
                d1 = _match(FA[a], FB[b], C, tmp, score, row, prev, skip_frac, n_starts)
                d2 = _match(FA[a], FBm[b], C, tmp, score, row, prev, skip_frac, n_starts)
                D[a, b] = min(d1, d2)
    if symmetric:
        for i in range(na):
            for j in range(i + 1, na):
                D[j, i] = D[i, j]
    return D


def elastic_distances(A: FloatArray, B: FloatArray | None) -> FloatArray:
    """Distances between resampled counter-clockwise outlines (see module doc).

    The aligned cost is divided by the sum of the two shapes' complexities
    (the spread of their descriptors over the outline).
    """
    FA = heights(A, DENSE)
    ca = complexity(FA)
    FB, FBm = height_descriptors(A if B is None else B, DENSE // 2)
    D = _distances(FA, FB, FBm, B is None, SKIP, N_STARTS)
    cb = ca if B is None else complexity(FB[:, ::2])
    return D / (ca[:, None] + cb[None, :])


def complexity(F: FloatArray) -> FloatArray:
    """Spread of each shape's descriptors over its outline.

    The sum over heights of their standard deviation (0 only for a shape whose
    points all look alike, such as a circle: floored at 1e-12).
    """
    return np.maximum(F.std(axis=1, dtype=np.float64).sum(axis=1), 1e-12)


@nb.njit(parallel=True, **_OPTS)
def _pair_distances(FA, FB, FBm, ia, ib, skip_frac, n_starts):
    # the pairs (FA[ia[p]], FB[ib[p]]) only, spread over numba's threads in blocks
    n_pairs = ia.shape[0]
    N = FA.shape[1]
    D = np.empty(n_pairs)
    block = 16
    for task in nb.prange((n_pairs + block - 1) // block):
        C = np.empty((N, 2 * N), dtype=np.float32)
        score = np.empty(N)
        tmp = np.empty(2 * N, dtype=np.float32)
        row = np.empty(N + 1)
        prev = np.empty(N + 1)
        for p in range(task * block, min(n_pairs, (task + 1) * block)):
            a, b = ia[p], ib[p]
            d1 = _match(FA[a], FB[b], C, tmp, score, row, prev, skip_frac, n_starts)
            d2 = _match(FA[a], FBm[b], C, tmp, score, row, prev, skip_frac, n_starts)
            D[p] = min(d1, d2)
    return D


def query_descriptors(outlines: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Descriptors of resampled outlines on the query side of :func:`pair_distances`.

    Returns ``(F, F_mirror, complexity)``: descriptors at half steps (n, 2N,
    M), those of the mirror images, and each outline's complexity.
    """
    F, Fm = height_descriptors(outlines, DENSE // 2)
    return F, Fm, complexity(F[:, ::2])


def pair_distances(
    FA: FloatArray,
    ca: FloatArray,
    FB: FloatArray,
    FBm: FloatArray,
    cb: FloatArray,
    ia: np.ndarray,
    ib: np.ndarray,
) -> FloatArray:
    """Elastic distances of the pairs ``(A[ia[p]], B[ib[p]])``, as :func:`elastic_distances`.

    ``FA`` (n_a, N, M) and ``ca`` are :func:`height_descriptors` (at whole
    steps) and :func:`complexity` of the first outlines; ``FB``, ``FBm``,
    ``cb`` come from :func:`query_descriptors`.
    """
    ia = np.ascontiguousarray(ia, dtype=np.int64)
    ib = np.ascontiguousarray(ib, dtype=np.int64)
    if ia.size == 0:
        return np.empty(0)
    D = _pair_distances(FA, FB, FBm, ia, ib, SKIP, N_STARTS)
    return D / (ca[ia] + cb[ib])
