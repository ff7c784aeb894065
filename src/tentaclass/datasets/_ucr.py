"""Outline time series from the UCR archive that aeon ships (optional ``bench`` extra)."""

from __future__ import annotations

import numpy as np
from sklearn.utils import Bunch

from ..errors import InputError

#: Shape-outline data sets that aeon ships inside its package (no download).
UCR_SHAPES = ("ArrowHead", "OSULeaf")


def ucr_shapes(name: str) -> Bunch:
    """A UCR shape-outline data set with its official train/test split.

    The series are centroid-distance profiles of outlines (arrow heads,
    leaves), not joint angles: they show how the classifiers fare on other
    one-dimensional shape signatures.

    Parameters
    ----------
    name : {"ArrowHead", "OSULeaf"}

    Returns
    -------
    data : Bunch
        ``data`` (n_samples, n_timepoints) float, ``target`` (n_samples,) str,
        ``split`` (n_samples,) ``"train"`` or ``"test"``.

    Raises
    ------
    InputError
        Unknown name, or aeon is not installed (``pip install 'tentaclass[bench]'``).
    """
    if name not in UCR_SHAPES:
        raise InputError(f"unknown UCR data set {name!r}; choose from {', '.join(UCR_SHAPES)}")
    try:
        from aeon.datasets import load_classification
    except ImportError as exc:
        raise InputError(
            f"the UCR data set {name!r} needs aeon: pip install 'tentaclass[bench]'"
        ) from exc
    parts = []
    for split in ("train", "test"):
        X, y = load_classification(name, split=split)
        parts.append((np.asarray(X, dtype=np.float64)[:, 0, :], np.asarray(y).astype(str), split))
    return Bunch(
        data=np.concatenate([p[0] for p in parts]),
        target=np.concatenate([p[1] for p in parts]),
        split=np.concatenate([np.full(len(p[1]), p[2]) for p in parts]),
        DESCR=f"UCR {name}, official split, from the copy aeon ships.",
    )
