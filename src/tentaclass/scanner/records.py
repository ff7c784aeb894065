"""Frozen result records of the scanner, with ``to_dict()`` for JSON.

Coordinates are ``(row, col)`` in pixels; boxes are half-open
``(row0, col0, row1, col1)`` (numpy slicing: ``grid[row0:row1, col0:col1]``).
For :func:`~tentaclass.scanner.inspect` they refer to the grid given; for
:class:`~tentaclass.scanner.LineScanner` rows count lines from the start of
the stream and columns pixels across the belt.
"""

from __future__ import annotations

import functools
import gc
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from typing import Any, ParamSpec, TypeVar

_P = ParamSpec("_P")
_R = TypeVar("_R")

__all__ = ["DEFECT_KINDS", "Defect", "Inspection", "ScannedObject"]

DEFECT_KINDS: tuple[str, ...] = (
    "hole",
    "bite",
    "broken_corner",
    "truncated",
    "burr",
    "size",
    "broken",
    "too_tall",
)
"""Kinds of defect: ``hole`` (enclosed gap), missing material (``bite`` at an
edge, ``broken_corner`` at a vertex of the expected outline, ``truncated``: a
large part missing or cut off at the grid's edge), extra material (``burr``),
``size`` (out of tolerance against a nominal size), ``broken`` (the grid
holds several separate pieces) and ``too_tall`` (object
taller than a :class:`~tentaclass.scanner.LineScanner`'s ``max_height``)."""


def _moved(record: Any, drow: int, dcol: int, **changes: Any) -> Any:
    """``record`` (with ``bbox`` and ``centroid``) moved by ``(drow, dcol)``, and ``changes``."""
    r0, c0, r1, c1 = record.bbox
    return replace(
        record,
        bbox=(r0 + drow, c0 + dcol, r1 + drow, c1 + dcol),
        centroid=(record.centroid[0] + drow, record.centroid[1] + dcol),
        **changes,
    )


@dataclass(frozen=True)
class Defect:
    """One defect of an object.

    Attributes
    ----------
    kind : str
        One of :data:`DEFECT_KINDS`.
    area : int
        Pixels missing (hole, bite, broken corner, truncated) or extra (burr);
        0 for ``size`` and ``too_tall``.
    bbox : tuple of 4 ints
        Half-open ``(row0, col0, row1, col1)`` box of the defect's pixels.
    centroid : tuple of 2 floats
        ``(row, col)`` centre of the defect's pixels.
    depth : float
        How far the defect reaches into (or out of) the expected outline, in
        pixels; for ``size`` the relative deviation from the nominal size.
    note : str
        A human-readable description.
    """

    kind: str
    area: int
    bbox: tuple[int, int, int, int]
    centroid: tuple[float, float]
    depth: float = 0.0
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        """Plain dict of built-in types (lists for tuples), ready for :func:`json.dumps`."""
        d = asdict(self)
        d["bbox"] = list(self.bbox)
        d["centroid"] = list(self.centroid)
        return d

    def shifted(self, drow: int, dcol: int) -> Defect:
        """The same defect with its coordinates moved by ``(drow, dcol)``."""
        return _moved(self, drow, dcol)


@dataclass(frozen=True)
class Inspection:
    """Everything :func:`~tentaclass.scanner.inspect` found out about one object.

    Attributes
    ----------
    label : str or None
        Class of the object; None if it could not be classified (empty grid
        region, or an object reported ``too_tall``).
    confidence : float
        Posterior probability of ``label`` from the model, in [0, 1].
    bbox : tuple of 4 ints
        Half-open ``(row0, col0, row1, col1)`` box of the object's pixels.
    area : int
        Object pixels (holes not counted).
    centroid : tuple of 2 floats
        ``(row, col)`` mean of the object's pixel centres.
    orientation : float
        Direction of the long side of the minimum rotated rectangle, degrees in
        [0, 180) counter-clockwise from the column axis as seen on the image.
    length, width : float
        Long and short sides of that rectangle (pixels; a circle's diameter).
    holes : int
        Number of holes (also listed in ``defects``).
    hole_area : int
        Pixels in all holes.
    defects : tuple of Defect
        Defects found, largest first within each kind.
    accept : bool
        True when no defect was found.
    reasons : tuple of str
        Why the object was rejected (empty when accepted).
    """

    label: str | None
    confidence: float
    bbox: tuple[int, int, int, int]
    area: int
    centroid: tuple[float, float]
    orientation: float
    length: float
    width: float
    holes: int
    hole_area: int
    defects: tuple[Defect, ...]
    accept: bool
    reasons: tuple[str, ...]

    def to_dict(self) -> dict[str, Any]:
        """Plain dict of built-in types, ready for :func:`json.dumps`.

        Examples
        --------
        >>> import json
        >>> from tentaclass.scanner import inspect
        >>> r = inspect([[1, 1], [1, 1]])
        >>> json.loads(json.dumps(r.to_dict()))["label"]
        'square'
        """
        d = asdict(self)
        d["bbox"] = list(self.bbox)
        d["centroid"] = list(self.centroid)
        d["defects"] = [x.to_dict() for x in self.defects]
        d["reasons"] = list(self.reasons)
        return d

    def shifted(self, drow: int, dcol: int) -> Inspection:
        """The same record with all coordinates moved by ``(drow, dcol)``."""
        return _moved(self, drow, dcol, defects=tuple(x.shifted(drow, dcol) for x in self.defects))


