"""``tentaclass classify``: joint-angle arrays -> class and probability."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np
from sklearn.pipeline import Pipeline

from .._validation import as_angle_array
from ..classifiers import TentacleClassifier
from ..datasets import reference_tentacle
from ..io import load_model
from ..report import classification_table, table_to_json
from .options import AngleList, read_angle_file


def default_model(n_links: int) -> TentacleClassifier:
    """The built-in model: the four thesis classes at ``n_links`` links."""
    X, y = reference_tentacle(n_links, return_X_y=True)
    return TentacleClassifier(detrend=True, spread=0.5).fit(X, y)


def model_from_file(path: Path) -> tuple[TentacleClassifier | Pipeline, int]:
    """A model of joint angles from a ``.tcm`` file, and its chain length."""
    model = load_model(path)
    if isinstance(model, TentacleClassifier):
        return model, model.n_features_in_
    if isinstance(model, Pipeline):
        return model, model.steps[0][1].n_features_in_
    raise ValueError(
        f"{path}: holds a bare {type(model).__name__} of feature vectors; classify needs "
        "a model of joint angles (from 'tentaclass train' or a TentacleClassifier)"
    )


@click.command()
@click.argument("angles", type=AngleList(), required=False)
@click.option(
    "--file",
    "file",
    type=click.Path(exists=True, dir_okay=False, path_type=Path),
    help="Text/CSV file with one angle array per row, or a .npy file.",
)
@click.option(
    "--model",
    "model_file",
    type=click.Path(exists=True, dir_okay=False, path_type=Path),
    help="Model file (.tcm, from 'tentaclass train') to use instead of the built-in model.",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of a table.")
def classify(
    angles: np.ndarray | None, file: Path | None, model_file: Path | None, as_json: bool
) -> None:
    """Classify joint-angle arrays: ANGLES such as "0 0 0 pi/2 ..." or --file.

    The built-in model knows the thesis's four classes (square, circle,
    triangle, rectangle) for chains of any length; --model uses a trained one.
    """
    if (angles is None) == (file is None):
        raise click.UsageError("give either ANGLES or --file, not both or neither")
    X = read_angle_file(file) if file is not None else angles[None, :]
    X = as_angle_array(X, "angle array", min_joints=3)
    if model_file is None:
        model = default_model(X.shape[1])
    else:
        model, n_joints = model_from_file(model_file)
        if X.shape[1] != n_joints:
            raise ValueError(
                f"the model {model_file.name} expects arrays of {n_joints} joint angles, "
                f"got {X.shape[1]}"
            )
    labels = model.predict(X)
    table = classification_table(labels, model.predict_proba(X), model.classes_)
    if as_json:
        click.echo(table_to_json(table))
        return
    click.echo(f"{'index':>5}  {'class':<10} {'probability':>11}")
    for i, lab, p in zip(table["index"], table["label"], table["probability"], strict=True):
        click.echo(f"{i:>5}  {str(lab).upper():<10} {p:>11.3f}")
