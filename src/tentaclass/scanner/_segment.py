"""Compiled kernel of the line scanner: threshold, run-length encode, union-find.

Each row is thresholded and cut into runs (maximal stretches of object
pixels); a run joins every run of the previous row it touches (8-connected:
columns overlapping or meeting at a corner) through a union-find over labels.
An object whose root got no run in a row is complete: its runs are copied to
the output and its labels and runs go back to free lists, so memory holds only
the objects in flight. An object that reaches ``max_height + 1`` rows is cut:
its runs so far are output as a too-tall record and everything that joins it
later is dropped.

Pools are plain arrays owned by the Python caller; the kernel stops before a
row that might not fit (returning the rows done) and the caller grows the
pools or drains the output, then calls again. Rows are processed strictly one
after the other, so the result never depends on how they were chunked.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from .._jit import plain_calls

# label pool columns
PARENT, NEXT, TAIL, FIRST, LAST, MINC, AREA, STATUS, RHEAD, RTAIL = range(10)
N_LAB_FIELDS = 10
OPEN, DEAD, DONE = 0, 1, 2
# state scalars
(
    S_NPREV,
    S_FREE_LAB,
    S_FREE_RUN,
    S_LABS_USED,
    S_RUNS_USED,
    S_NOUT,
    S_NOUT_RUNS,
    S_IGNORED,
) = range(8)
N_STATE = 8
# output object columns: kind (0 complete, 1 too tall), first row, last row, min col,
# area, first output run, stop output run
N_OUT_FIELDS = 7

_OPTS = {"cache": True, "nogil": True, "boundscheck": False}


@nb.njit(**_OPTS)
def _find(labs, x):
    while labs[x, PARENT] != x:
        p = labs[labs[x, PARENT], PARENT]
        labs[x, PARENT] = p
        x = p
    return x


@nb.njit(**_OPTS)
def _free_runs(labs, runs, st, root):
    x = labs[root, RHEAD]
    while x != -1:
        nx = runs[x, 3]
        runs[x, 3] = st[S_FREE_RUN]
        st[S_FREE_RUN] = x
        st[S_RUNS_USED] -= 1
        x = nx
    labs[root, RHEAD] = -1
    labs[root, RTAIL] = -1


@nb.njit(**_OPTS)
def _union(labs, runs, st, a, b):
    """Merge roots ``a`` and ``b``; return the new root."""
    if labs[b, FIRST] < labs[a, FIRST]:
        a, b = b, a
    labs[b, PARENT] = a
    labs[labs[a, TAIL], NEXT] = b
    labs[a, TAIL] = labs[b, TAIL]
    labs[a, FIRST] = min(labs[a, FIRST], labs[b, FIRST])
    labs[a, LAST] = max(labs[a, LAST], labs[b, LAST])
    labs[a, MINC] = min(labs[a, MINC], labs[b, MINC])
    labs[a, AREA] += labs[b, AREA]
    if labs[a, STATUS] == DEAD or labs[b, STATUS] == DEAD:
        # whatever joins a cut (already reported) object is dropped with it
        _free_runs(labs, runs, st, a)
        _free_runs(labs, runs, st, b)
        labs[a, STATUS] = DEAD
    elif labs[b, RHEAD] != -1:
        if labs[a, RHEAD] == -1:
            labs[a, RHEAD] = labs[b, RHEAD]
        else:
            runs[labs[a, RTAIL], 3] = labs[b, RHEAD]
        labs[a, RTAIL] = labs[b, RTAIL]
    labs[b, RHEAD] = -1
    labs[b, RTAIL] = -1
    return a


@nb.njit(**_OPTS)
def _output(labs, runs, st, root, kind, last, out, out_runs):
    k = st[S_NOUT]
    out[k, 0] = kind
    out[k, 1] = labs[root, FIRST]
    out[k, 2] = last
    out[k, 3] = labs[root, MINC]
    out[k, 4] = labs[root, AREA]
    m = st[S_NOUT_RUNS]
    out[k, 5] = m
    x = labs[root, RHEAD]
    while x != -1:
        out_runs[m, 0] = runs[x, 0]
        out_runs[m, 1] = runs[x, 1]
        out_runs[m, 2] = runs[x, 2]
        m += 1
        x = runs[x, 3]
    out[k, 6] = m
    st[S_NOUT_RUNS] = m
    st[S_NOUT] = k + 1
    _free_runs(labs, runs, st, root)


@nb.njit(**_OPTS)
def _finish(labs, runs, st, prev, r, min_area, out, out_runs, done):
    """Output the objects of the previous row that got no run in row ``r``."""
    nd = 0
    for j in range(st[S_NPREV]):
        root = _find(labs, prev[j, 2])
        if labs[root, LAST] >= r or labs[root, STATUS] == DONE:
            continue
        if labs[root, STATUS] == OPEN:
            if labs[root, AREA] >= min_area:
                _output(labs, runs, st, root, 0, labs[root, LAST], out, out_runs)
            else:
                st[S_IGNORED] += 1
                _free_runs(labs, runs, st, root)
        labs[root, STATUS] = DONE
        done[nd] = root
        nd += 1
    # only now free the labels: other runs of the previous row may still point at them
    for i in range(nd):
        x = done[i]
        while x != -1:
            nx = labs[x, NEXT]
            labs[x, NEXT] = st[S_FREE_LAB]
            st[S_FREE_LAB] = x
            st[S_LABS_USED] -= 1
            x = nx


@nb.njit(**_OPTS)
def scan_rows(
    img, words, r0, mode, dark, level, contrast, rate, bg, max_height, min_area, final,
    st, prev, cur, labs, runs, out, out_runs, done,
):  # fmt: skip
    """Process rows of ``img`` (global row numbers from ``r0``); return rows done.

    ``mode`` 0: object where the value is non-zero (binary), 1: beyond the
    fixed ``level``, 2: beyond ``bg[col]`` by more than ``contrast``, ``bg``
    following the belt (updated by ``rate`` where no object is seen). ``dark``
    flips the side. ``words``: for mode 0, the same rows as 64-bit words (an
    all-zero word is skipped at once), or an empty array. With ``final``, the
    objects still open after the last row are output instead (``img`` is
    ignored).
    """
    width = bg.shape[0]
    n_words = words.shape[1]
    per_word = width // n_words if words.shape[0] else 0
    per_row = width // 2 + 1
    if final:
        _finish(labs, runs, st, prev, r0, min_area, out, out_runs, done)
        st[S_NPREV] = 0
        return 0
    n_rows = img.shape[0]
    for i in range(n_rows):
        # stop before a row that might not fit in the pools or the output
        if (
            labs.shape[0] - st[S_LABS_USED] < per_row
            or runs.shape[0] - st[S_RUNS_USED] < per_row
            or out.shape[0] - st[S_NOUT] < st[S_LABS_USED] + per_row
            or out_runs.shape[0] - st[S_NOUT_RUNS] < st[S_RUNS_USED] + per_row
        ):
            return i
        r = r0 + i
        # threshold and run-length encode the row
        ncur = 0
        inside = False
        if mode == 0:
            c = 0
            while c < width:
                if per_word:
                    while c < width and c % per_word and img[i, c] == 0:
                        c += 1
                    if c % per_word == 0:  # at a word: skip the all-zero ones
                        w = c // per_word
                        while w < n_words and words[i, w] == 0:
                            w += 1
                        c = w * per_word
                while c < width and img[i, c] == 0:
                    c += 1
                if c == width:
                    break
                cur[ncur, 0] = c
                while c < width and img[i, c] != 0:
                    c += 1
                cur[ncur, 1] = c
                ncur += 1
        for c in range(width if mode != 0 else 0):
            v = img[i, c]
            if mode == 0:
                on = v != 0
            elif mode == 1:
                on = (v < level) if dark else (v > level)
            else:
                d = v - bg[c]
                on = (-d > contrast) if dark else (d > contrast)
                if not on:
                    bg[c] += rate * d
            if on and not inside:
                cur[ncur, 0] = c
                inside = True
            elif inside and not on:
                cur[ncur, 1] = c
                ncur += 1
                inside = False
        if inside:
            cur[ncur, 1] = width
            ncur += 1
        # join the runs to those of the previous row
        nprev = st[S_NPREV]
        j = 0
        for k in range(ncur):
            s = cur[k, 0]
            e = cur[k, 1]
            while j < nprev and prev[j, 1] < s:
                j += 1
            root = -1
            jj = j
            while jj < nprev and prev[jj, 0] <= e:
                p = _find(labs, prev[jj, 2])
                if root == -1:
                    root = p
                elif p != root:
                    root = _union(labs, runs, st, root, p)
                jj += 1
            if root == -1:
                root = st[S_FREE_LAB]
                st[S_FREE_LAB] = labs[root, NEXT]
                st[S_LABS_USED] += 1
                labs[root, PARENT] = root
                labs[root, NEXT] = -1
                labs[root, TAIL] = root
                labs[root, FIRST] = r
                labs[root, LAST] = r
                labs[root, MINC] = s
                labs[root, AREA] = 0
                labs[root, STATUS] = OPEN
                labs[root, RHEAD] = -1
                labs[root, RTAIL] = -1
            cur[k, 2] = root
            labs[root, LAST] = r
            labs[root, AREA] += e - s
            if s < labs[root, MINC]:
                labs[root, MINC] = s
            if labs[root, STATUS] == OPEN:
                x = st[S_FREE_RUN]
                st[S_FREE_RUN] = runs[x, 3]
                st[S_RUNS_USED] += 1
                runs[x, 0] = r
                runs[x, 1] = s
                runs[x, 2] = e
                runs[x, 3] = -1
                if labs[root, RHEAD] == -1:
                    labs[root, RHEAD] = x
                else:
                    runs[labs[root, RTAIL], 3] = x
                labs[root, RTAIL] = x
        # objects of the previous row not continued in this one are complete
        _finish(labs, runs, st, prev, r, min_area, out, out_runs, done)
        # objects reaching max_height + 1 rows are cut here
        for k in range(ncur):
            root = _find(labs, cur[k, 2])
            if labs[root, STATUS] == OPEN and r - labs[root, FIRST] >= max_height:
                _output(labs, runs, st, root, 1, r, out, out_runs)
                labs[root, STATUS] = DEAD
        for k in range(ncur):
            prev[k, 0] = cur[k, 0]
            prev[k, 1] = cur[k, 1]
            prev[k, 2] = cur[k, 2]
        st[S_NPREV] = ncur
    return n_rows


@nb.njit(**_OPTS)
def paint_all(out, out_runs):
    """Masks of all output objects in one flat buffer: ``(flat, starts, heights, widths)``.

    Each mask spans its object's rows and the columns from its first to its
    last pixel (C order).
    """
    n = out.shape[0]
    heights = np.empty(n, dtype=np.int64)
    widths = np.empty(n, dtype=np.int64)
    starts = np.zeros(n + 1, dtype=np.int64)
    for i in range(n):
        maxc = 0
        for m in range(out[i, 5], out[i, 6]):
            maxc = max(maxc, out_runs[m, 2])
        heights[i] = out[i, 2] - out[i, 1] + 1
        widths[i] = maxc - out[i, 3]
        starts[i + 1] = starts[i] + heights[i] * widths[i]
    flat = np.zeros(starts[n], dtype=np.bool_)
    for i in range(n):
        top, left, w = out[i, 1], out[i, 3], widths[i]
        for m in range(out[i, 5], out[i, 6]):
            base = starts[i] + (out_runs[m, 0] - top) * w - left
            for c in range(out_runs[m, 1], out_runs[m, 2]):
                flat[base + c] = True
    return flat, starts, heights, widths


def new_pools(width: int, n_labels: int, n_runs: int) -> dict:
    """Empty pools: every label and run on its free list."""
    per_row = width // 2 + 1
    labs = np.zeros((n_labels, N_LAB_FIELDS), dtype=np.int64)
    labs[:, NEXT] = np.arange(1, n_labels + 1)
    labs[-1, NEXT] = -1
    runs = np.zeros((n_runs, 4), dtype=np.int64)
    runs[:, 3] = np.arange(1, n_runs + 1)
    runs[-1, 3] = -1
    st = np.zeros(N_STATE, dtype=np.int64)
    st[S_FREE_LAB] = 0
    st[S_FREE_RUN] = 0
    return {
        "st": st,
        "prev": np.zeros((per_row, 3), dtype=np.int64),
        "cur": np.zeros((per_row, 3), dtype=np.int64),
        "labs": labs,
        "runs": runs,
        "out": np.zeros((n_labels + per_row, N_OUT_FIELDS), dtype=np.int64),
        "out_runs": np.zeros((n_runs + per_row, 3), dtype=np.int64),
        "done": np.zeros(per_row, dtype=np.int64),
    }


def grow(pools: dict, width: int) -> None:
    """Double the label and run pools (and the output), keeping their content."""
    per_row = width // 2 + 1
    st = pools["st"]
    labs = pools["labs"]
    n = labs.shape[0]
    new = np.zeros((2 * n, N_LAB_FIELDS), dtype=np.int64)
    new[:n] = labs
    new[n:, NEXT] = np.arange(n + 1, 2 * n + 1)
    new[-1, NEXT] = st[S_FREE_LAB]
    st[S_FREE_LAB] = n
    pools["labs"] = new
    runs = pools["runs"]
    m = runs.shape[0]
    newr = np.zeros((2 * m, 4), dtype=np.int64)
    newr[:m] = runs
    newr[m:, 3] = np.arange(m + 1, 2 * m + 1)
    newr[-1, 3] = st[S_FREE_RUN]
    st[S_FREE_RUN] = m
    pools["runs"] = newr
    out = np.zeros((2 * n + per_row, N_OUT_FIELDS), dtype=np.int64)
    out[: pools["out"].shape[0]] = pools["out"]
    pools["out"] = out
    out_runs = np.zeros((2 * m + per_row, 3), dtype=np.int64)
    out_runs[: pools["out_runs"].shape[0]] = pools["out_runs"]
    pools["out_runs"] = out_runs


def compact_output(out: np.ndarray, out_runs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Output rows with only their own runs kept, one after the other (renumbered)."""
    counts = out[:, 6] - out[:, 5]
    starts = np.zeros(out.shape[0] + 1, dtype=np.int64)
    np.cumsum(counts, out=starts[1:])
    index = np.repeat(out[:, 5] - starts[:-1], counts) + np.arange(starts[-1])
    new = out.copy()
    new[:, 5] = starts[:-1]
    new[:, 6] = starts[1:]
    return new, out_runs[index]


plain_calls(globals())
