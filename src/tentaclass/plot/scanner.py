"""Figures: one inspected object, and the belt with boxes, labels and defect marks.

matplotlib is imported only when a function here is called; functions draw on
``ax`` (a new figure's axes when None), return the artists and never call
``plt.show()``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._validation import as_belt_image, as_binary_grid, as_list_of, check_positive_int
from ..errors import InputError
from ..scanner import (
    Inspection,
    ScannedObject,
    ScannerModel,
    crop,
    expected_outline,
    inspect,
    measure,
)
from ._axes import axes_or_new

__all__ = ["DEFECT_COLORS", "plot_belt", "plot_inspection", "save_belt_figure"]

DEFECT_COLORS: dict[str, str] = {
    "hole": "tab:red",
    "bite": "tab:orange",
    "broken_corner": "tab:orange",
    "truncated": "tab:purple",
    "burr": "tab:pink",
    "size": "tab:brown",
    "broken": "tab:purple",
    "too_tall": "tab:gray",
}
"""Colour of each defect kind's marks."""


def plot_inspection(
    grid: Any,
    result: Inspection | None = None,
    *,
    model: ScannerModel | None = None,
    ax: Any = None,
    **imshow_kwargs: Any,
) -> dict[str, Any]:
    """Draw an object with its outline, the outline expected for its class and its defects.

    Parameters
    ----------
    grid : array_like of shape (rows, cols)
        The object's binary grid.
    result : Inspection, optional
        From :func:`~tentaclass.scanner.inspect` on ``grid``; computed if None.
    model : ScannerModel, optional
        Used when ``result`` is None.
    ax : matplotlib Axes, optional
        Where to draw; a new figure if None.
    **imshow_kwargs
        Passed to ``ax.imshow`` (default a grey colour map).

    Returns
    -------
    artists : dict
        ``image`` (AxesImage), ``expected`` (Line2D of the expected outline),
        ``defects`` (list of Rectangle patches), ``labels`` (list of Text).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from tentaclass.datasets import thesis_scanner
    >>> art = plot_inspection(thesis_scanner().test_grids[0])
    >>> len(art["defects"]), art["labels"][0].get_text()
    (1, 'hole 2 px')
    """
    from matplotlib.patches import Rectangle

    arr = as_binary_grid(grid, "grid")
    if arr.ndim != 2:
        raise InputError(f"grid must be 2-D, got shape {arr.shape}")
    if result is None:
        result = inspect(arr, model)
    ax = axes_or_new(ax)
    kw = {"cmap": "Greys", "vmin": 0, "vmax": 1.6, "interpolation": "nearest"}
    kw.update(imshow_kwargs)
    image = ax.imshow(arr, **kw)
    mask, top, left = crop(arr)
    outline = expected_outline(measure(mask), result.label)
    expected = None
    if outline.geom_type == "Polygon":
        # drawn through the pixel edges, not the pixel centres it is fitted to
        outline = outline.buffer(0.5, join_style="mitre")
        xy = np.asarray(outline.exterior.coords)
        (expected,) = ax.plot(
            xy[:, 0] + left,
            xy[:, 1] + top,
            "--",
            color="tab:blue",
            lw=1.5,
            label=f"expected {result.label}",
        )
    patches, labels = [], []
    for d in result.defects:
        r0, c0, r1, c1 = d.bbox
        color = DEFECT_COLORS.get(d.kind, "tab:red")
        patch = Rectangle((c0 - 0.5, r0 - 0.5), c1 - c0, r1 - r0, fill=False, ec=color, lw=2)
        ax.add_patch(patch)
        patches.append(patch)
        text = f"{d.kind.replace('_', ' ')} {d.area} px" if d.area else d.kind
        labels.append(
            ax.text(c1 - 0.3, r0 - 0.6, text, color=color, fontsize=8, va="bottom", ha="left")
        )
    verdict = "ACCEPT" if result.accept else "REJECT"
    ax.set_title(f"{result.label} ({result.confidence:.2f}) - {verdict}")
    ax.set_xticks([])
    ax.set_yticks([])
    return {"image": image, "expected": expected, "defects": patches, "labels": labels}