@dataclass(frozen=True)
class ScannedObject:
    """One object found on the belt by a :class:`~tentaclass.scanner.LineScanner`.

    Attributes
    ----------
    id : int
        0, 1, 2, ... in the order objects are emitted: by last row, then by
        first column.
    first_row, last_row : int
        First and last line (counted from 0 at the start of the stream) that
        hold pixels of the object; ``last_row`` is inclusive.
    inspection : Inspection
        Class, measures and defects, in belt coordinates.
    """

    id: int
    first_row: int
    last_row: int
    inspection: Inspection

    @property
    def label(self) -> str | None:
        """Class of the object (None if not classified)."""
        return self.inspection.label

    @property
    def confidence(self) -> float:
        """Posterior probability of :attr:`label`."""
        return self.inspection.confidence

    @property
    def bbox(self) -> tuple[int, int, int, int]:
        """Half-open ``(row0, col0, row1, col1)`` box on the belt."""
        return self.inspection.bbox

    @property
    def area(self) -> int:
        """Object pixels."""
        return self.inspection.area

    @property
    def defects(self) -> tuple[Defect, ...]:
        """Defects found."""
        return self.inspection.defects

    @property
    def accept(self) -> bool:
        """True when no defect was found."""
        return self.inspection.accept

    def to_dict(self) -> dict[str, Any]:
        """Flat dict: ``id``, ``first_row``, ``last_row`` then the inspection's fields."""
        return {
            "id": self.id,
            "first_row": self.first_row,
            "last_row": self.last_row,
            **self.inspection.to_dict(),
        }


# Constructors of the records without checks, for the thousands of objects per second
# of a belt: each fills the instance's __dict__ at once instead of field by field
# through the frozen dataclass's __setattr__ (the same instance as the class gives;
# tests compare them).
_new = object.__new__


def new_defect(
    kind: str,
    area: int,
    bbox: tuple[int, int, int, int],
    centroid: tuple[float, float],
    depth: float,
    note: str,
) -> Defect:
    """``Defect(kind, area, bbox, centroid, depth, note)``, built faster."""
    obj = _new(Defect)
    obj.__dict__.update(
        {"kind": kind, "area": area, "bbox": bbox, "centroid": centroid, "depth": depth,
         "note": note}
    )  # fmt: skip
    return obj


def new_inspection(
    label: str | None,
    confidence: float,
    bbox: tuple[int, int, int, int],
    area: int,
    centroid: tuple[float, float],
    orientation: float,
    length: float,
    width: float,
    holes: int,
    hole_area: int,
    defects: tuple[Defect, ...],
    accept: bool,
    reasons: tuple[str, ...],
) -> Inspection:
    """``Inspection(...)`` with the fields in order, built faster."""
    obj = _new(Inspection)
    obj.__dict__.update(
        {"label": label, "confidence": confidence, "bbox": bbox, "area": area,
         "centroid": centroid, "orientation": orientation, "length": length, "width": width,
         "holes": holes, "hole_area": hole_area, "defects": defects, "accept": accept,
         "reasons": reasons}
    )  # fmt: skip
    return obj


def new_scanned(id: int, first_row: int, last_row: int, inspection: Inspection) -> ScannedObject:
    """``ScannedObject(id, first_row, last_row, inspection)``, built faster."""
    obj = _new(ScannedObject)
    obj.__dict__.update(
        {"id": id, "first_row": first_row, "last_row": last_row, "inspection": inspection}
    )
    return obj


def collector_paused(func: Callable[_P, _R]) -> Callable[_P, _R]:
    """``func`` run with Python's cyclic garbage collector paused (if it was on).

    A batch of thousands of records allocates tens of thousands of objects,
    none of them in a reference cycle; the collector would go over them
    several times while they are built (and over all older objects at times).
    Paused, it goes over them once, at its next run after the batch.
    """

    @functools.wraps(func)
    def paused(*args: _P.args, **kwargs: _P.kwargs) -> _R:
        if not gc.isenabled():
            return func(*args, **kwargs)
        gc.disable()
        try:
            return func(*args, **kwargs)
        finally:
            gc.enable()

    return paused
