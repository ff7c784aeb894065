"""Outline time series from the UCR archive that aeon ships (optional ``bench`` extra)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from sklearn.utils import Bunch

from .._lazy import import_extra
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
    aeon = import_extra(
        "aeon.datasets", "bench", f"the UCR data set {name!r} needs aeon", error=InputError
    )
    parts = []
    for split in ("train", "test"):
        X, y = aeon.load_classification(name, split=split)
        parts.append((np.asarray(X, dtype=np.float64)[:, 0, :], np.asarray(y).astype(str), split))
    return _split_bunch(parts, f"UCR {name}, official split, from the copy aeon ships.")


def _split_bunch(parts: list, descr: str) -> Bunch:
    """One Bunch of ``(data, target, split name)`` parts, train first."""
    return Bunch(
        data=np.concatenate([q[0] for q in parts]),
        target=np.concatenate([q[1] for q in parts]),
        split=np.concatenate([np.full(len(q[1]), q[2]) for q in parts]),
        DESCR=descr,
    )


def _read_tsv(path: Path) -> tuple[np.ndarray, np.ndarray]:
    rows = [line.rstrip("\n").split("\t") for line in path.read_text().splitlines() if line.strip()]
    if not rows:
        raise InputError(f"{path}: no series in the file")
    _same_lengths(path, [len(r) - 1 for r in rows])
    labels = np.array([r[0].strip() for r in rows])
    try:
        data = np.array([[float(v) for v in r[1:]] for r in rows])
    except ValueError as exc:
        raise InputError(f"{path}: a value is not a number ({exc})") from None
    return data, labels


def _read_ts(path: Path) -> tuple[np.ndarray, np.ndarray]:
    data, labels, in_data = [], [], False
    for line in path.read_text().splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        if line.lower().startswith("@data"):
            in_data = True
            continue
        if line.startswith("@"):
            if line.lower().startswith("@univariate") and line.split()[-1].lower() == "false":
                raise InputError(f"{path}: multivariate .ts files are not supported")
            continue
        if in_data:
            *dims, label = line.split(":")
            if len(dims) != 1:
                raise InputError(f"{path}: multivariate .ts files are not supported")
            try:
                data.append([float(v) for v in dims[0].split(",")])
            except ValueError as exc:
                raise InputError(f"{path}: a value is not a number ({exc})") from None
            labels.append(label.strip())
    if not data:
        raise InputError(f"{path}: no @data section with series")
    _same_lengths(path, [len(r) for r in data])
    return np.array(data), np.array(labels)


def _same_lengths(path: Path, lengths: list[int]) -> None:
    """Refuse a file whose series differ in length (this reader does not resample)."""
    seen = sorted(set(lengths))
    if len(seen) != 1:
        raise InputError(f"{path}: series of different lengths ({seen[:5]} values)")


def load_ucr(path: str | os.PathLike, name: str | None = None) -> Bunch:
    r"""A UCR / UEA univariate data set from disk, with its official split.

    Parameters
    ----------
    path : path-like
        The archive's folder (holding ``NAME/NAME_TRAIN.tsv``), the data set's
        own folder, or one ``_TRAIN`` file; ``.tsv`` (UCR 2018: label, then
        the values, tab-separated) and ``.ts`` (sktime / aeon) are read.
    name : str, optional
        The data set (``"ArrowHead"``); default: the folder's or file's name.

    Returns
    -------
    data : Bunch
        ``data`` (n_samples, n_timepoints) float, ``target`` (n_samples,) str,
        ``split`` (n_samples,) ``"train"`` or ``"test"``.

    Raises
    ------
    InputError
        No such data set, a file in another format, values that are not
        numbers or NaN, series of different lengths.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp()) / "Toy"
    >>> d.mkdir()
    >>> _ = (d / "Toy_TRAIN.tsv").write_text("1\t0\t1\t2\n2\t2\t1\t0\n")
    >>> _ = (d / "Toy_TEST.tsv").write_text("1\t0\t1\t3\n")
    >>> b = load_ucr(d)
    >>> b.data.shape, b.target.tolist(), b.split.tolist()
    ((3, 3), ['1', '2', '1'], ['train', 'train', 'test'])
    """
    p = Path(path)
    if p.is_file():
        stem = p.stem.rsplit("_", 1)[0]
        folder, name = p.parent, name or stem
    elif p.is_dir():
        if name and (p / name).is_dir():
            folder = p / name
        else:
            folder, name = p, name or p.name
    else:
        raise InputError(f"{path}: no such file or folder")
    parts = []
    for split in ("train", "test"):
        for ext, reader in ((".tsv", _read_tsv), (".ts", _read_ts)):
            f = folder / f"{name}_{split.upper()}{ext}"
            if f.is_file():
                X, y = reader(f)
                break
        else:
            raise InputError(
                f"{folder}: no {name}_{split.upper()}.tsv or .ts file (UCR / UEA format)"
            )
        if not np.all(np.isfinite(X)):
            raise InputError(f"{f}: {int(np.sum(~np.isfinite(X)))} NaN or infinite value(s)")
        parts.append((X, y, split))
    if parts[0][0].shape[1] != parts[1][0].shape[1]:
        raise InputError(
            f"{name}: train and test series differ in length "
            f"({parts[0][0].shape[1]} and {parts[1][0].shape[1]})"
        )
    return _split_bunch(parts, f"{name} from {folder}, official train/test split.")
