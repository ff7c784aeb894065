"""Confusion matrix of a classification: counts in the cells, integer colour bar."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._typing import ArrayLike
from .._validation import check_positive_int
from ._axes import axes_or_new

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_confusion_matrix"]


def plot_confusion_matrix(
    y_true: ArrayLike,
    y_pred: ArrayLike,
    ax: Axes | None = None,
    *,
    max_labels: int = 80,
) -> dict[str, Any]:
    """Counts of true (rows) against predicted (columns) classes.

    Parameters
    ----------
    y_true, y_pred : array_like of shape (n_samples,)
        Class labels of any type (compared as strings).
    ax : matplotlib Axes, optional
        A new figure's axes when None.
    max_labels : int, default=80
        With more classes than this, class names and the counts in the cells
        are left out (they would not be readable); the colour still shows them.

    Returns
    -------
    artists : dict
        ``"image"`` (AxesImage), ``"colorbar"``, ``"counts"`` (list of Text).

    Examples
    --------
    >>> art = plot_confusion_matrix(["a", "a", "b"], ["a", "b", "b"])
    >>> [t.get_text() for t in art["counts"]]
    ['1', '1', '1']
    """
    from matplotlib.ticker import MaxNLocator
    from sklearn.metrics import confusion_matrix

    max_labels = check_positive_int(max_labels, "max_labels", minimum=0)
    t = np.asarray(y_true).astype(str)
    p = np.asarray(y_pred).astype(str)
    labels = np.unique(np.concatenate([t, p]))
    cm = confusion_matrix(t, p, labels=labels)
    ax = axes_or_new(ax)
    image = ax.imshow(cm, cmap="Blues", vmin=0)
    colorbar = ax.figure.colorbar(image, ax=ax, shrink=0.8, label="count")
    colorbar.locator = MaxNLocator(integer=True)
    colorbar.update_ticks()
    counts = []
    n = len(labels)
    if n <= max_labels:
        size = max(6.0, min(10.0, 320.0 / n))
        ax.set_xticks(range(n), labels, rotation=45, ha="right", fontsize=size)
        ax.set_yticks(range(n), labels, fontsize=size)
        light = cm.max() / 2
        for (i, j), c in np.ndenumerate(cm):
            if c:
                counts.append(
                    ax.text(
                        j,
                        i,
                        str(c),
                        ha="center",
                        va="center",
                        fontsize=size,
                        color="white" if c > light else "black",
                    )
                )
    else:
        ax.set_xticks([])
        ax.set_yticks([])
    ax.set_xlabel("predicted class")
    ax.set_ylabel("true class")
    return {"image": image, "colorbar": colorbar, "counts": counts}
