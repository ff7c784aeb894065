"""``tentaclass train``: labelled joint-angle arrays -> a ``.tcm`` model file."""

from __future__ import annotations

import csv
import zipfile
from pathlib import Path

import click
import numpy as np

from .._validation import as_angle_array
from ..classifiers import RBFNetworkClassifier, TentacleClassifier
from ..io import save_model
from .options import parse_angle


class Spread(click.ParamType):
    """``auto`` or a number > 0."""

    name = "auto|FLOAT"

    def convert(self, value, param, ctx):  # noqa: D102
        if isinstance(value, float) or value == "auto":
            return value
        try:
            v = float(value)
        except ValueError:
            self.fail(f"{value!r} is neither 'auto' nor a number", param, ctx)
        if not (np.isfinite(v) and v > 0):
            self.fail(f"spread must be 'auto' or a finite number > 0, got {value!r}", param, ctx)
        return v


def _read_npz(path: Path) -> tuple[np.ndarray, np.ndarray]:
    if not zipfile.is_zipfile(path):
        raise ValueError(f"{path}: not a readable .npz file (not a zip archive)")
    try:
        with np.load(path, allow_pickle=False) as data:
            missing = [k for k in ("X", "y") if k not in data.files]
            if missing:
                raise ValueError(
                    f"{path}: the .npz must hold arrays 'X' and 'y'; missing {missing} "
                    f"(found {sorted(data.files)})"
                )
            X, y = data["X"], data["y"]
    except ValueError as exc:
        if "allow_pickle" in str(exc) or "Object arrays" in str(exc):
            raise ValueError(
                f"{path}: arrays stored as Python objects (pickles) are not read; "
                "save labels as strings or numbers"
            ) from None
        if str(exc).startswith(str(path)):
            raise
        raise ValueError(f"{path}: not a readable .npz file ({exc})") from None
    except (OSError, EOFError, zipfile.BadZipFile) as exc:
        raise ValueError(f"{path}: not a readable .npz file ({exc})") from None
    if X.ndim != 2 or not np.issubdtype(X.dtype, np.number) or np.iscomplexobj(X):
        raise ValueError(f"{path}: X must be a 2-D array of real numbers, got {X.dtype} {X.shape}")
    if y.ndim != 1:
        raise ValueError(f"{path}: y must be 1-D, got shape {y.shape}")
    return X.astype(np.float64), y


def _read_csv(path: Path) -> tuple[np.ndarray, np.ndarray]:
    try:
        text = path.read_text()
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file") from None
    rows, labels = [], []
    lines = [(i, line) for i, line in enumerate(text.splitlines(), 1)]
    for lineno, line in lines:
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [f.strip() for f in next(csv.reader([line]))]
        if len(fields) < 2:
            raise ValueError(f"{path}, line {lineno}: expected angles then a label, got {line!r}")
        *angle_fields, label = fields
        try:
            angles = [parse_angle(f) for f in angle_fields]
        except ValueError as exc:
            if not rows and all(_not_angle(f) for f in angle_fields):
                continue  # a header row
            raise ValueError(f"{path}, line {lineno}: {exc}") from None
        if not label:
            raise ValueError(f"{path}, line {lineno}: empty label")
        rows.append(angles)
        labels.append(label)
    if not rows:
        raise ValueError(f"{path}: no labelled angle arrays found")
    lengths = sorted({len(r) for r in rows})
    if len(lengths) > 1:
        raise ValueError(f"{path}: rows have different numbers of angles {lengths}")
    return np.array(rows), np.array(labels)


def _not_angle(field: str) -> bool:
    try:
        parse_angle(field)
    except ValueError:
        return True
    return False


def read_training_file(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Joint angles ``X`` (n_samples, n_joints) and labels ``y`` from ``.npz`` or CSV.

    A ``.npz`` holds arrays ``X`` and ``y``. A CSV has one array per row: the
    angles (numbers or expressions of pi such as ``pi/2``), then the label in
    the last column; ``#`` starts a comment and a first row of column names is
    skipped. CSV labels are strings.
    """
    X, y = _read_npz(path) if path.suffix.lower() == ".npz" else _read_csv(path)
    X = as_angle_array(X, "X", min_joints=3)
    if y.shape[0] != X.shape[0]:
        raise ValueError(f"{path}: {X.shape[0]} angle arrays but {y.shape[0]} labels")
    if np.unique(y).size < 2:
        raise ValueError(f"{path}: the labels name only one class; at least 2 are needed")
    return X, y


@click.command()
@click.option(
    "--data",
    "data",
    required=True,
    type=click.Path(exists=True, dir_okay=False, path_type=Path),
    help=".npz with arrays X (n_samples, n_joints) and y, or a CSV: angles..., label.",
)
@click.option(
    "--out",
    "out",
    required=True,
    type=click.Path(dir_okay=False, writable=True, path_type=Path),
    help="Model file to write (.tcm).",
)
@click.option(
    "--classifier",
    type=click.Choice(["pnn", "rbf"]),
    default="pnn",
    show_default=True,
    help="Probabilistic neural network or radial-basis-function network.",
)
@click.option(
    "--spread",
    type=Spread(),
    default="auto",
    show_default=True,
    help="Kernel width, or 'auto' to choose it on the training data.",
)
@click.option(
    "--n-coeffs",
    type=click.IntRange(min=1),
    default=None,
    help="Fourier coefficients kept [default: n_joints // 2].",
)
@click.option(
    "--detrend/--no-detrend",
    default=True,
    show_default=True,
    help="Ramp through the measured total turn (robust to joint noise).",
)
def train(
    data: Path,
    out: Path,
    classifier: str,
    spread: float | str,
    n_coeffs: int | None,
    detrend: bool,
) -> None:
    """Train a classifier on labelled joint-angle arrays and save it to --out.

    Use the model with "tentaclass classify --model FILE".
    """
    X, y = read_training_file(data)
    if classifier == "pnn":
        model = TentacleClassifier(n_coeffs=n_coeffs, detrend=detrend, spread=spread)
    else:
        model = TentacleClassifier(
            n_coeffs=n_coeffs, detrend=detrend, classifier=RBFNetworkClassifier(spread=spread)
        )
    model.fit(X, y)
    accuracy = model.score(X, y)
    save_model(model, out)
    used = model.pipeline_.named_steps["classifier"].spread_
    names = ", ".join(str(c) for c in model.classes_)
    click.echo(
        f"{classifier}: {len(model.classes_)} classes ({names}), {X.shape[0]} samples of "
        f"{X.shape[1]} joints, spread {used:.4g}, training accuracy {accuracy:.3f} -> {out}"
    )
