"""Shape retrieval: distances between outline series, and the bull's-eye test."""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validation import as_float_array, check_positive_int
from ..errors import InputError, ShapeError
from ..features.outline import znormalize
from ._shift_nn import ShiftNNClassifier

__all__ = ["bullseye_score", "shape_distances"]


def shape_distances(A: ArrayLike, B: ArrayLike | None = None) -> FloatArray:
    """Distances between outline series, whatever their start point and direction.

    Each series is z-normalised, then ``d(a, b) = min over cyclic shifts s and
    mirror images of ||a - roll(b, s)|| / sqrt(n)``, all shifts scored at once
    by FFT cross-correlation.

    Parameters
    ----------
    A : array_like of shape (n_a, n_timepoints)
    B : array_like of shape (n_b, n_timepoints), optional
        Default ``A`` (the square matrix of all pairs).

    Returns
    -------
    D : ndarray of shape (n_a, n_b)
        Non-negative; symmetric with a zero diagonal when ``B`` is None.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 * np.pi, 32, endpoint=False)
    >>> a = np.cos(3 * t)
    >>> D = shape_distances([a, np.roll(a, 5)[::-1], np.cos(2 * t)])
    >>> bool(D[0, 1] < 1e-9 < D[0, 2])
    True
    """
    Za = _series(A, "A")
    Zb = Za if B is None else _series(B, "B")
    if Zb.shape[1] != Za.shape[1]:
        raise ShapeError(
            f"A and B must hold series of one length, got {Za.shape[1]} and {Zb.shape[1]}"
        )
    nn = ShiftNNClassifier(signal="raw", center=False).fit(Zb, np.zeros(len(Zb)))
    D = np.sqrt(nn.shift_distances(Za) / Za.shape[1])
    if B is None:
        D = np.minimum(D, D.T)
        np.fill_diagonal(D, 0.0)
    return D


def _series(X: ArrayLike, name: str) -> FloatArray:
    arr = as_float_array(X, name, min_ndim=2)
    if arr.ndim != 2:
        raise ShapeError(f"{name} must have shape (n_series, n_timepoints), got {arr.shape}")
    if arr.shape[0] == 0 or arr.shape[1] < 3:
        raise ShapeError(f"{name} must hold series of at least 3 points, got shape {arr.shape}")
    return znormalize(arr, name)


def bullseye_score(D: ArrayLike, labels: ArrayLike, *, top: int = 40) -> float:
    """The MPEG-7 bull's-eye test of a distance matrix.

    For each shape, count the shapes of its own class among its ``top``
    nearest (itself included); the score is the sum over all shapes divided by
    its largest possible value, ``sum of min(class size, top)`` (28 000 for
    MPEG-7 Part B: 1400 shapes, 20 per class, top 40).

    Parameters
    ----------
    D : array_like of shape (n, n)
        Pairwise distances (smaller is nearer).
    labels : array_like of shape (n,)
    top : int, default=40

    Returns
    -------
    score : float
        In [0, 1].

    Examples
    --------
    >>> D = [[0, 1, 5, 5], [1, 0, 5, 5], [5, 5, 0, 1], [5, 5, 1, 0]]
    >>> bullseye_score(D, ["a", "a", "b", "b"], top=2)
    1.0
    """
    D = as_float_array(D, "D", min_ndim=2)
    if D.ndim != 2 or D.shape[0] != D.shape[1]:
        raise ShapeError(f"D must be a square matrix, got shape {D.shape}")
    labels = np.asarray(labels)
    if labels.shape != (D.shape[0],):
        raise ShapeError(f"labels must have shape ({D.shape[0]},), got {labels.shape}")
    k = min(check_positive_int(top, "top"), D.shape[0])
    if D.shape[0] == 0:
        raise InputError("D is empty")
    # nearest first; ties broken by index so the shape itself comes first
    D = D.copy()
    np.fill_diagonal(D, -np.inf)
    nearest = np.argsort(D, axis=1, kind="stable")[:, :k]
    hits = (labels[nearest] == labels[:, None]).sum()
    _, counts = np.unique(labels, return_inverse=False, return_counts=True)
    best = sum(min(c, k) * c for c in counts)
    return float(hits / best)
