"""Outline time series from the UCR archive that aeon ships (optional ``bench`` extra)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from sklearn.utils import Bunch

from .._lazy import import_extra
from .._validation import as_path
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


def _text(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a UTF-8 text file (UCR .tsv or UEA .ts)") from None


def _series(path: Path, k: int, label: str, values: list[str]) -> list[float]:
    """One series of the file's line ``k``: a class label and at least one number."""
    if not label.strip():
        raise InputError(f"{path}: line {k} has no class label")
    if not values or values == [""]:
        raise InputError(f"{path}: line {k} holds a label and no values")
    try:
        return [float(v) for v in values]
    except ValueError as exc:
        raise InputError(f"{path}: line {k}: a value is not a number ({exc})") from None


def _read_tsv(path: Path) -> tuple[np.ndarray, np.ndarray]:
    lines = enumerate(_text(path).splitlines(), start=1)
    rows = [(k, line.split("\t")) for k, line in lines if line.strip()]
    if not rows:
        raise InputError(f"{path}: no series in the file")
    if all(len(r) == 1 for _, r in rows):
        raise InputError(
            f"{path}: no tab on any line: UCR .tsv files hold the label, then the values, "
            "separated by tabs"
        )
    data = [_series(path, k, r[0], r[1:]) for k, r in rows]
    _same_lengths(path, [len(r) for r in data])
    return np.array(data), np.array([r[0].strip() for _, r in rows])


def _read_ts(path: Path) -> tuple[np.ndarray, np.ndarray]:
    data, labels, in_data = [], [], False
    for k, line in enumerate(_text(path).splitlines(), start=1):
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
            if ":" not in line:
                raise InputError(f"{path}: line {k} has no ':' before a class label")
            *dims, label = line.split(":")
            if len(dims) != 1:
                raise InputError(f"{path}: multivariate .ts files are not supported")
            data.append(_series(path, k, label, dims[0].split(",")))
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
    p = as_path(path)
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
