"""Streaming line scanner: rows from the sensor in, one record per object out.

Each :meth:`LineScanner.feed` call labels the rows still needed (those of
objects not yet complete) together with the new rows, with
:func:`scipy.ndimage.label` (8-connected), and stitches across chunk
boundaries by keeping, between calls, only the pixels of objects that touch
the newest row. An object is complete - and is emitted - once a row arrives
that holds none of its pixels. So memory is bounded by the tallest object (at
most ``max_height`` rows) plus one chunk, not by the belt's length.

Results do not depend on how the rows are chunked: an object is emitted in the
call that receives the row after its last row, and objects are numbered by
``(last_row, first column, first_row)``, whether rows come one at a time or as
a whole image. An object taller than ``max_height`` is cut when its
``max_height + 1``-th row arrives: it is reported then, with a ``too_tall``
defect and no class, and the rest of it is skipped (also any object that later
joins it). The cut happens at that row for every chunking too: a chunk is
split there before processing.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any

import numpy as np
from scipy import ndimage

from .._validation import check_positive_int
from ..errors import InputError
from .defects import DefectSettings
from .descriptors import measure
from .inspection import NominalSize, _check_options, inspect_masks
from .model import ScannerModel
from .records import Defect, Inspection, ScannedObject

__all__ = ["LineScanner"]

_EIGHT = np.ones((3, 3), dtype=bool)


class LineScanner:
    """Find, classify and inspect objects in rows streamed from a line sensor.

    Parameters
    ----------
    width : int
        Pixels per row.
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
    nominal_size, size_tolerance, settings
        As in :func:`~tentaclass.scanner.inspect`.

    Attributes
    ----------
    rows_seen : int
        Rows consumed so far.
    n_emitted : int
        Objects emitted so far.
    n_ignored : int
        Objects ignored as smaller than ``min_area``.

    Notes
    -----
    Objects are 8-connected: pixels touching at a corner belong to one object.
    Rows are numpy arrays (``(width,)`` for one row, ``(n_rows, width)`` for
    several) of bool or 0/1 numbers, or ``bytes`` with one byte (0 or 1) per
    pixel; bytes may stop anywhere, even inside a row. A chunk holding a bad
    row is refused as a whole with :class:`~tentaclass.errors.InputError`
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
    """

    def __init__(
        self,
        width: int,
        model: ScannerModel | None = None,
        *,
        max_height: int = 1024,
        min_area: int = 1,
        nominal_size: NominalSize = None,
        size_tolerance: float = 0.1,
        settings: DefectSettings | None = None,
    ):
        self.width = check_positive_int(width, "width")
        self.max_height = check_positive_int(max_height, "max_height")
        self.model, self.settings, self.size_tolerance = _check_options(
            model, settings, size_tolerance
        )
        self.min_area = check_positive_int(min_area, "min_area")
        self.nominal_size = nominal_size
        self.rows_seen = 0
        self.n_emitted = 0
        self.n_ignored = 0
        self._buf = np.zeros((0, self.width), dtype=bool)
        self._dead = np.zeros((0, self.width), dtype=bool)
        self._partial = b""
        self._next_partial = b""
        self._closed = False

    # -- input -------------------------------------------------------------------------------
    def _rows_from(self, rows: Any) -> np.ndarray:
        """Validate one chunk into a bool array of shape (n, width)."""
        if isinstance(rows, bytes | bytearray | memoryview):
            data = self._partial + bytes(rows)
            n = len(data) // self.width
            arr = np.frombuffer(data[: n * self.width], dtype=np.uint8).reshape(n, self.width)
            bad = arr > 1
            if bad.any():
                i, j = np.argwhere(bad)[0]
                hint = (
                    f" (the character {chr(arr[i, j])!r}: text rows? use --format text)"
                    if arr[i, j] in (48, 49)
                    else ""
                )
                raise InputError(
                    f"row {self.rows_seen + i}, column {j}: byte value {arr[i, j]}, "
                    f"expected 0 or 1{hint}"
                )
            self._next_partial = data[n * self.width :]
            return arr.astype(bool)
        self._next_partial = self._partial
        if self._partial:
            raise InputError(
                f"row {self.rows_seen} is incomplete ({len(self._partial)} of {self.width} "
                "bytes); finish it with bytes before feeding arrays"
            )
        try:
            arr = np.asarray(rows)
        except ValueError:
            arr = None
        if arr is None or arr.dtype == object:
            lens = [len(np.atleast_1d(r)) for r in rows]
            i = next(k for k, n in enumerate(lens) if n != self.width)
            raise InputError(
                f"row {self.rows_seen + i} has {lens[i]} pixels, expected {self.width}"
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
        if arr.dtype == bool:
            return arr
        if not np.issubdtype(arr.dtype, np.number):
            raise InputError(f"rows must hold 0/1 or bool values, got dtype {arr.dtype}")
        ok = (arr == 0) | (arr == 1)
        if not ok.all():
            i, j = np.argwhere(~ok)[0]
            raise InputError(
                f"row {self.rows_seen + i}, column {j}: value {arr[i, j].item()!r}, expected 0 or 1"
            )
        return arr.astype(bool)

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
        if self._closed:
            raise InputError("the scanner is closed: create a new one for a new stream")
        new = self._rows_from(rows)
        self._partial = self._next_partial
        return self._consume(new, final=False)

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
        out = self._consume(np.zeros((0, self.width), dtype=bool), final=True)
        self._closed = True
        self._buf = self._dead = np.zeros((0, self.width), dtype=bool)
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
    def pending_rows(self) -> int:
        """Rows held in memory for objects not yet complete."""
        return self._buf.shape[0]

    def _label(self, new: np.ndarray) -> tuple:
        """Label the kept rows plus ``new``, skipping runs of empty rows.

        Objects cannot span an empty row, so all but the first row of each run
        of empty rows is dropped before labelling (kept: the last row, which
        decides what is still open). On a quiet belt this skips most of the
        image. Returns the buffer height, the labels of the kept rows, their
        row numbers in the buffer, per object the (labels slice, first row,
        stop row) and the labels of already reported (dead) objects.
        """
        buf = np.concatenate([self._buf, new]) if self._buf.size else new
        h = buf.shape[0]
        busy = buf.any(axis=1)
        keep = busy.copy()
        keep[1:] |= busy[:-1]
        keep[-1] = True
        rows = np.flatnonzero(keep)
        sub = buf[rows] if rows.size < h else buf
        lab, _ = ndimage.label(sub, _EIGHT)
        objs = [
            (sl, int(rows[sl[0].start]), int(rows[sl[0].stop - 1]) + 1)
            for sl in ndimage.find_objects(lab)
        ]
        dead_labels: set[int] = set()
        if self._dead.any():
            # Dead pixels only ever sit in the last kept row of the previous call.
            r = int(np.searchsorted(rows, self._dead.shape[0] - 1))
            dead_labels = set(np.unique(lab[r][self._dead[-1]]).tolist())
        return h, lab, rows, objs, dead_labels

    def _first_live_row(self, labelled: tuple, k: int) -> int | None:
        """First buffer row of object ``k``'s pixels that are not already reported."""
        _, lab, rows, objs, dead_labels = labelled
        sl, r0, _ = objs[k - 1]
        if k not in dead_labels:
            return r0
        part = lab[sl] == k
        r = int(np.searchsorted(rows, self._dead.shape[0] - 1)) - sl[0].start
        if 0 <= r < part.shape[0]:
            part[r] &= ~self._dead[-1][sl[1]]
        live = np.flatnonzero(part.any(axis=1))
        return int(rows[sl[0].start + live[0]]) if live.size else None

    def _consume(self, new: np.ndarray, final: bool) -> list[ScannedObject]:
        out: list[ScannedObject] = []
        while self._buf.shape[0] + new.shape[0] > 0:
            old = self._buf.shape[0]
            labelled = self._label(new)
            h, objs = labelled[0], labelled[3]
            # Split at the first row where 1-row-at-a-time feeding could cut a tall
            # object: its first not yet reported row + max_height. Splitting more
            # often than needed is harmless; missing a cut is not (an object may
            # join an already reported one below the cut and vanish with it).
            cut = h - 1
            for k, (_, r0, r1) in enumerate(objs, 1):
                if r1 - r0 > self.max_height:
                    first = self._first_live_row(labelled, k)
                    if first is not None and r1 - first > self.max_height:
                        cut = min(cut, first + self.max_height)
            if cut < h - 1:
                take = cut + 1 - old
                self.rows_seen += take
                out += self._step(self._label(new[:take]), final=False)
                new = new[take:]
                continue
            self.rows_seen += new.shape[0]
            out += self._step(labelled, final)
            break
        return out

    def _step(self, labelled: tuple, final: bool) -> list[ScannedObject]:
        """Emit the complete objects of a labelled buffer and keep the open ones."""
        h, lab, rows, objs, dead_set = labelled
        # rows_seen already counts every row of the buffer; its row 0 is global row `base`.
        base = self.rows_seen - h
        done, tall, keep_live, keep_dead = [], [], [], []
        for k, (sl, r0, r1) in enumerate(objs, 1):
            is_open = r1 == h and not final
            if k in dead_set:
                if is_open:
                    keep_dead.append(k)
                continue
            if r1 - r0 > self.max_height:
                tall.append((k, sl, r0))
                if is_open:
                    keep_dead.append(k)
            elif is_open:
                keep_live.append(k)
            else:
                done.append((k, sl, r0))
        records = self._records(lab, done, tall, base)
        # Keep the rows of the open objects; of dead (already reported) ones only the last row.
        start = min((objs[k - 1][1] for k in keep_live), default=h - 1)
        self._buf = np.zeros((h - start, self.width), dtype=bool)
        first = int(np.searchsorted(rows, start))
        if keep_live:
            self._buf[rows[first:] - start] = np.isin(lab[first:], keep_live)
        self._dead = np.zeros_like(self._buf)
        if keep_dead:
            self._dead[-1] = np.isin(lab[-1], keep_dead)
            self._buf[-1] |= self._dead[-1]
        return records

    def _records(self, lab: np.ndarray, done: list, tall: list, base: int) -> list[ScannedObject]:
        items = []  # (sort key, kind, label, slice of lab, first row in the buffer)
        for kind, group in (("done", done), ("tall", tall)):
            for k, sl, r0 in group:
                n = sl[0].stop - sl[0].start
                if kind == "tall":
                    n = min(n, self.max_height + 1)
                    sl = (slice(sl[0].start, sl[0].start + n), sl[1])
                items.append(((base + r0 + n - 1, sl[1].start, base + r0), kind, k, sl, r0))
        items.sort(key=lambda t: t[0])
        # The belt's side edges cut objects; along the belt, only the stream's start does.
        belt = (0.0, 0.0, np.inf, float(self.width))
        masks, offsets, kept = [], [], []
        for item in items:
            _, kind, k, sl, r0 = item
            if kind == "done":
                mask = lab[sl] == k
                if np.count_nonzero(mask) < self.min_area:
                    self.n_ignored += 1
                    continue
                masks.append(mask)
                offsets.append((base + r0, sl[1].start))
            kept.append(item)
        results = iter(
            inspect_masks(
                masks,
                offsets,
                self.model,
                self.settings,
                self.nominal_size,
                self.size_tolerance,
                [belt] * len(masks),
                single=True,
            )
        )
        out = []
        for (last, _, first), kind, k, sl, r0 in kept:
            if kind == "done":
                insp = next(results)
            else:
                insp = self._too_tall(lab[sl] == k, base + r0, sl[1].start)
            out.append(ScannedObject(self.n_emitted, first, last, insp))
            self.n_emitted += 1
        return out

    def _too_tall(self, mask: np.ndarray, top: int, left: int) -> Inspection:
        """Record of an object cut at ``max_height + 1`` rows (no class, rejected)."""
        # Crop the columns: the cut part may be narrower than the component's box.
        cols = np.nonzero(mask.any(axis=0))[0]
        mask = mask[:, cols[0] : cols[-1] + 1]
        left += int(cols[0])
        g = measure(mask)
        rr, cc = np.nonzero(mask)
        bbox = (top, left, top + mask.shape[0], left + mask.shape[1])
        centroid = (round(float(rr.mean()) + top, 6), round(float(cc.mean()) + left, 6))
        note = f"taller than max_height={self.max_height} rows: cut at row {bbox[2] - 1}"
        d = Defect("too_tall", 0, bbox, centroid, 0.0, note)
        return Inspection(
            label=None,
            confidence=0.0,
            bbox=bbox,
            area=g.area,
            centroid=centroid,
            orientation=g.orientation,
            length=g.length,
            width=g.width,
            holes=0,
            hole_area=0,
            defects=(d,),
            accept=False,
            reasons=(note,),
        )
