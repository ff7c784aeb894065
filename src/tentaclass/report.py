"""Classification results as a table of columns, ready for JSON or pandas."""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from .errors import InputError

__all__ = ["classification_table", "table_records", "table_to_json"]


def classification_table(
    labels: np.ndarray, proba: np.ndarray, classes: np.ndarray
) -> dict[str, np.ndarray]:
    """Per-array results as a dict of equal-length columns.

    Parameters
    ----------
    labels : ndarray of shape (n_samples,)
        Predicted labels (may include a rejection label).
    proba : ndarray of shape (n_samples, n_classes)
        Class probabilities, columns in the order of ``classes``.
    classes : ndarray of shape (n_classes,)

    Returns
    -------
    table : dict of str -> ndarray of shape (n_samples,)
        ``index``, ``label``, ``probability`` (of the most probable class) and
        one ``p_<class>`` column per class. Empty inputs give empty columns of
        the right dtypes.

    Examples
    --------
    >>> import numpy as np
    >>> t = classification_table(np.array(["a"]), np.array([[0.9, 0.1]]), np.array(["a", "b"]))
    >>> sorted(t), t["probability"].tolist()
    (['index', 'label', 'p_a', 'p_b', 'probability'], [0.9])
    """
    proba = np.asarray(proba, dtype=np.float64)
    n, k = len(labels), len(classes)
    if proba.shape != (n, k) and not (proba.size == 0 and n * k == 0):
        raise InputError(
            f"proba must have shape (n_samples, n_classes) = ({n}, {k}) for {n} labels and "
            f"{k} classes, got shape {proba.shape}"
        )
    proba = proba.reshape(n, k)
    table: dict[str, np.ndarray] = {
        "index": np.arange(len(labels)),
        "label": np.asarray(labels).astype(str),
        "probability": proba.max(axis=1) if len(labels) else np.zeros(0),
    }
    for j, c in enumerate(classes):
        table[f"p_{c}"] = proba[:, j]
    return table


def table_records(table: dict[str, np.ndarray]) -> list[dict[str, Any]]:
    """Rows of a column table as plain-Python dicts (JSON-serialisable)."""
    n = len(next(iter(table.values()))) if table else 0
    return [{k: np.asarray(v)[i].item() for k, v in table.items()} for i in range(n)]


def table_to_json(table: dict[str, np.ndarray], **kwargs: Any) -> str:
    """A column table as a JSON list of row objects."""
    return json.dumps(table_records(table), **kwargs)
