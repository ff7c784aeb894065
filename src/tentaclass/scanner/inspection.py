"""Inspect one object: class, position, size, defects and the accept/reject decision."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from scipy import ndimage

from .._validation import as_binary_grid_2d, as_grid_list, check_positive_float
from ..errors import InputError
from ..features.fourier import _one_blas_thread
from ._rounding import rounded
from .defects import (
    REASON,
    DefectSettings,
    defect_arrays,
    defect_fields,
    defect_records,
    shape_codes,
)
from .descriptors import Geometry, MaskBatch, flatten_masks, measure_batch_arrays
from .model import _ONE_THREAD_MIN_ROWS, ScannerModel, crop, default_model
from .records import Defect, Inspection, ScannedObject, collector_paused, new_inspection

__all__ = ["NominalSize", "inspect", "inspect_many"]

NominalSize = float | tuple[float, float] | Mapping[str, Any] | str | None
"""A nominal size: a length, a ``(length, width)`` pair, a mapping from class
to either, or ``"learned"`` (the model's per-class median training size)."""


def _nominal_for(
    nominal_size: NominalSize, label: str | None, model: ScannerModel
) -> tuple[float, float | None] | None:
    """``(length, width or None)`` the object of class ``label`` should have."""
    if nominal_size is None or label is None:
        return None
    if isinstance(nominal_size, str):
        if nominal_size != "learned":
            raise InputError(
                f"nominal_size must be a number, a pair, a mapping or 'learned', "
                f"got {nominal_size!r}"
            )
        return model.nominal_sizes().get(label)
    value = nominal_size
    if isinstance(nominal_size, Mapping):
        if label not in nominal_size:
            return None
        value = nominal_size[label]
    if isinstance(value, Sequence) and not isinstance(value, str):
        if len(value) != 2:
            raise InputError(f"a nominal size pair must be (length, width), got {value!r}")
        return (
            check_positive_float(value[0], "nominal length"),
            check_positive_float(value[1], "nominal width"),
        )
    return (check_positive_float(value, "nominal_size"), None)


def _size_defect(
    g: Geometry,
    nominal: tuple[float, float | None],
    tolerance: float,
    bbox: tuple[int, int, int, int],
    centroid: tuple[float, float],
) -> Defect | None:
    length, width = nominal
    dev = g.length / length - 1.0
    note = f"length {g.length:.1f} px, nominal {length:.1f} px"
    if width is not None:
        dw = g.width / width - 1.0
        if abs(dw) > abs(dev):
            dev, note = dw, f"width {g.width:.1f} px, nominal {width:.1f} px"
    if abs(dev) <= tolerance + 1e-12:
        return None
    word = "smaller" if dev < 0 else "larger"
    return Defect(
        "size",
        0,
        bbox,
        centroid,
        round(float(dev), 4),
        f"{note}: {abs(dev):.0%} {word} (tolerance {tolerance:.0%})",
    )


def _reason(d: Defect) -> str:
    r, c = d.centroid
    if d.kind in ("size", "too_tall", "broken"):
        return d.note
    return REASON.format(d.kind.replace("_", " "), r, c, d.note)


def _assemble(
    g: Geometry,
    defects: list[Defect],
    centroid: tuple[float, float],
    label: str | None,
    confidence: float,
    top: int,
    left: int,
    model: ScannerModel,
    nominal_size: NominalSize,
    size_tolerance: float,
    single: bool = False,
) -> Inspection:
    """Record of a measured, classified object cropped at (top, left), with its defects.

    ``defects`` are in grid coordinates, ``centroid`` (the mean pixel centre)
    in mask coordinates.
    """
    bbox = (top, left, top + g.mask.shape[0], left + g.mask.shape[1])
    centroid = (round(centroid[0] + top, 6), round(centroid[1] + left, 6))
    nominal = None if nominal_size is None else _nominal_for(nominal_size, label, model)
    if nominal is not None:
        d = _size_defect(g, nominal, size_tolerance, bbox, centroid)
        if d is not None:
            defects.append(d)
    n_pieces = 1 if single else ndimage.label(g.mask, np.ones((3, 3), dtype=bool))[1]
    if n_pieces > 1:
        defects.insert(
            0, Defect("broken", 0, bbox, centroid, 0.0, f"object in {n_pieces} separate pieces")
        )
    return _record(
        label, confidence, bbox, g.area, centroid, g.orientation, g.length, g.width, defects
    )


def _placement(
    mask: np.ndarray, top: int, left: int
) -> tuple[tuple[int, int, int, int], tuple[float, float]]:
    """Bounding box and centroid on the belt of an object's mask cropped at (top, left)."""
    rr, cc = np.nonzero(mask)
    bbox = (top, left, top + mask.shape[0], left + mask.shape[1])
    return bbox, (round(float(rr.mean()) + top, 6), round(float(cc.mean()) + left, 6))


def _record(
    label: str | None,
    confidence: float,
    bbox: tuple[int, int, int, int],
    area: int,
    centroid: tuple[float, float],
    orientation: float,
    length: float,
    width: float,
    defects: list[Defect],
) -> Inspection:
    """The inspection record of a measured object; accepted when it has no defect."""
    holes, hole_area, found, reasons = _defect_fields(defects)
    return new_inspection(
        label,
        round(confidence, 6),
        bbox,
        area,
        centroid,
        orientation,
        length,
        width,
        holes,
        hole_area,
        found,
        not defects,
        reasons,
    )


def _defect_fields(
    defects: list[Defect],
) -> tuple[int, int, tuple[Defect, ...], tuple[str, ...]]:
    """Holes, their area, the defects and the reasons of a record."""
    holes = [d.area for d in defects if d.kind == "hole"]
    return len(holes), int(sum(holes)), tuple(defects), tuple(map(_reason, defects))


def _check_options(
    model: ScannerModel | None, settings: DefectSettings | None, size_tolerance: float
) -> tuple[ScannerModel, DefectSettings, float]:
    if model is None:
        model = default_model()
    elif not isinstance(model, ScannerModel):
        raise InputError(f"model must be a ScannerModel, got {type(model).__name__}")
    if settings is None:
        settings = DefectSettings()
    elif not isinstance(settings, DefectSettings):
        raise InputError(f"settings must be a DefectSettings, got {type(settings).__name__}")
    tol = check_positive_float(size_tolerance, "size_tolerance", allow_zero=True)
    return model, settings, tol


@collector_paused
def inspect_masks(
    masks: Sequence[np.ndarray] | None,
    offsets: Sequence[tuple[int, int]] | np.ndarray,
    model: ScannerModel,
    settings: DefectSettings,
    nominal_size: NominalSize = None,
    size_tolerance: float = 0.1,
    extents: Sequence[tuple[float, float, float, float] | None] | np.ndarray | None = None,
    single: bool = False,
    flat: MaskBatch | None = None,
    scanned: tuple[int, list[int], list[int]] | None = None,
) -> list[Any]:
    """Inspect validated, cropped object masks in one batch (one classifier call).

    Private kernel of :func:`inspect_many` and the line scanner; ``offsets``
    are the ``(row, col)`` of each mask's top-left pixel (pairs or an
    ``(n, 2)`` array), ``extents`` the ``(row0, col0, row1, col1)`` of each
    grid (or the belt) in the same coordinates as the offsets (or an ``(n,
    4)`` array); ``single`` says each mask is known to be one 8-connected
    piece; ``flat``: the masks already in flat buffers (``masks`` are views of
    it, or None: its views); ``scanned``: the first id and the first and last
    rows of the objects of a line scanner, whose records (ScannedObject) are
    then returned (with ``single`` and no ``nominal_size``).
    """
    n = len(offsets)
    if not n:
        return []
    off = np.asarray(offsets, dtype=np.int64).reshape(n, 2)
    tops, lefts = off[:, 0].tolist(), off[:, 1].tolist()
    batch = flat if flat is not None else flatten_masks(masks or [])
    m = measure_batch_arrays(batch)
    if n >= _ONE_THREAD_MIN_ROWS:
        # thin products (features, the classifier's distances): BLAS threads only
        # cost here (ten times over on a busy machine)
        with _one_blas_thread():
            proba = model.predict_features_proba(model._batch_features(m))
    else:  # too small for BLAS to start its threads
        proba = model.predict_features_proba(model._batch_features(m))
    best = np.argmax(proba, axis=1)
    names = [str(x) for x in model.classes_.tolist()]
    labels = [names[k] for k in best.tolist()]
    confidence = proba[np.arange(n), best]
    # the grid (or belt) in each mask's coordinates
    if isinstance(extents, np.ndarray):
        ext = extents.astype(float).reshape(n, 4)
    else:
        ext = np.array(
            [(-np.inf, -np.inf, np.inf, np.inf) if e is None else e for e in extents]
            if extents is not None
            else [(-np.inf, -np.inf, np.inf, np.inf)] * n,
            dtype=float,
        ).reshape(n, 4)
    ints, floats = defect_arrays(
        m.batch, m.area, m.width, m.length, labels, settings, ext - np.tile(off, 2),
        (m.centres, m.centre_starts), shape_codes(names)[best],
    )  # fmt: skip
    if nominal_size is not None or not single:
        found = defect_records(ints, floats, tops, lefts)
        defects = [found.get(i, []) for i in range(n)]
        centroids = (m.sums / m.area[:, None]).tolist()
        geoms = m.geometries()
        if masks is not None:
            for g, mask in zip(geoms, masks, strict=True):
                g.__dict__["mask"] = mask
        return [
            _assemble(g, d, c, label, p, top, left, model, nominal_size, size_tolerance, single)
            for g, d, c, label, p, top, left in zip(
                geoms, defects, centroids, labels, confidence.tolist(), tops, lefts, strict=True
            )
        ]
    # the same records as _assemble gives, built in one pass: the numbers of all
    # objects at once (rounded as Python rounds), one Python object per record
    bottoms = (off[:, 0] + batch.heights).tolist()
    rights = (off[:, 1] + batch.widths).tolist()
    boxes = list(zip(tops, lefts, bottoms, rights, strict=True))
    rows = rounded(m.sums[:, 0] / m.area + off[:, 0], 6).tolist()
    cols = rounded(m.sums[:, 1] / m.area + off[:, 1], 6).tolist()
    centroids = list(zip(rows, cols, strict=True))
    fields: list[tuple[int, int, tuple[Defect, ...], tuple[str, ...]]] = [(0, 0, (), ())] * n
    for i, f in defect_fields(ints, floats, tops, lefts).items():
        fields[i] = f
    out: list[Any] = []
    new = object.__new__
    columns = (
        labels, rounded(confidence, 6).tolist(), boxes, m.area.tolist(), centroids,
        m.orientation.tolist(), m.length.tolist(), m.width.tolist(), fields,
    )  # fmt: skip
    if scanned is not None:  # the scanner's records too, in the same pass
        i = scanned[0]
        for first, last, label, p, box, area, centroid, angle, long, short, (
            holes, hole_area, listed, why,
        ) in zip(scanned[1], scanned[2], *columns, strict=True):  # fmt: skip
            r = new(Inspection)
            r.__dict__.update(
                {"label": label, "confidence": p, "bbox": box, "area": area,
                 "centroid": centroid, "orientation": angle, "length": long, "width": short,
                 "holes": holes, "hole_area": hole_area, "defects": listed,
                 "accept": not listed, "reasons": why}
            )  # fmt: skip
            o = new(ScannedObject)
            o.__dict__.update({"id": i, "first_row": first, "last_row": last, "inspection": r})
            out.append(o)
            i += 1
        return out
    for label, p, box, area, centroid, angle, long, short, (holes, hole_area, listed, why) in zip(
        *columns, strict=True
    ):
        r = new(Inspection)  # new_inspection(...), without a call per object
        r.__dict__.update(
            {"label": label, "confidence": p, "bbox": box, "area": area, "centroid": centroid,
             "orientation": angle, "length": long, "width": short, "holes": holes,
             "hole_area": hole_area, "defects": listed, "accept": not listed, "reasons": why}
        )  # fmt: skip
        out.append(r)
    return out


def inspect(
    grid: Any,
    model: ScannerModel | None = None,
    *,
    nominal_size: NominalSize = None,
    size_tolerance: float = 0.1,
    settings: DefectSettings | None = None,
) -> Inspection:
    """Classify one object's binary grid, measure it and look for defects.

    Parameters
    ----------
    grid : array_like of shape (rows, cols)
        Binary grid (bool or 0/1) holding one object; any size. Recognition
        does not depend on where the object lies, its rotation or its size.
    model : ScannerModel, optional
        Classifier; default :func:`default_model` (the thesis's four classes).
    nominal_size : float, (float, float), mapping or "learned", optional
        Makes size matter: the object's length (and width, if a pair is given)
        must be within ``size_tolerance`` of this, else it gets a ``size``
        defect. A mapping gives a size per class (classes not in it are not
        checked); ``"learned"`` uses the model's median training size per class.
    size_tolerance : float, default=0.1
        Allowed relative deviation from ``nominal_size``.
    settings : DefectSettings, optional
        Defect thresholds.

    Returns
    -------
    result : Inspection
        Frozen record; ``result.to_dict()`` is JSON-ready.

    Notes
    -----
    Objects are 8-connected. If the grid holds several separate pieces they are
    inspected as one object with an extra ``broken`` defect.

    Examples
    --------
    The thesis's square with a hole (its network answered "triangle"):

    >>> r = inspect([[1, 1, 1, 1, 1],
    ...              [1, 1, 0, 1, 1],
    ...              [1, 1, 0, 1, 1],
    ...              [1, 1, 1, 1, 1],
    ...              [1, 1, 1, 1, 1]])
    >>> r.label, r.holes, r.hole_area, r.accept
    ('square', 1, 2, False)
    >>> r.reasons
    ('hole at (1.5, 2.0): hole of 2 px',)

    A 3 x 3 block is a (smaller) square, rejected only when size matters:

    >>> block = [[0, 0, 0, 0, 0], [0, 1, 1, 1, 0], [0, 1, 1, 1, 0], [0, 1, 1, 1, 0],
    ...          [0, 0, 0, 0, 0]]
    >>> inspect(block).accept, inspect(block).length
    (True, 3.0)
    >>> inspect(block, nominal_size=5).reasons
    ('length 3.0 px, nominal 5.0 px: 40% smaller (tolerance 10%)',)
    """
    model, settings, tol = _check_options(model, settings, size_tolerance)
    arr = as_binary_grid_2d(grid)
    if not arr.any():
        raise InputError("grid holds no object pixels")
    mask, top, left = crop(arr)
    extent = (0.0, 0.0, float(arr.shape[0]), float(arr.shape[1]))
    return inspect_masks([mask], [(top, left)], model, settings, nominal_size, tol, [extent])[0]


def inspect_many(
    grids: Any,
    model: ScannerModel | None = None,
    *,
    nominal_size: NominalSize = None,
    size_tolerance: float = 0.1,
    settings: DefectSettings | None = None,
) -> list[Inspection]:
    """:func:`inspect` for several grids, classified in one batch.

    Parameters
    ----------
    grids : sequence of 2-D binary arrays or array of shape (n_grids, rows, cols)
        One object per grid; sizes may differ.
    model, nominal_size, size_tolerance, settings
        As in :func:`inspect`.

    Returns
    -------
    results : list of Inspection

    Examples
    --------
    >>> from tentaclass.datasets import thesis_scanner
    >>> [r.label for r in inspect_many(thesis_scanner().grids[::4])]
    ['square', 'circle', 'triangle', 'rectangle']
    """
    model, settings, tol = _check_options(model, settings, size_tolerance)
    arrs = as_grid_list(grids)
    crops = [crop(g) for g in arrs]
    extents = [(0.0, 0.0, float(g.shape[0]), float(g.shape[1])) for g in arrs]
    return inspect_masks(
        [c[0] for c in crops],
        [(c[1], c[2]) for c in crops],
        model,
        settings,
        nominal_size,
        tol,
        extents,
    )
