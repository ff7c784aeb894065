"""One closed lap out of a longer or offset wrap, from the joint angles alone.

A real chain does not stop exactly where it closed: it may stand off the
object (approach links), wrap more than once, or stop short. On a robot only
the joint angles ``q`` and the link length are known, so this module rebuilds
the joint positions by forward kinematics, finds where the chain last returned
to a point it had passed one turn (``2*pi`` of turning) before, and resamples
that last lap to a fixed number of equal links: the closed array the Fourier
features expect. It makes recognition independent of the offset, the number
of laps and the link length.
"""

from __future__ import annotations

import numpy as np

from .._dask import blockwise
from .._typing import ArrayLike, BoolArray, FloatArray
from .._validation import MAX_LINKS, as_angle_array, check_positive_int
from ..errors import InputError
from ..geometry import _link_lengths, angles_to_points, points_to_angles, resample_closed

__all__ = ["last_lap"]


def _closure(points: FloatArray, t: FloatArray) -> tuple[int, float] | None:
    """Link ``m`` and fraction ``u`` where the last lap starts, or None.

    The last lap ends at ``p_n``; it starts where the chain passed closest to
    ``p_n`` while it still had about one turn to go (``t_n - t_m`` within a
    quarter turn of ``2*pi``).
    """
    n = len(t)
    turn_left = t[-1] - np.concatenate([[0.0], t])  # turning still to come after joint j
    end = points[-1]
    a, b = points[:-1], points[1:]
    ab = b - a
    denom = np.einsum("ij,ij->i", ab, ab)
    u = np.clip(np.einsum("ij,ij->i", end - a, ab) / np.where(denom > 0, denom, 1.0), 0.0, 1.0)
    dist = np.linalg.norm(a + u[:, None] * ab - end, axis=1)
    # turning left over link j..n, interpolated at the closest point of link j
    left = turn_left[:-1] - u * (turn_left[:-1] - turn_left[1:])
    ok = np.abs(left - 2 * np.pi) < np.pi / 2
    ok[max(n - 2, 0) :] = False  # a lap needs at least 3 links
    if not ok.any():
        return None
    m = int(np.flatnonzero(ok)[np.argmin(dist[ok])])
    return m, float(u[m])


def _resample_open(points: FloatArray, n: int) -> FloatArray:
    """``n`` points equally spaced by arc length along an open chain, both ends kept."""
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    t = np.linspace(0.0, s[-1], n)
    return np.stack([np.interp(t, s, points[:, 0]), np.interp(t, s, points[:, 1])], axis=1)


@blockwise
def last_lap(
    q: ArrayLike, n_out: int | None = None, link_lengths: ArrayLike = 1.0
) -> tuple[FloatArray, BoolArray]:
    """The last full lap of a wrap, as a closed array of ``n_out`` equal links.

    Parameters
    ----------
    q : array_like of shape (..., n_joints)
        Joint angles of wraps that may start with approach links, cover more
        than one lap, or fall short of one.
    n_out : int, optional
        Links of the output lap, at least 2; default ``n_joints``.
    link_lengths : float or array_like of shape (n_joints,), default=1.0
        Link lengths (only their ratios matter).

    Returns
    -------
    lap : ndarray of shape (..., n_out)
        Angles of the closed lap (sum ``2*pi``; clockwise wraps are mirrored
        to counter-clockwise ones first, ``q -> -q``, which leaves the Fourier
        features of a closed lap unchanged). Rows with no full lap keep their angles,
        resampled to ``n_out`` links along the open chain, scaled to sum
        ``2*pi`` - a guess, flagged in ``closed``.
    closed : ndarray of bool, shape (...)
        True where a full lap was found.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.tile([0, 0, 0, np.pi / 2], 4)
    >>> approach_and_more = np.concatenate([[0.0, 0.0], square, square[:6]])
    >>> lap, closed = last_lap(approach_and_more, n_out=16)
    >>> bool(closed), bool(np.isclose(lap.sum(), 2 * np.pi))
    (True, True)
    >>> from tentaclass.features import fourier_features
    >>> bool(np.allclose(fourier_features(lap), fourier_features(square), atol=1e-9))
    True
    """
    q = as_angle_array(q, "q", min_joints=2)
    n = q.shape[-1]
    # at most the longest chain, or the input's own length
    top = max(n, MAX_LINKS)
    n_out = n if n_out is None else check_positive_int(n_out, "n_out", minimum=2, maximum=top)
    batch = q.shape[:-1]
    flat = q.reshape(-1, n)
    # Clockwise wraps are mirrored (negated) but not reversed: reversing would
    # move the approach links to the end of the chain.
    flat = np.where(flat.sum(axis=1, keepdims=True) < 0, -flat, flat)
    # only the ratios of the lengths matter: each row's longest link is 1
    lengths = _link_lengths(link_lengths, n)
    if lengths.ndim:
        lengths = lengths / lengths.max(axis=-1, keepdims=True)
    points = angles_to_points(flat, 1.0 if lengths.ndim == 0 else lengths)
    t = np.cumsum(flat, axis=1)
    out = np.empty((flat.shape[0], n_out))
    closed = np.zeros(flat.shape[0], bool)
    # Per row: the closure search is a handful of vector operations over the
    # chain; a batched version would pad ragged laps for no gain at these sizes.
    for i in range(flat.shape[0]):
        found = _closure(points[i], t[i])
        ring = None
        if found is not None:
            m, u = found
            start = points[i, m] + u * (points[i, m + 1] - points[i, m])
            ring = np.vstack([start, points[i, m + 1 : -1]])
            steps = np.linalg.norm(np.diff(np.vstack([ring, ring[:1]]), axis=0), axis=1)
            ring = ring[steps > 1e-12]
            if len(ring) < 3:  # a degenerate "lap" of coincident joints
                ring = None
        if ring is None:
            # the chain closed by the chord from its end back to its base: the cap
            # it spans describes a partial wrap far better than the open arc alone
            try:
                chain = resample_closed(points[i], n_out + 1)
                turns = points_to_angles(chain, closed=False)
            except InputError:  # a chain folded flat on itself has no closed shape
                chain = _resample_open(points[i], n_out + 1)
                turns = points_to_angles(chain, closed=False)
            total = turns.sum()
            out[i] = turns * (2 * np.pi / total) if abs(total) > 1e-12 else 2 * np.pi / n_out
            continue
        out[i] = points_to_angles(resample_closed(ring, n_out))
        closed[i] = True
    return out.reshape(*batch, n_out), closed.reshape(batch)