def plot_belt(
    image: Any,
    objects: Sequence[ScannedObject],
    *,
    ax: Any = None,
    **imshow_kwargs: Any,
) -> dict[str, Any]:
    """Draw a belt image with each object's box, id, class and defect marks.

    Accepted objects are boxed in green, rejected ones in red; defects are
    marked with a cross at their centre in the colour of their kind
    (:data:`DEFECT_COLORS`).

    Parameters
    ----------
    image : array_like of shape (n_rows, width)
        The belt (rows top to bottom, as they passed the sensor): binary
        (objects black) or grey levels, drawn as they are (darkest black).
    objects : sequence of ScannedObject
        Records from a :class:`~tentaclass.scanner.LineScanner` on that belt.
    ax : matplotlib Axes, optional
        Where to draw; a new figure if None.
    **imshow_kwargs
        Passed to ``ax.imshow``.

    Returns
    -------
    artists : dict
        ``image``, ``boxes`` (Rectangles), ``labels`` (Texts), ``marks`` (PathCollection
        of the defect crosses, or None).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from tentaclass.scanner import LineScanner
    >>> from tentaclass.scanner.simulate import make_belt
    >>> belt = make_belt(4, width=64, random_state=0)
    >>> objs = list(LineScanner(64).scan([belt.image]))
    >>> art = plot_belt(belt.image, objs)
    >>> len(art["boxes"]) == len(objs) == 4
    True
    """
    from matplotlib.patches import Rectangle

    img = as_belt_image(image, "image")
    objects = as_list_of(objects, "objects", ScannedObject)
    ax = axes_or_new(ax)
    if img.dtype == bool:
        kw = {"cmap": "Greys", "vmin": 0, "vmax": 1.6, "interpolation": "nearest"}
    else:  # grey levels as the camera saw them
        low, high = float(img.min()), float(img.max())
        kw = {"cmap": "gray", "vmin": low, "vmax": max(high, low + 1), "interpolation": "nearest"}
    kw.update(imshow_kwargs)
    art = ax.imshow(img, **kw)
    boxes, labels, pts, colors = [], [], [], []
    for obj in objects:
        r0, c0, r1, c1 = obj.bbox
        color = "tab:green" if obj.accept else "tab:red"
        rect = Rectangle((c0 - 1, r0 - 1), c1 - c0 + 1, r1 - r0 + 1, fill=False, ec=color, lw=1.2)
        ax.add_patch(rect)
        boxes.append(rect)
        labels.append(
            ax.text(
                c1 + 1,
                r0,
                f"{obj.id} {obj.label or '?'}",
                color=color,
                fontsize=7,
                va="top",
                ha="left",
            )
        )
        for d in obj.defects:
            if d.kind in ("size", "too_tall", "broken"):
                continue
            pts.append(d.centroid)
            colors.append(DEFECT_COLORS.get(d.kind, "tab:red"))
    marks = None
    if pts:
        p = np.asarray(pts)
        marks = ax.scatter(p[:, 1], p[:, 0], marker="x", c=colors, s=30, linewidths=1.5)
    ax.set_xlabel("column (pixels across the belt)")
    ax.set_ylabel("row (time)")
    return {"image": art, "boxes": boxes, "labels": labels, "marks": marks}


#: Matplotlib's image renderer (Agg) draws fewer than 2**16 pixels along each side.
_MAX_FIGURE_PIXELS = 2**16


def save_belt_figure(
    image: Any, objects: Sequence[ScannedObject], path: str | Path, *, dpi: int = 100
) -> None:
    """Draw :func:`plot_belt` on a figure sized to the belt and save it (PNG, ...)."""
    from matplotlib.figure import Figure

    img = as_belt_image(image, "image")
    h, w = img.shape
    dpi = check_positive_int(dpi, "dpi")
    objects = as_list_of(objects, "objects", ScannedObject)
    scale = min(1.0, 2400.0 / max(h, w)) * 3 / dpi
    size = (max(4.0, w * scale + 1.5), max(3.0, h * scale + 1.0))
    pixels = max(size) * dpi
    if pixels >= _MAX_FIGURE_PIXELS:
        raise InputError(
            f"dpi {dpi:,} would make a figure {pixels:,.0f} pixels across, more than the "
            f"{_MAX_FIGURE_PIXELS:,} matplotlib draws: use a smaller dpi"
        )
    fig = Figure(figsize=size)
    ax = fig.add_subplot()
    plot_belt(img, objects, ax=ax)
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
