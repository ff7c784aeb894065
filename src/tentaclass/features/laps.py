"""Every lap of a wrap, found from the joint angles alone, averaged into one.

A fixed chain wraps a small object more than once and a large one less than
once, after an approach from a base that stands off. From the angles alone
this module finds the approach (:func:`tentaclass.grasp_state`), the length
of one lap in links (where the chain returns on itself: the heading has
turned by one full turn and the rebuilt joint positions meet again), cuts the
chain into laps backwards from its end and averages the heading function of
all of them, phase by phase: a partial first lap fills in the phases it
covers. Joint noise is white in the angles, so averaging ``k`` laps divides
its variance by ``k``. The result is one closed lap of equal links, the array
the shape matchers expect.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validation import MAX_LINKS, as_angle_array, check_positive_int

__all__ = ["LapSplit", "split_laps"]

#: Candidate lap lengths are tried on a grid this fine (in links).
_STEP = 0.1
#: (row, candidate, arc) values :func:`_periods` holds at a time.
_WORK_VALUES = 2_000_000
#: A lap is accepted when the heading has turned within this of a full turn.
_TURN_TOL = np.pi / 2
#: ... and the chain's end lies within this fraction of a lap of the point one lap before.
_GAP_TOL = 0.3
#: A lap overlapping the chain by less than this fraction of the chain ...
_SHORT_OVERLAP = 1 / 8
#: ... only where the chain's end comes within this many links of the point a lap before.
_SHORT_GAP = 3.0


@dataclass(frozen=True)
class LapSplit:
    """Laps of a batch of wraps; every field has the batch shape unless noted.

    Attributes
    ----------
    lap : ndarray of shape (..., n_out)
        Joint angles of the averaged closed lap, ``n_out`` equal links, sum
        ``2*pi``, counter-clockwise. For a partial wrap: the turns of the part
        after the approach, resampled to ``n_out`` links (sum below ``2*pi``).
    laps : ndarray of float
        Laps wrapped after the approach (``(n_joints - offset) / period``; for
        a partial wrap its turn over ``2*pi``).
    period : ndarray of float
        Links in one lap (NaN for a partial wrap).
    offset : ndarray of int
        Approach links before the first contact.
    closed : ndarray of bool
        True where at least one full lap was found.
    direction : ndarray of int
        +1 counter-clockwise, -1 clockwise (mirrored before everything else).
    """

    lap: FloatArray
    laps: FloatArray
    period: FloatArray
    offset: np.ndarray
    closed: np.ndarray
    direction: np.ndarray


def _interp(values: FloatArray, x: FloatArray) -> FloatArray:
    """Piecewise-linear ``values`` sampled at 0, 1, ..., taken at ``x`` (rows broadcast).

    ``values`` (b, m); ``x`` (b, ...) in index units; clamped at both ends.
    """
    m = values.shape[1]
    x = np.clip(x, 0.0, m - 1.0)
    i = np.minimum(np.floor(x).astype(np.int64), m - 2)
    f = x - i
    flat_i = i.reshape(len(values), -1)
    lo = np.take_along_axis(values, flat_i, axis=1).reshape(x.shape)
    hi = np.take_along_axis(values, flat_i + 1, axis=1).reshape(x.shape)
    return lo + f * (hi - lo)


def _periods(heading: FloatArray, points: np.ndarray, start: FloatArray) -> FloatArray:
    """Links per lap for each row, or NaN where no full lap follows the approach.

    ``heading`` (b, n) of each link (link ``k`` spans arc ``[k, k+1]``),
    ``points`` (b, n + 1) complex joints, ``start`` (b,) arc where the
    surface starts. Cost of a lap length ``P``: the mean squared difference
    of the heading function and itself ``P`` links earlier plus one turn, over
    everything after the approach, plus the squared gap between the chain's
    end and the point ``P`` links before it, relative to ``P``. Exact for a
    clean wrap (the gap closes), robust to noise (the heading comparison uses
    local angles only).

    A lap that overlaps the chain by less than ``_SHORT_OVERLAP`` of it
    compares only a few headings, which a lap about as long as the whole
    chain can match by chance (a hugging chain's second lap meets the
    outline at other points than its first, so the right lap length's
    headings differ by up to a radian on a wiggly outline). Such a lap is
    accepted only where the chain's end comes back within ``_SHORT_GAP``
    links of the point one lap before it.
    """
    b, n = heading.shape
    cands = np.arange(3.0, n + _STEP / 2, _STEP)
    s = np.arange(0.5, n, 0.5)  # arc positions compared
    out = np.full(b, np.nan)
    # at most about 2e6 (row, candidate, arc) values at a time: rows in chunks, and for
    # long chains (one row already more) candidates in blocks, so memory stays bounded
    chunk = max(1, _WORK_VALUES // (len(cands) * len(s)))
    for lo in range(0, b, chunk):
        h, p, a = heading[lo : lo + chunk], points[lo : lo + chunk], start[lo : lo + chunk]
        m = len(h)
        # heading at arc x: link midpoints at k + 0.5
        now = _interp(h, np.broadcast_to(s - 0.5, (m, len(s))))[:, None, :]
        # only lap lengths whose ends meet for some row are scored (the others cost inf):
        # a wrap of many laps or a short chain leaves few of the 10 * n candidates
        gap, meet = _ends_meet(h, p, a, cands)
        live = np.flatnonzero(meet.any(axis=0))
        cost = np.full((m, len(cands)), np.inf)
        step = max(1, _WORK_VALUES // (m * len(s)))
        for c in range(0, len(live), step):
            cols = live[c : c + step]
            cost[:, cols] = _lap_costs(h, a, now, cands[cols], s, gap[:, cols], meet[:, cols])
        best = np.argmin(cost, axis=1)
        found = np.isfinite(cost[np.arange(m), best])
        out[lo : lo + chunk] = np.where(found, cands[best], np.nan)
    return out


def _lap_costs(
    h: FloatArray,
    a: FloatArray,
    now: FloatArray,
    cands: FloatArray,
    s: np.ndarray,
    gap: FloatArray,
    meet: np.ndarray,
) -> FloatArray:
    """:func:`_periods`'s cost of each lap length ``cands`` for rows ``h`` (inf: refused).

    ``a`` the rows' surface starts, ``now`` the headings at the arc positions
    ``s``, ``gap`` and ``meet`` those of :func:`_ends_meet` for ``cands``.
    Shape (rows, candidates).
    """
    m, n = h.shape
    earlier = s[None, None, :] - cands[None, :, None]  # (1, c, s)
    valid = earlier >= a[:, None, None]  # (m, c, s)
    then = _interp(h, np.broadcast_to(earlier - 0.5, (m, len(cands), len(s))))
    diff = (now - then - 2 * np.pi) ** 2
    count = valid.sum(axis=2)
    cost = np.where(valid, diff, 0.0).sum(axis=2) / np.maximum(count, 1)
    cost = cost + gap**2
    # a lap overlaps itself by a link or more and its ends meet again
    ok = (count >= 2) & meet
    # count is in half links: a short overlap must close in links, not only relative to P
    ok &= (count >= 2 * _SHORT_OVERLAP * n) | (gap * cands < _SHORT_GAP)
    return np.where(ok, cost, np.inf)


def _ends_meet(
    h: FloatArray, p: np.ndarray, a: FloatArray, cands: FloatArray
) -> tuple[FloatArray, np.ndarray]:
    """Whether a lap of ``cands`` links can end where the chain ends, and the gap there.

    The gap is the distance from the chain's end to the point ``cands`` links
    before it, over the lap length. The ends allow a lap where the heading
    turned within ``_TURN_TOL`` of a full turn, the gap is below ``_GAP_TOL``
    and the lap lies after the approach. Rows ``h`` (headings), ``p`` (complex
    joints), ``a`` (surface starts); shape (rows, candidates). Costs one value
    per candidate, not one per arc position.
    """
    m, n = h.shape
    end_then = _interp_complex(p, np.broadcast_to(n - cands, (m, len(cands))))
    gap = np.abs(p[:, -1:] - end_then) / cands
    turned = h[:, -1:] - _interp(h, np.broadcast_to(n - 1.0 - cands, (m, len(cands))))
    meet = (np.abs(turned - 2 * np.pi) < _TURN_TOL) & (gap < _GAP_TOL)
    return gap, meet & (cands[None, :] <= n - a[:, None])


def _interp_complex(z: np.ndarray, x: FloatArray) -> np.ndarray:
    return _interp(z.real, x) + 1j * _interp(z.imag, x)


def _merged(heading, start, period, mean, phase_index, n_out):
    """One lap's heading function from the link headings of every lap, merged by phase.

    Each link after the approach is a sample of the lap's heading at its own
    phase (laps start at different points between joints, so together they
    sample the outline more finely than one lap). Each lap is first shifted to
    agree on average with ``mean`` (the phase-wise average: joint noise drifts
    each lap's heading by its own constant), then all samples are sorted by
    phase and interpolated (periodically) at the ``n_out`` output phases.
    """
    n = len(heading)
    s = np.arange(n) + 0.5
    keep = s >= start + 0.5
    s, h = s[keep], heading[keep]
    back = (n - s) / period  # laps from the chain's end
    j = np.floor(back)
    ph = 1.0 - (back - j)  # phase in [0, 1)
    h = h + 2 * np.pi * j
    # each lap's offset from the average, removed
    ref = np.interp(ph * n_out - 0.5, phase_index, mean, period=n_out)
    for lap in np.unique(j):
        sel = j == lap
        h[sel] -= np.mean(h[sel] - ref[sel])
    order = np.argsort(ph)
    ph, h = ph[order], h[order]
    ph = np.concatenate([ph - 1, ph, ph + 1])
    h = np.concatenate([h - 2 * np.pi, h, h + 2 * np.pi])
    return np.interp((phase_index + 0.5) / n_out, ph, h)


def split_laps(q: ArrayLike, n_out: int = 64) -> LapSplit:
    """Find the laps of wraps from their joint angles and average them into one.

    Parameters
    ----------
    q : array_like of shape (..., n_joints)
        Joint angles of wraps by a chain of equal links: any approach, any
        number of laps (also less than one), either direction.
    n_out : int, default=64
        Links of the averaged lap.

    Returns
    -------
    LapSplit

    Examples
    --------
    >>> import numpy as np
    >>> square = np.tile([0, 0, 0, np.pi / 2], 4)  # one lap of 16 links
    >>> approach = np.r_[0.0, 0.0, -np.pi / 2]  # base 2 links off the object
    >>> s = split_laps(np.r_[approach, square, square[:8]], n_out=16)
    >>> float(s.period), round(float(s.laps), 2), int(s.offset), bool(s.closed)
    (16.0, 1.5, 2, True)
    >>> bool(np.isclose(s.lap.sum(), 2 * np.pi))
    True
    """
    from ..wrapping import grasp_state

    q = as_angle_array(q, "q", min_joints=3)
    batch, n = q.shape[:-1], q.shape[-1]
    # at most the longest chain, or the input's own length
    n_out = check_positive_int(n_out, "n_out", minimum=3, maximum=max(n, MAX_LINKS))
    flat = q.reshape(-1, n)
    flat = np.where(np.isfinite(flat), flat, 0.0)
    g = grasp_state(flat)
    direction = g.direction
    flat = flat * direction[:, None]
    heading = np.cumsum(flat, axis=1)
    z = np.concatenate([np.zeros((len(flat), 1)), np.cumsum(np.exp(1j * heading), axis=1)], 1)
    offset = np.minimum(g.offset_links, n - 3)
    start = offset.astype(float)
    period = _periods(heading, z, start)
    closed = np.isfinite(period)
    laps = np.where(closed, (n - start) / np.where(closed, period, 1.0), 0.0)
    lap = np.empty((len(flat), n_out))
    # closed: heading at phase m of lap j (j = 0 the last), averaged over the laps seen
    pc = np.where(closed, period, 1.0)
    n_laps = int(np.ceil(np.nanmax(laps, initial=1.0))) + 1
    j = np.arange(n_laps)[None, :, None]
    phase = (np.arange(n_out) + 0.5) / n_out
    s = n - (j + 1 - phase[None, None, :]) * pc[:, None, None]  # (b, laps, n_out)
    seen = s >= start[:, None, None] + 0.5
    h = _interp(heading, s - 0.5) + 2 * np.pi * j
    mean = np.where(seen, h, 0.0).sum(axis=1) / np.maximum(seen.sum(axis=1), 1)
    phase_of = phase * n_out - 0.5  # sample positions in index units
    for r in np.flatnonzero(closed):
        mean[r] = _merged(heading[r], start[r], pc[r], mean[r], phase_of, n_out)
    turns = np.diff(mean, axis=1, prepend=(mean[:, -1] - 2 * np.pi)[:, None])
    lap[closed] = turns[closed]
    # partial: the turns after the approach, resampled to n_out equal links
    open_rows = np.flatnonzero(~closed)
    if open_rows.size:
        a = start[open_rows]
        x = a[:, None] + 0.5 + (np.arange(n_out + 1) / n_out) * (n - 1 - a)[:, None]
        ho = _interp(heading[open_rows], x - 0.5)
        lap[open_rows] = np.diff(ho, axis=1)
        laps[open_rows] = (heading[open_rows, -1] - _interp(heading[open_rows], a[:, None])[:, 0]
                           ) / (2 * np.pi)  # fmt: skip
    return LapSplit(
        lap=lap.reshape(*batch, n_out),
        laps=laps.reshape(batch),
        period=period.reshape(batch),
        offset=offset.reshape(batch),
        closed=closed.reshape(batch),
        direction=direction.reshape(batch),
    )
