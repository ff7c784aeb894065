"""Streaming line scanner: rows from the sensor in, one record per object out.

Each row is thresholded, cut into runs of object pixels and joined to the runs
of the row before (8-connected) by a union-find over run labels, in a compiled
kernel (:mod:`~tentaclass.scanner._segment`); this is the classic run-length
method of line-scan vision systems. An object is complete - and is emitted -
once a row arrives that holds none of its pixels; only then are its pixels
painted into a mask for classification and inspection. Memory holds only the
runs of the objects in flight, never the belt.

Rows are processed one after the other whatever the chunking, so results never
depend on it: an object is emitted in the call that receives the row after its
last row (objects numbered by ``(last_row, first column, first_row)``), one
row per call costs a few microseconds. An object taller than ``max_height`` is
cut when its ``max_height + 1``-th row arrives and reported, from the call
that receives the row after that, with a ``too_tall`` defect and no class; the
rest of it is skipped (also any object that later joins it).

Grey-level rows need a threshold (:mod:`~tentaclass.scanner.threshold`); what
is not given is chosen from the first ``calibration_rows`` rows, which are
held until then (bool rows and bytes are binary and need none).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any

import numpy as np

from .._validation import MAX_AXIS, check_positive_int, check_total
from ..errors import InputError
from . import _segment as seg
from .defects import DefectSettings
from .descriptors import MaskBatch, measure
from .inspection import NominalSize, _check_options, _placement, _record, inspect_masks
from .model import ScannerModel
from .records import Defect, Inspection, ScannedObject
from .threshold import Threshold, belt_levels, check_options, choose_threshold

__all__ = ["LineScanner"]

_KERNEL_DTYPES = (np.uint8, np.uint16, np.float32, np.float64)
_MODES = {"binary": 0, "fixed": 1, "adaptive": 2}


_NO_WORDS = np.zeros((0, 0), dtype=np.uint64)
_NO_WORDS.flags.writeable = False  # read-only as the rows' own words are (see _read_only)


def _read_only(rows: np.ndarray) -> np.ndarray:
    """``rows`` as a read-only array (a view, no copy).

    numba compiles a kernel once per argument type, and an array's type includes
    whether it can be written: passing every chunk read-only, whether the caller's
    array is writeable (a simulated belt, a camera's buffer) or not (rows read
    with :func:`numpy.frombuffer`, a read-only memory map), compiles the scanning
    kernel once per pixel type, not twice.
    """
    if rows.flags.writeable:
        rows = rows.view()
        rows.flags.writeable = False
    return rows


def _words(rows: np.ndarray) -> np.ndarray:
    """Binary rows of bytes as 64-bit words, for the kernel to skip empty stretches (if aligned)."""
    if (
        rows.dtype != np.uint8
        or rows.shape[1] % 8
        or rows.strides[1] != 1
        or rows.strides[0] % 8
        or rows.ctypes.data % 8
    ):
        return _NO_WORDS
    return rows.view(np.uint64)


class LineScanner:
    """Find, classify and inspect objects in rows streamed from a line sensor.

    Parameters
    ----------
    width : int
        Pixels per row, at most about 47 million (the scanner's buffers hold
        about 22 numbers per pixel of a row).
    model : ScannerModel, optional
        Classifier; default :func:`~tentaclass.scanner.default_model`.
    max_height : int, default=1024
        Tallest object expected, in rows. Taller objects are reported with a
        ``too_tall`` defect when they exceed it (not dropped), which bounds
        memory on a belt with, e.g., a long streak of material.
    min_area : int, default=1
        Objects with fewer pixels are ignored (not emitted, no id), e.g. the
        speckle of a noisy sensor; counted in ``n_ignored``. Objects reported
        ``too_tall`` are never ignored.
    threshold : "auto", "binary", "fixed", "adaptive" or float, default="auto"
        Which pixels are object (see :mod:`~tentaclass.scanner.threshold`):
        ``"binary"`` rows of 0/1; a number: a fixed grey level; ``"fixed"``
        or ``"adaptive"`` (a running belt level per column, for uneven
        illumination) with the level or contrast chosen from the data;
        ``"auto"``: binary for bool rows, bytes and rows of only 0 and 1,
        else fixed or adaptive as the first rows require.
    polarity : {"auto", "dark", "light"}, default="auto"
        Objects darker or lighter than the belt (binary: object where 0 or
        1); ``"auto"`` chooses from the first rows (binary: light).
    contrast : float, optional
        For grey rows: how far from the belt level an object pixel is at
        least (default chosen from the first rows).
    calibration_rows : int, default=64
        Grey rows held back to choose what is ``"auto"``, when needed.
    latency : int, default=0
        Rows an object may wait after its last row before it is emitted: rows
        fed in chunks of fewer rows are staged and run through the kernel
        ``latency`` at a time, and the objects completed meanwhile are
        measured and classified in one batch (much cheaper per row and per
        object when rows come one per call). 0: every row is processed when
        fed and an object is emitted in the call that receives the row after
        its last row.
    nominal_size, size_tolerance, settings
        As in :func:`~tentaclass.scanner.inspect`.

    Attributes
    ----------
    rows_seen : int
        Rows consumed so far (held calibration rows included).
    n_emitted : int
        Objects emitted so far.
    threshold_ : Threshold or None
        The rule in use, once chosen (it is reported by ``tentaclass scan``).

    Notes
    -----
    Objects are 8-connected: pixels touching at a corner belong to one object.
    Rows are numpy arrays (``(width,)`` for one row, ``(n_rows, width)`` for
    several) of bool, integers or floats, or ``bytes`` with one byte (0 or 1)
    per pixel; bytes may stop anywhere, even inside a row. A chunk holding a
    bad row (wrong width or rank, not numbers, NaN, not 0/1 in a binary
    stream) is refused as a whole with :class:`~tentaclass.errors.InputError`
    naming the row; the scanner is unchanged, objects already emitted stay
    emitted, and feeding may go on.

    Examples
    --------
    >>> import numpy as np
    >>> belt = np.zeros((12, 10), dtype=bool)
    >>> belt[1:4, 1:4] = True       # a 3 x 3 square
    >>> belt[2:9, 6:9] = True       # a 7 x 3 rectangle beside it
    >>> belt[5, 7] = False          # ... with a hole
    >>> scanner = LineScanner(10)
    >>> [(o.id, o.label, o.first_row, o.last_row) for o in scanner.feed(belt[:5])]
    [(0, 'square', 1, 3)]
    >>> [(o.id, o.label, o.accept, o.inspection.holes) for o in scanner.feed(belt[5:])]
    [(1, 'rectangle', False, 1)]
    >>> scanner.close()
    []

    Grey rows: a dark object on a belt lit unevenly from left to right.

    >>> grey = 150 + 5 * np.arange(10) + np.zeros((30, 1))
    >>> grey[:12][belt] = 30
    >>> scanner = LineScanner(10)
    >>> [o.label for o in scanner.scan(grey)]
    ['square', 'rectangle']
    >>> print(scanner.threshold_.describe())  # doctest: +NORMALIZE_WHITESPACE
    dark objects, below the belt level of each column by more than 80
    (adaptive threshold; belt 150 to 195)
    """

    def __init__(
        self,
        width: int,
        model: ScannerModel | None = None,
        *,
        max_height: int = 1024,
        min_area: int = 1,
        threshold: Any = "auto",
        polarity: str = "auto",
        contrast: float | None = None,
        calibration_rows: int = 64,
        latency: int = 0,
        nominal_size: NominalSize = None,
        size_tolerance: float = 0.1,
        settings: DefectSettings | None = None,
    ):
        self.width = check_positive_int(width, "width", maximum=MAX_AXIS)
        # the kernel's pools (below) hold about 22 int64 per pixel of a row
        per_row = self.width // 2 + 1
        pools = max(256, 2 * per_row) * seg.N_LAB_FIELDS + max(4096, 4 * per_row) * 4
        check_total(pools + 6 * per_row, f"the scanner's buffers for rows of {self.width:,} pixels")
        self.max_height = check_positive_int(max_height, "max_height")
        self.model, self.settings, self.size_tolerance = _check_options(
            model, settings, size_tolerance
        )
        self.min_area = check_positive_int(min_area, "min_area")
        check_options(threshold, polarity, contrast)
        self.threshold, self.polarity, self.contrast = threshold, polarity, contrast
        self.calibration_rows = check_positive_int(calibration_rows, "calibration_rows")
        self.latency = check_positive_int(latency, "latency", minimum=0)
        check_total(self.latency * self.width, "the rows held for the latency (latency x width)")
        # with a latency, rows fed one by one are staged and run through the
        # kernel a latency at a time: an object whose last row comes just after
        # a run waits the whole latency, and those of a stage go in one batch
        self._stage_rows = max(1, self.latency)
        self._stage: np.ndarray | None = None
        self._slots: list[Any] = []  # memoryviews of the stage's rows
        self._n_stage = 0
        self._fast_dtype: np.dtype | None = None
        self._row_shape = (self.width,)
        self._one_row = (1, self.width)
        self.nominal_size = nominal_size
        self.rows_seen = 0
        self.n_emitted = 0
        self.threshold_: Threshold | None = None
        self._held: list[np.ndarray] = []  # calibration rows
        self._n_held = 0
        # objects output by the kernel, not yet emitted: its output rows (kind, first
        # row, last row, first column, area, runs start, runs stop) and their runs
        self._pend = np.zeros((0, seg.N_OUT_FIELDS), dtype=np.int64)
        self._pend_runs = np.zeros((0, 3), dtype=np.int64)
        # room for the runs of two full rows in labels and four in runs: the kernel
        # needs a row's worth free before each row, and would otherwise stop to
        # grow the pools several times at the start of a wide belt
        self._pools = seg.new_pools(self.width, max(256, 2 * per_row), max(4096, 4 * per_row))
        self._bg = np.zeros(self.width, dtype=np.float64)
        self._rule: tuple = (0, False, 0.5, 0.5, 0.0)  # kernel arguments of threshold_
        self._done_rows = 0  # rows through the kernel
        self._partial = b""
        self._next_partial = b""
        self._closed = False
        if not isinstance(threshold, str) and polarity != "auto":
            self._resolve(None)
        elif threshold == "binary":
            self._resolve(None)

    # -- input -------------------------------------------------------------------------------
    def _bytes_rows(self, rows: bytes | bytearray | memoryview) -> np.ndarray:
        data = self._partial + bytes(rows)
        n = len(data) // self.width
        arr = np.frombuffer(data, dtype=np.uint8, count=n * self.width).reshape(n, self.width)
        if arr.size and arr.max() > 1:
            i, j = np.argwhere(arr > 1)[0]
            hint = (
                f" (the character {chr(arr[i, j])!r}: text rows? use --format text)"
                if arr[i, j] in (48, 49)
                else " (grey levels? feed them as an array, or use --dtype uint8)"
            )
            raise InputError(
                f"row {self.rows_seen + i}, column {j}: byte value {arr[i, j]}, "
                f"expected 0 or 1{hint}"
            )
        self._next_partial = data[n * self.width :]
        return arr

    def _array_rows(self, rows: Any) -> np.ndarray:
        """Validate one chunk of arrays into a kernel-ready (n, width) array."""
        arr: np.ndarray | None
        if isinstance(rows, np.ndarray) and rows.dtype.kind in "buif":
            arr = rows
        else:
            try:
                arr = np.asarray(rows)
            except (ValueError, TypeError):
                arr = None
            if arr is not None and arr.ndim == 0 and arr.dtype == object:
                raise InputError(
                    f"row {self.rows_seen}: rows must be an array of shape (width,) or "
                    f"(n_rows, width), or bytes, got {type(rows).__name__}"
                )
            if arr is None or arr.dtype == object:
                lens = []
                for r in rows:
                    try:
                        lens.append(len(np.atleast_1d(np.asarray(r, dtype=float))))
                    except (TypeError, ValueError):
                        lens.append(-1)
                bad = [k for k, n in enumerate(lens) if n != self.width]
                if bad:
                    i = bad[0]
                    what = "does not hold numbers" if lens[i] < 0 else f"has {lens[i]} pixels"
                    raise InputError(f"row {self.rows_seen + i} {what}, expected {self.width}")
                raise InputError(
                    f"row {self.rows_seen}: rows must hold numbers or bool, got Python objects"
                )
        if arr.ndim == 1:
            arr = arr[None, :]
        if arr.ndim != 2:
            raise InputError(
                f"rows must be one row (width,) or a chunk (n_rows, width), got shape {arr.shape}"
            )
        if arr.shape[1] != self.width:
            raise InputError(
                f"row {self.rows_seen} has {arr.shape[1]} pixels, expected {self.width}"
            )
        kind = arr.dtype.kind
        if kind == "b":
            return arr.view(np.uint8)
        if kind not in "iuf":
            raise InputError(f"rows must hold numbers or bool, got dtype {arr.dtype}")
        if kind == "f":
            finite = np.isfinite(arr)
            if not finite.all():
                i, j = np.argwhere(~finite)[0]
                value = arr[i, j].item()
                raise InputError(
                    f"row {self.rows_seen + i}, column {j}: value {value!r} is not finite"
                )
        t = self.threshold_
        if t is not None and t.mode == "binary":
            ok = (arr == 0) | (arr == 1)
            if not ok.all():
                i, j = np.argwhere(~ok)[0]
                raise InputError(
                    f"row {self.rows_seen + i}, column {j}: value {arr[i, j].item()!r}, "
                    "expected 0 or 1 (binary rows)"
                )
            return arr if arr.dtype == np.uint8 else arr.astype(np.uint8)
        if arr.dtype.type in _KERNEL_DTYPES:
            return arr
        if kind in "iu" and arr.size and arr.min() >= 0 and arr.max() <= 65535:
            return arr.astype(np.uint16)
        return arr.astype(np.float64)

    # -- processing --------------------------------------------------------------------------
    def feed(self, rows: Any) -> list[ScannedObject]:
        """Consume rows; return the objects completed by them.

        Parameters
        ----------
        rows : array_like of shape (width,) or (n_rows, width), or bytes
            The next rows of the belt, in order.

        Returns
        -------
        objects : list of ScannedObject
            Objects whose last row has passed, in id order.
        """
        if (
            type(rows) is np.ndarray
            and rows.dtype is self._fast_dtype
            and ((shape := rows.shape) == self._row_shape or shape == self._one_row)
            and not self._partial
        ):
            # one row of a type that needs no checks, to the stage (a camera's case)
            k = self._n_stage
            # (a copy of the same type and shape: no cast)
            self._slots[k][:] = rows if len(shape) == 1 else rows[0]
            self._n_stage = k = k + 1
            self.rows_seen += 1
            return self._drain() if k == self._stage_rows else []
        if self._closed:
            raise InputError("the scanner is closed: create a new one for a new stream")
        if isinstance(rows, bytes | bytearray | memoryview):
            arr = self._bytes_rows(rows)
            binary = True
        else:
            self._next_partial = self._partial
            if self._partial:
                raise InputError(
                    f"row {self.rows_seen} is incomplete ({len(self._partial)} of {self.width} "
                    "bytes); finish it with bytes before feeding arrays"
                )
            binary = isinstance(rows, np.ndarray) and rows.dtype == bool
            arr = self._array_rows(rows)
        self._partial = self._next_partial
        if arr.shape[0] == 0:
            return []
        if binary and self._n_held:
            raise InputError(
                f"row {self.rows_seen}: binary rows after {self._n_held} grey rows held to choose "
                "the threshold: feed one kind of rows per stream"
            )
        self.rows_seen += arr.shape[0]
        if self.threshold_ is None:
            if binary and self.threshold == "auto":
                self._resolve(None, binary=True)
            else:
                self._held.append(arr)
                self._n_held += arr.shape[0]
                if self._n_held < self.calibration_rows:
                    return []
                arr = self._release()
        if self.latency and (self._n_stage or arr.shape[0] < self._stage_rows):
            return self._staged(arr)
        return self._run(arr)

    def _staged(self, arr: np.ndarray) -> list[ScannedObject]:
        """Copy rows to the stage; run the kernel on it whenever it is full."""
        out = []
        if self._stage is None or self._stage.dtype != arr.dtype:
            out += self._drain()
            self._stage = np.empty((self._stage_rows, self.width), dtype=arr.dtype)
            # rows of this type go to the stage unchecked: bool for binary rows,
            # integers for grey ones (any value is valid, none is NaN)
            binary = self.threshold_ is not None and self.threshold_.mode == "binary"
            self._fast_dtype = (
                np.dtype(bool)
                if binary and arr.dtype == np.uint8
                else arr.dtype
                if not binary and arr.dtype in (np.uint8, np.uint16)
                else None
            )
            # the stage's rows as buffers of that type, one per slot (a buffer's
            # copy costs less than numpy's assignment; it takes any strides)
            fast = self._fast_dtype
            self._slots = [] if fast is None else [memoryview(r) for r in self._stage.view(fast)]
        i = 0
        while i < arr.shape[0]:
            k = min(arr.shape[0] - i, self._stage_rows - self._n_stage)
            self._stage[self._n_stage : self._n_stage + k] = arr[i : i + k]
            self._n_stage += k
            i += k
            if self._n_stage == self._stage_rows:
                out += self._drain()
        return out

    def _drain(self) -> list[ScannedObject]:
        """Run the staged rows through the kernel."""
        if not self._n_stage or self._stage is None:
            return []
        rows, self._n_stage = self._stage[: self._n_stage], 0
        return self._run(rows)

    def _release(self) -> np.ndarray:
        """The rows held for calibration, with the threshold now chosen from them."""
        held = self._held
        arr = held[0] if len(held) == 1 else np.concatenate(held)
        if arr.dtype.type not in _KERNEL_DTYPES:
            arr = arr.astype(np.float64)
        self._held, self._n_held = [], 0
        self._resolve(arr[: self.calibration_rows])  # the same rows for any chunking
        return arr

    def _resolve(self, sample: np.ndarray | None, binary: bool = False) -> None:
        """Fix the threshold rule, from ``sample`` rows for what is "auto"."""
        if sample is None:
            if binary or self.threshold == "binary":
                pol = "light" if self.polarity == "auto" else self.polarity
                t = Threshold("binary", pol, 0.5, 0.5, (0.0, 0.0))
            else:
                level = float(self.threshold)
                t = Threshold("fixed", self.polarity, level, 0.0, (level, level))
        else:
            t = choose_threshold(sample, self.threshold, self.polarity, self.contrast)
            if t.mode == "adaptive":
                self._bg[:] = belt_levels(sample, t.polarity, t.contrast)
        self.threshold_ = t
        self._rule = (_MODES[t.mode], t.polarity == "dark", t.level, t.contrast, t.rate)

    def flush(self) -> list[ScannedObject]:
        """Process the rows held for calibration now; return the objects complete so far.

        The threshold is then chosen from fewer rows than ``calibration_rows``,
        and objects waiting for their ``latency`` are emitted. Useful when a
        stream stops early (e.g. on bad input) to report what was complete
        before.

        Examples
        --------
        >>> import numpy as np
        >>> grey = np.full((6, 5), 200, dtype=np.uint8)
        >>> grey[1:4, 1:4] = 10
        >>> scanner = LineScanner(5)
        >>> scanner.feed(grey), [o.label for o in scanner.flush()]
        ([], ['square'])
        """
        if self._closed:
            return []
        out = self._run(self._release()) if self._held else []
        out += self._drain()
        return out + self._emit(final=False)

    def close(self) -> list[ScannedObject]:
        """End the stream: emit the objects still open at its last row.

        Raises
        ------
        InputError
            If no row was fed at all (an empty stream), or the bytes fed end
            inside a row (a truncated stream); the scanner stays open then.
        """
        if self._closed:
            return []
        if self._partial:
            raise InputError(
                f"truncated stream: row {self.rows_seen} has only {len(self._partial)} of "
                f"{self.width} bytes"
            )
        if self.rows_seen == 0:
            raise InputError("empty stream: no rows were fed")
        out = self._run(self._release()) if self._held else []
        out += self._drain()
        out += self._run(None)
        self._closed = True
        self._fast_dtype = None
        ignored = self.n_ignored
        self._pools = seg.new_pools(self.width, 1, 1)  # free the pools
        self._pools["st"][seg.S_IGNORED] = ignored
        return out

    def scan(self, chunks: Iterable[Any]) -> Iterator[ScannedObject]:
        """Feed every chunk, then close; yield the objects as they complete.

        Examples
        --------
        >>> import numpy as np
        >>> belt = np.zeros((6, 5), dtype=int)
        >>> belt[1:4, 1:4] = 1
        >>> [o.label for o in LineScanner(5).scan(belt)]  # one row at a time
        ['square']
        """
        for chunk in chunks:
            yield from self.feed(chunk)
        yield from self.close()

    @property
    def n_ignored(self) -> int:
        """Objects ignored as smaller than ``min_area``."""
        return int(self._pools["st"][seg.S_IGNORED])

    @property
    def pending_rows(self) -> int:
        """Rows spanned by the objects in flight (plus rows held for calibration)."""
        labs = self._pools["labs"]
        idx = np.arange(labs.shape[0])
        live = (labs[:, seg.PARENT] == idx) & (labs[:, seg.STATUS] == seg.OPEN)
        live &= labs[:, seg.RHEAD] != -1
        first = labs[live, seg.FIRST]
        waiting = self._n_held + self._n_stage
        return (self._done_rows - int(first.min()) if first.size else 0) + waiting

    def _run(self, arr: np.ndarray | None) -> list[ScannedObject]:
        """Push rows (None: the end of the stream) through the kernel; build the records."""
        p = self._pools
        final = arr is None
        if arr is None:
            arr = np.zeros((0, self.width), dtype=np.uint8)
        mode, dark, level, contrast, rate = self._rule
        if mode == 0 and dark:
            arr = (arr == 0).view(np.uint8)
            dark = False
        # C order, read-only: the kernel is compiled for one kind of rows per pixel type
        arr = _read_only(np.ascontiguousarray(arr))
        words = _words(arr) if mode == 0 else _NO_WORDS
        start, n = 0, arr.shape[0]
        kept: list[tuple[np.ndarray, np.ndarray]] = []  # the objects output, added at the end
        while True:
            rows = arr[start:] if start else arr
            done = seg.scan_rows(
                rows, words[start:] if start else words, self._done_rows, mode, dark,
                level, contrast, rate, self._bg, self.max_height, self.min_area, final,
                p["st"], p["prev"], p["cur"], p["labs"], p["runs"], p["out"], p["out_runs"],
                p["done"],
            )  # fmt: skip
            self._done_rows += done
            start += done
            st = p["st"]
            if st[seg.S_NOUT]:
                n_out, n_runs = int(st[seg.S_NOUT]), int(st[seg.S_NOUT_RUNS])
                kept.append((p["out"][:n_out].copy(), p["out_runs"][:n_runs].copy()))
                st[seg.S_NOUT] = 0
                st[seg.S_NOUT_RUNS] = 0
            elif not final and start < n:
                seg.grow(p, self.width)
                p = self._pools
            if final or start >= n:
                break
        if kept:
            self._keep(kept)
        return self._emit(final) if self._pend.shape[0] else []

    def _keep(self, kept: list[tuple[np.ndarray, np.ndarray]]) -> None:
        """Add the objects the kernel output (rows and their runs, per call) to those pending."""
        outs = [self._pend]
        at = self._pend_runs.shape[0]
        for new, runs in kept:
            new[:, 5:7] += at  # the runs' places among all pending runs
            at += runs.shape[0]
            outs.append(new)
        self._pend = np.concatenate(outs)
        self._pend_runs = np.concatenate([self._pend_runs, *(runs for _, runs in kept)])

    def _emit(self, final: bool) -> list[ScannedObject]:
        """Records of the pending objects that may go: all at the end of the stream.

        Too-tall objects cut at the newest row wait for the next row, so that ids
        (by last row) never depend on where a chunk ends.
        """
        pend = self._pend
        go = np.ones(pend.shape[0], dtype=bool)
        if not final:
            go = pend[:, 2] < self._done_rows - 1
            if not go.any():
                return []
        out = pend[go]
        out = out[np.lexsort((out[:, 1], out[:, 3], out[:, 2]))]  # by last row, column, first
        runs = self._pend_runs
        if go.all():
            self._pend = pend[:0]
            self._pend_runs = runs[:0]
        else:
            self._pend, self._pend_runs = seg.compact_output(pend[~go], runs)
        whole = out[:, 0] == 0
        inspections: list[Inspection] = []
        if whole.any():
            done = out[whole]
            batch = MaskBatch(*seg.paint_all(done, runs))
            # The belt's side edges cut objects; along the belt, only the stream's start does.
            belt = np.array([0.0, 0.0, np.inf, float(self.width)])
            scanned = None
            if self.nominal_size is None and whole.all():  # the records in one pass
                scanned = (self.n_emitted, out[:, 1].tolist(), out[:, 2].tolist())
            records = inspect_masks(
                None, done[:, [1, 3]], self.model, self.settings, self.nominal_size,
                self.size_tolerance, np.tile(belt, (done.shape[0], 1)), single=True, flat=batch,
                scanned=scanned,
            )  # fmt: skip
            if scanned is not None:
                self.n_emitted += len(records)
                return records
            inspections = records
        if not whole.all():
            cut = out[~whole]
            flat, starts, heights, widths = seg.paint_all(cut, runs)
            tall = iter(
                [
                    self._too_tall(flat[a:b].reshape(h, w), top, left)
                    for a, b, h, w, top, left in zip(
                        starts[:-1].tolist(),
                        starts[1:].tolist(),
                        heights.tolist(),
                        widths.tolist(),
                        cut[:, 1].tolist(),
                        cut[:, 3].tolist(),
                        strict=True,
                    )
                ]
            )
            inspected = iter(inspections)
            inspections = [next(inspected) if w else next(tall) for w in whole.tolist()]
        records = []
        i = self.n_emitted
        new = object.__new__
        for insp, first, last in zip(
            inspections, out[:, 1].tolist(), out[:, 2].tolist(), strict=True
        ):
            r = new(ScannedObject)  # new_scanned(...), without a call per object
            r.__dict__.update({"id": i, "first_row": first, "last_row": last, "inspection": insp})
            records.append(r)
            i += 1
        self.n_emitted = i
        return records

    def _too_tall(self, mask: np.ndarray, top: int, left: int) -> Inspection:
        """Record of an object cut at ``max_height + 1`` rows (no class, rejected)."""
        # Crop the columns: the cut part may be narrower than the component's box.
        cols = np.nonzero(mask.any(axis=0))[0]
        mask = mask[:, cols[0] : cols[-1] + 1]
        left += int(cols[0])
        bbox, centroid = _placement(mask, top, left)
        note = f"taller than max_height={self.max_height} rows: cut at row {bbox[2] - 1}"
        d = Defect("too_tall", 0, bbox, centroid, 0.0, note)
        g = measure(mask)
        return _record(None, 0.0, bbox, g.area, centroid, g.orientation, g.length, g.width, [d])
