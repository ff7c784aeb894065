"""``tentaclass classify``: joint-angle arrays -> class and probability."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import click
import numpy as np

from .options import (
    AngleList,
    dask_client,
    files_options,
    finite,
    input_file_option,
    note,
    parse_angle_rows,
    read_angle_file,
    refuse_unused,
    scheduler_option,
)

#: Arrays that turn less than this many laps in total do not wrap anything.
MIN_LAPS = 0.05


def default_model(n_links: int) -> Any:
    """The one-lap reference model: the four thesis classes at ``n_links`` links."""
    from ..classifiers import FourierClassifier
    from ..datasets import reference_tentacle

    X, y = reference_tentacle(n_links, return_X_y=True)
    return FourierClassifier(detrend=True, spread=0.5).fit(X, y)


def model_from_file(path: Path) -> tuple[Any, dict]:
    """A model of joint angles from a ``.tcm`` file, and its info.

    Models the light reader covers predict without importing scikit-learn
    (:func:`tentaclass.io._light.load_light`); others are loaded in full.
    """
    from ..io._light import load_light

    light, info = load_light(path)
    if light is not None:
        return light, info
    from sklearn.pipeline import Pipeline

    from ..classifiers import FourierClassifier, TentacleClassifier
    from ..io import load_model

    model = load_model(path)
    if not isinstance(model, TentacleClassifier | FourierClassifier | Pipeline):
        raise ValueError(
            f"{path}: holds a bare {type(model).__name__} of feature vectors; classify needs "
            "a model of joint angles (from 'tentaclass train', a TentacleClassifier or a "
            "FourierClassifier)"
        )
    return model, info


def _read_stdin() -> np.ndarray:
    stream = sys.stdin
    if stream is None or stream.isatty():
        raise ValueError("give either ANGLES or --file, or pipe angle arrays into stdin")
    try:
        text = stream.read()
        text.encode("utf-8")  # bytes that are not UTF-8 read as lone surrogates fail here
    except (UnicodeDecodeError, UnicodeEncodeError):
        raise ValueError("standard input: not UTF-8 text (angle arrays, one per line)") from None
    lines = text.removeprefix("\ufeff").splitlines()  # (a byte-order mark)
    if not any(line.split("#", 1)[0].strip() for line in lines):
        raise ValueError(
            "standard input holds no angle arrays: give ANGLES or --file, or pipe angle "
            "arrays into stdin"
        )
    return parse_angle_rows(lines, "standard input")


def _check_wraps(X: np.ndarray, name: str) -> None:
    """Refuse arrays of a chain that turns around nothing (e.g. all zeros), or too much."""
    from .._validation import check_total_turn
    from ..wrapping import grasp_state

    check_total_turn(X, name)

    laps = np.atleast_1d(grasp_state(X).laps)
    flat = np.flatnonzero(laps < MIN_LAPS)
    if flat.size:
        i = int(flat[0])
        raise ValueError(
            f"angle array {i} turns {float(np.abs(X[i].sum())):.3g} rad in total: not a chain "
            f"wrapped around an object (a wrap turns about 2*pi per lap)"
        )


def builtin_model(n_links: int) -> tuple[Any, dict]:
    """The model and info ``classify`` uses without ``--model``, for ``n_links`` links.

    The bundled model of that chain length. For a chain length without one,
    the one-lap reference model of the four thesis classes
    (:func:`default_model`, info ``{}``), and always a one-line warning on
    stderr saying so and naming the bundled lengths: its answers come from
    ideal one-lap wraps, not from wraps of the user's chain.

    Examples
    --------
    >>> model, info = builtin_model(16)  # bundled
    >>> info["chain"]["n_links"], model.classes_.tolist()
    (16, ['circle', 'rectangle', 'square', 'triangle'])
    >>> model, info = builtin_model(24)  # none bundled: the reference shapes, a warning
    >>> info, model.n_features_in_
    ({}, 24)
    """
    from .._validation import MAX_POINTS
    from ..io._deploy import bundled_links, bundled_predictor

    if n_links in bundled_links():
        return bundled_predictor(n_links)
    if n_links > MAX_POINTS:
        raise click.ClickException(
            f"arrays of {n_links:,} angles are longer than the reference shapes are built for "
            f"(at most {MAX_POINTS:,}); classify them with --model"
        )
    links = ", ".join(map(str, bundled_links()))
    note(
        f"warning: no bundled model for {n_links} links (bundled: {links}); using the one-lap "
        "reference shapes: train a model for your chain with 'tentaclass train --outlines'"
    )
    return default_model(n_links), {}


@click.command()
@click.argument("angles", type=AngleList(), required=False)
@input_file_option(
    "--file", "file", "Text/CSV file with one angle array per row, a .npy or a Parquet file."
)
@input_file_option(
    "--model",
    "model_file",
    "Model file (.tcm, from 'tentaclass train') to use instead of the bundled model.",
)
@click.option(
    "--reject",
    is_flag=True,
    help="Answer 'unknown' for objects unlike every class (the model's own threshold).",
)
@click.option(
    "--reject-below",
    type=click.FloatRange(min=0, max=1),
    callback=finite,
    help="Rejection threshold on the best class score, instead of the model's own.",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of a table.")
@files_options(".labels.parquet for Parquet, .labels.csv otherwise")
@scheduler_option
def classify(
    angles: np.ndarray | None,
    file: Path | None,
    model_file: Path | None,
    reject: bool,
    reject_below: float | None,
    as_json: bool,
    files: str | None = None,
    out_dir: Path | None = None,
    scheduler: str | None = None,
) -> None:
    """Classify joint-angle arrays: ANGLES such as "0 0 0 pi/2 ...", --file, or stdin.

    With neither ANGLES nor --file, reads one array per line from standard
    input, so `tentaclass wrap ... | tentaclass classify` works. The bundled
    models know the thesis's four classes (square, circle, triangle,
    rectangle) for chains of 16, 32, 40 and 64 links; --model uses a trained
    one.
    """
    from .._validation import as_angle_array
    from ..io import best_class_score, check_chain_length
    from ..io._deploy import _predict_once, info_reject_below
    from ..report import classification_table, table_to_json

    ctx = click.get_current_context()
    if files is not None or scheduler is not None:
        refuse_unused(ctx, ("reject", "reject_below", "as_json"), "does not go with --files")
        return _many(files, out_dir, model_file, scheduler, angles is not None or file is not None)
    refuse_unused(ctx, ("out_dir",), "needs --files")
    if angles is not None and file is not None:
        raise click.UsageError("give either ANGLES or --file, not both")
    if file is not None:
        X = read_angle_file(file)
    elif angles is not None:
        X = angles[None, :]
    else:
        X = _read_stdin()
    name = str(file) if file is not None else "ANGLES" if angles is not None else "stdin"
    X = as_angle_array(X, name, min_joints=3)
    _check_wraps(X, name)
    if model_file is None:
        model, info = builtin_model(X.shape[1])
        name = "the bundled model"
    else:
        model, info = model_from_file(model_file)
        name = f"the model {model_file.name}"
        n_in = getattr(model, "n_features_in_", None)
        check_chain_length(X, info, n_in if isinstance(n_in, int) else None, name)
    labels, proba, best = _predict_once(model, X)
    labels = labels.astype(object)
    own = getattr(model, "reject", None)
    if own is not None and reject_below is None:
        # a recogniser that rejects by itself answers "unknown" in predict already
        if reject and not own:
            raise ValueError(
                f"{name} was trained without rejection: train it again with --reject-rate"
            )
        if not reject and model_file is None:  # the bundled model rejects on request only
            rejected = labels == getattr(model, "unknown_label", "unknown")
            labels[rejected] = model.classes_[np.argmax(proba[rejected], axis=1)]
    elif reject or reject_below is not None:
        threshold = reject_below if reject_below is not None else info_reject_below(info, name)
        if threshold is None:
            raise ValueError(f"{name} has no rejection threshold of its own: give --reject-below")
        best = best if best is not None else best_class_score(model, X)
        labels[best < threshold] = "unknown"
    table = classification_table(labels, proba, model.classes_)
    if as_json:
        click.echo(table_to_json(table))
        return
    click.echo(f"{'index':>5}  {'class':<10} {'probability':>11}")
    closest = np.asarray(model.classes_)[np.argmax(proba, axis=1)] if len(proba) else []
    for i, lab, p, near in zip(
        table["index"], table["label"], table["probability"], closest, strict=True
    ):
        if lab == "unknown":  # the probabilities are among the known classes: not shown
            click.echo(f"{i:>5}  {'unknown':<10} {'-':>11}  (closest: {str(near).upper()})")
        else:
            click.echo(f"{i:>5}  {str(lab).upper():<10} {p:>11.3f}")


def _many(
    files: str | None, out_dir: Path | None, model_file: Path | None, scheduler: str | None,
    single: bool,
) -> None:  # fmt: skip
    """``--files`` (optionally ``--scheduler``): one result file per input file."""
    if files is None or single:
        raise click.UsageError(
            "--files/--scheduler take the place of ANGLES and --file: give --files GLOB"
        )
    if out_dir is None:
        raise click.UsageError("--files needs --out-dir, the folder for the per-file results")
    model = model_from_file(model_file)[0] if model_file is not None else None
    from ._files import classify_files

    with dask_client(scheduler) as client:
        done = classify_files(files, out_dir, client, model)
    for src, dst, n in done:
        click.echo(f"{src}: {n} arrays -> {dst}" if n else f"{src}: no rows -> {dst} (empty)")
