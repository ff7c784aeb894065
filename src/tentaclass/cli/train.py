"""``tentaclass train``: labelled joint-angle arrays -> a ``.tcm`` model file."""

from __future__ import annotations

import csv
import glob
import re
import zipfile
from pathlib import Path
from typing import Any, cast

import click
import numpy as np

from .._validation import as_angle_array, check_spread, check_total_turn
from ..errors import InputError
from ..io import save_model
from .options import (
    OutputFile,
    dask_client,
    finite,
    image_outline,
    input_file_option,
    load_npy,
    number_option,
    parse_angle,
    predict_on,
    progress_bar,
    random_state_option,
    read_text,
    refuse_unused,
    scheduler_option,
)


class Spread(click.ParamType):
    """``auto`` or a number > 0 that the classifiers can square (:func:`check_spread`)."""

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
        try:
            check_spread(v)  # 1e300 was refused by the classifier, after the data was read
        except InputError as exc:
            self.fail(str(exc), param, ctx)
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
    if y.dtype.kind not in "biufUS":  # (float labels get the classifiers' own message)
        raise ValueError(f"{path}: y must hold labels (strings or integers), got {y.dtype}")
    empty = np.flatnonzero(y == y.dtype.type()) if y.dtype.kind in "US" else np.array([])
    if empty.size:  # as a CSV row's empty label is refused
        raise ValueError(f"{path}: label {int(empty[0])} is empty")
    bad = np.flatnonzero(~np.isfinite(y)) if y.dtype.kind == "f" else np.array([])
    if bad.size:  # a NaN label is no class
        raise ValueError(f"{path}: label {int(bad[0])} is {y[bad[0]]}, not a class")
    return X.astype(np.float64), y


def _read_csv(path: Path) -> tuple[np.ndarray, np.ndarray]:
    text = read_text(path)
    rows: list[list[float]] = []
    labels: list[str] = []
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
    angle_like = [lab for lab in labels if not _not_angle(lab) and not lab.lstrip("+-").isdigit()]
    if len(angle_like) == len(labels):
        raise ValueError(
            f"{path}: the last column holds angles (e.g. {angle_like[0]!r}), not labels: "
            "each row needs the angles, then the class label"
        )
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
    X = as_angle_array(X, str(path), min_joints=3)
    check_total_turn(X, str(path))
    if y.shape[0] != X.shape[0]:
        raise ValueError(f"{path}: {X.shape[0]} angle arrays but {y.shape[0]} labels")
    if np.unique(y).size < 2:
        raise ValueError(f"{path}: the labels name only one class; at least 2 are needed")
    return X, y


_NUMBERED = re.compile(r"^(.*?)[-_ ]*\d+$")


def label_from_name(path: Path) -> str:
    """Class label from a file name: ``apple-3.png`` -> ``apple``, ``cup.csv`` -> ``cup``.

    >>> label_from_name(Path("shapes/apple-3.png")), label_from_name(Path("cup.npy"))
    ('apple', 'cup')
    """
    stem = path.stem
    m = _NUMBERED.match(stem)
    return m[1] if m and m[1] else stem


def read_labels(path: Path) -> dict[str, str]:
    """``file,label`` rows (a header row ``file,label`` is skipped): file name -> label."""
    text = read_text(path)
    labels: dict[str, str] = {}
    for lineno, row in enumerate(csv.reader(text.splitlines()), 1):
        row = [f.strip() for f in row]
        if not row or not any(row) or row[0].startswith("#"):
            continue
        if len(row) != 2 or not row[0] or not row[1]:
            raise ValueError(f"{path}, line {lineno}: expected 'file,label', got {','.join(row)!r}")
        if lineno == 1 and row == ["file", "label"]:
            continue
        labels[Path(row[0]).name] = row[1]
    if not labels:
        raise ValueError(f"{path}: no 'file,label' rows found")
    return labels


def read_outline(path: Path) -> np.ndarray:
    """One outline from an image (largest object), a CSV of ``x,y`` rows or an ``.npy``."""
    from ..shapes import as_outline

    suffix = path.suffix.lower()
    if suffix in (".png", ".gif", ".bmp", ".jpg", ".jpeg", ".tif", ".tiff", ".pbm", ".pgm"):
        return image_outline(path)
    points = load_npy(path) if suffix == ".npy" else _read_points(path)
    try:
        return as_outline(points, str(path))
    except ValueError as exc:  # the message names the file already ("a.csv intersects itself")
        line = str(exc).splitlines()[0]
        raise ValueError(line if line.startswith(str(path)) else f"{path}: {line}") from None


def _read_points(path: Path) -> np.ndarray:
    """``x,y`` rows of a CSV file; ``#`` comments and a first row of column names are skipped."""
    try:
        lines = read_text(path).splitlines()
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file of 'x,y' rows") from None
    points: list[list[float]] = []
    first = True
    for lineno, line in enumerate(lines, 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [f.strip() for f in next(csv.reader([line]))]
        try:
            values = [float(f) for f in fields]
        except ValueError:
            if first and len(fields) == 2 and all(_not_angle(f) for f in fields):
                first = False
                continue  # a header row such as 'x,y'
            values = []
        first = False
        if len(values) != 2:
            raise ValueError(f"{path}, line {lineno}: expected 'x,y' (two numbers), got {line!r}")
        points.append(values)
    if not points:
        raise ValueError(f"{path}: no 'x,y' rows found")
    return np.array(points)


def _outline_files(patterns: tuple[str, ...]) -> list[Path]:
    found: list[Path] = []
    for pattern in patterns:
        matches = sorted(Path(p) for p in glob.glob(pattern, recursive=True))
        matches = [p for p in matches if p.is_file()]
        if not matches:
            raise ValueError(f"--outlines {pattern!r} matches no file")
        found += matches
    return found


def _pair(
    text: str | None, name: str, default: tuple[float, float] | None, one_is_max: bool = False
) -> tuple[float, float] | None:
    """``MIN,MAX`` (or one number) of the option ``name``; a usage error naming it."""
    if text is None:
        return default
    try:
        values = [float(t) for t in text.replace(",", " ").split()]
    except ValueError:
        raise click.BadParameter(f"{text!r} is not a number or MIN,MAX", param_hint=name) from None
    if len(values) not in (1, 2):
        raise click.BadParameter(
            f"expected MIN,MAX (one or two numbers), got {text!r}", param_hint=name
        )
    if not all(np.isfinite(values)):
        raise click.BadParameter(
            f"MIN and MAX must be finite numbers, got {text!r}", param_hint=name
        )
    if len(values) == 1:
        if one_is_max and values[0] < 0:
            raise click.BadParameter(f"MAX must be >= 0, got {text!r}", param_hint=name)
        values = [0.0, values[0]] if one_is_max else values * 2
    if values[0] > values[1]:
        raise click.BadParameter(f"expected MIN,MAX with MIN <= MAX, got {text!r}", param_hint=name)
    return values[0], values[1]


def train_for_chain(
    files: list[Path],
    labels: list[str],
    *,
    n_links: int,
    link_length: float,
    laps: tuple[float, float] | None,
    diameters: tuple[float, float] | None,
    offset: tuple[float, float] | None,
    noise: tuple[float, float] | None,
    n_wraps: int,
    mode: str,
    random_state: int,
    reject_rate: float | None = None,
    quiet: bool = False,
) -> tuple[Any, dict[str, Any]]:
    """Wrap the outlines with the chain, train the default recogniser; model and info."""
    from ..datasets import chain_wraps
    from ..io import rejection_threshold

    outlines = [read_outline(f) for f in files]
    y_files = np.array(labels)
    settings: dict[str, Any] = {"link_length": link_length, "laps": laps, "diameters": diameters,
                "offset": offset, "noise": noise, "mode": mode}  # fmt: skip
    with progress_bar("wrapping") as bar:
        task = bar.add_task("wraps", total=len(outlines) * n_wraps, visible=not quiet)
        train = chain_wraps(
            outlines, n_links, n_wraps=n_wraps, random_state=random_state,
            progress=lambda done, total: bar.update(task, completed=done), **settings,
        )  # fmt: skip
        held_n = max(2, n_wraps // 10)
        task = bar.add_task("held out", total=len(outlines) * held_n, visible=not quiet)
        held = chain_wraps(
            outlines, n_links, n_wraps=held_n, random_state=random_state + 1,
            progress=lambda done, total: bar.update(task, completed=done), **settings,
        )  # fmt: skip
    chain = {"n_links": n_links, **settings}
    y = y_files[train.outline]
    if np.unique(y).size < 2:
        raise ValueError(
            f"{train.n_failed} of {train.n_failed + len(y)} wraps failed; those that worked "
            f"cover only {np.unique(y).tolist()}: at least 2 classes are needed"
        )
    from ..classifiers import TentacleClassifier

    own_reject = "reject" in TentacleClassifier().get_params()
    if own_reject and reject_rate is not None:
        model = TentacleClassifier(reject=reject_rate).fit(train.data, y)
    else:
        model = TentacleClassifier().fit(train.data, y)
    held_y = y_files[held.outline]
    info: dict[str, Any] = {
        "chain": {**chain, "n_wraps": n_wraps, "random_state": random_state},
        "classes": [str(c) for c in model.classes_],
        "outlines": [f.name for f in files],
        "training": {
            "n_samples": len(train.data),
            "n_failed": train.n_failed,
            "held_out_accuracy": float(np.mean(model.predict(held.data) == held_y)),
        },
    }
    if not own_reject:
        try:
            rate = 0.01 if reject_rate is None else reject_rate
            info["reject_below"] = rejection_threshold(model, held.data, rate)
        except ValueError:
            pass  # a classifier without class scores: no rejection
    return model, info


@click.command()
@input_file_option(
    "--data", "data", ".npz with arrays X (n_samples, n_joints) and y, or a CSV: angles..., label."
)
@click.option(
    "--outlines",
    "outlines",
    multiple=True,
    help="Object outlines to wrap (a glob such as 'shapes/*.png'; images, x,y CSV or .npy). "
    "The class is the file name without a trailing number (apple-3.png -> apple).",
)
@input_file_option(
    "--labels",
    "labels_file",
    "With --outlines: CSV of 'file,label' rows instead of labels from file names.",
)
@click.option(
    "--links", "n_links", type=click.IntRange(min=3, max=100_000),
    help="With --outlines: links of the robot's chain.",
)  # fmt: skip
@number_option(
    "--link-length", click.FloatRange(min=0, min_open=True), 1.0,
    "With --outlines: length of one link.",
)  # fmt: skip
@click.option("--laps", "laps_text", help="Laps the chain covers, MIN,MAX [default: 1,2].")
@click.option(
    "--diameters", "diameters_text",
    help="Object diameters MIN,MAX in link-length units (instead of --laps).",
)  # fmt: skip
@click.option(
    "--offset", "offset_text",
    help="Stand-off of the base from the object, MIN,MAX, a distance in the units of "
    "--link-length [default: 0,2 link lengths].",
)  # fmt: skip
@click.option(
    "--noise", "noise_text", help="Joint-noise sigma, MAX or MIN,MAX radians [default: 0]."
)
@click.option(
    "--wraps-per-outline", "n_wraps", type=click.IntRange(min=1, max=1_000_000), default=100,
    show_default=True, help="Wraps generated per outline.",
)  # fmt: skip
@click.option(
    "--mode", type=click.Choice(["taut", "hug", "both"]), default="both", show_default=True,
    help="How the chain lies on concave outlines.",
)  # fmt: skip
@random_state_option("Seed of the generated wraps.")
@click.option(
    "--reject-rate",
    type=click.FloatRange(0, 1, min_open=True, max_open=True),
    callback=finite,
    help="With --outlines: train the model to answer 'unknown' for objects unlike every "
    "class, rejecting about this fraction of known ones (e.g. 0.02).",
)
@click.option(
    "--out",
    "out",
    required=True,
    type=OutputFile(),
    help="Model file to write (.tcm).",
)
@click.option(
    "--classifier",
    type=click.Choice(["pnn", "rbf"]),
    default="pnn",
    show_default=True,
    help="With --data: probabilistic neural network or radial-basis-function network.",
)
@click.option(
    "--spread",
    type=Spread(),
    default="auto",
    show_default=True,
    help="With --data: kernel width, or 'auto' to choose it on the training data.",
)
@click.option(
    "--n-harmonics",
    type=click.IntRange(min=1),
    default=None,
    help="With --data: Fourier frequencies kept [default: n_joints // 2].",
)
@click.option(
    "--n-coeffs", type=click.IntRange(min=1), default=None, hidden=True,
    deprecated="--n-coeffs will be removed in the next release; use --n-harmonics",
)  # fmt: skip
@click.option(
    "--detrend/--no-detrend",
    default=True,
    show_default=True,
    help="With --data: ramp through the measured total turn (robust to joint noise).",
)
@scheduler_option
@click.pass_context
def train(
    ctx: click.Context,
    data: Path | None,
    outlines: tuple[str, ...],
    labels_file: Path | None,
    n_links: int | None,
    link_length: float,
    laps_text: str | None,
    diameters_text: str | None,
    offset_text: str | None,
    noise_text: str | None,
    n_wraps: int,
    mode: str,
    random_state: int,
    reject_rate: float | None,
    out: Path,
    classifier: str,
    spread: float | str,
    n_harmonics: int | None,
    n_coeffs: int | None,
    detrend: bool,
    scheduler: str | None = None,
) -> None:
    """Train a recogniser and save it to --out.

    Either for a robot's chain: --outlines of the objects and the chain's
    --links and --link-length; the outlines are wrapped at random sizes,
    rotations, starts and stand-offs and the default recogniser is trained on
    those wraps. Or on measured arrays: --data with labelled joint angles.

    Use the model with "tentaclass classify --model FILE".
    """
    if (data is None) == (not outlines):
        raise click.UsageError("give either --data or --outlines")
    if data is not None:
        refuse_unused(ctx, _FOR_OUTLINES, "is for --outlines; --data trains on measured arrays")
        if n_coeffs is not None:
            if n_harmonics is not None:
                raise click.UsageError("give --n-harmonics only, not --n-coeffs as well")
            n_harmonics = n_coeffs
        _train_on_arrays(data, out, classifier, spread, n_harmonics, detrend, scheduler)
        return
    refuse_unused(ctx, _FOR_DATA, "is for --data; --outlines trains the default recogniser")
    if n_links is None:
        raise click.UsageError("--outlines needs --links (the chain's number of links)")
    if laps_text is not None and diameters_text is not None:
        raise click.UsageError("give either --laps or --diameters, not both")
    diameters = _pair(diameters_text, "--diameters", None)
    laps = None if diameters is not None else _pair(laps_text, "--laps", (1.0, 2.0))
    offset = cast(tuple[float, float], _pair(offset_text, "--offset", (0.0, 2.0 * link_length)))
    noise = cast(tuple[float, float], _pair(noise_text, "--noise", (0.0, 0.0), one_is_max=True))
    from ..datasets._wraps import check_chain_settings

    try:  # ranges the chain cannot wrap are usage errors, found before any file is read
        check_chain_settings(n_links, link_length, laps=laps, diameters=diameters,
                             offset=offset, noise=noise, mode=mode)  # fmt: skip
    except InputError as exc:
        given = {"--laps": laps_text if diameters is None else "", "--offset": offset_text}
        left = [f"{name} {_show(value)}" for name, value in
                (("--laps", laps), ("--offset", offset))
                if given[name] is None and name[2:] in str(exc)]  # fmt: skip
        hint = f" (the default {' and '.join(left)}: give other values)" if left else ""
        raise click.UsageError(f"{exc}{hint}") from None
    files = _outline_files(outlines)
    if labels_file is not None:
        table = read_labels(labels_file)
        missing = [f.name for f in files if f.name not in table]
        if missing:
            raise ValueError(
                f"{labels_file}: no label for {len(missing)} outline file(s), e.g. {missing[0]!r}"
            )
        labels = [table[f.name] for f in files]
    else:
        labels = [label_from_name(f) for f in files]
    if len(set(labels)) < 2:
        raise ValueError(
            f"the outlines name only one class ({labels[0]!r}); at least 2 are needed "
            "(labels come from file names such as apple-1.png, or from --labels)"
        )
    quiet = bool(ctx.find_root().obj and ctx.find_root().obj.get("quiet"))
    model, info = train_for_chain(
        files, labels, n_links=n_links, link_length=link_length, laps=laps,
        diameters=diameters, offset=offset, noise=noise, n_wraps=n_wraps, mode=mode,
        random_state=random_state, reject_rate=reject_rate, quiet=quiet,
    )  # fmt: skip
    save_model(model, out, info=info)
    t = info["training"]
    click.echo(
        f"{len(info['classes'])} classes ({', '.join(info['classes'])}), {len(files)} outlines, "
        f"{t['n_samples']} wraps of {n_links} links ({t['n_failed']} failed), held-out "
        f"accuracy {t['held_out_accuracy']:.3f} -> {out}"
    )


#: Parameters of ``train`` that only training on outlines uses, and only training on arrays.
_FOR_OUTLINES = (
    "labels_file",
    "n_links",
    "link_length",
    "laps_text",
    "diameters_text",
    "offset_text",
    "noise_text",
    "n_wraps",
    "mode",
    "random_state",
    "seed",
    "reject_rate",
)
_FOR_DATA = ("classifier", "spread", "n_harmonics", "n_coeffs", "detrend", "scheduler")


def _train_on_arrays(
    data: Path, out: Path, classifier: str, spread: float | str, n_harmonics: int | None,
    detrend: bool, scheduler: str | None = None,
) -> None:  # fmt: skip
    from ..classifiers import FourierClassifier, RBFNetworkClassifier

    X, y = read_training_file(data)
    if classifier == "pnn":
        model = FourierClassifier(n_harmonics=n_harmonics, detrend=detrend, spread=spread)
    else:
        model = FourierClassifier(
            n_harmonics=n_harmonics, detrend=detrend, classifier=RBFNetworkClassifier(spread=spread)
        )
    with dask_client(scheduler) as client:
        model.fit(X, y)
        accuracy = float(np.mean(predict_on(model, X, client) == y))
    save_model(model, out, info={"chain": {"n_links": int(X.shape[1])}})
    used = model.pipeline_.named_steps["classifier"].spread_
    names = ", ".join(str(c) for c in model.classes_)
    click.echo(
        f"{classifier}: {len(model.classes_)} classes ({names}), {X.shape[0]} samples of "
        f"{X.shape[1]} joints, spread {used:.4g}, training accuracy {accuracy:.3f} -> {out}"
    )


def _show(pair: tuple[float, float] | None) -> str:
    """A MIN,MAX range as the user would type it."""
    return ",".join(f"{v:g}" for v in pair) if pair is not None else ""
