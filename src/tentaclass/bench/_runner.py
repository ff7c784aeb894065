"""Cross-validated accuracy and timing of several methods on one dataset."""

from __future__ import annotations

import inspect
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from sklearn.base import clone
from sklearn.model_selection import StratifiedKFold

from .._deprecation import UNSET, renamed
from .._typing import ArrayLike, FloatArray
from .._validation import as_float_array
from ..errors import InputError
from ._methods import METHODS, make_method


@dataclass(frozen=True)
class BenchResult:
    """One method's result on one dataset."""

    method: str
    accuracy: float
    accuracy_std: float
    fit_seconds: float
    predict_seconds: float
    n_train: int
    n_test: int
    y_true: np.ndarray = field(repr=False)
    y_pred: np.ndarray = field(repr=False)
    error: str = ""


def _splits(y, groups, is_eval, split, n_splits, seed):
    """(train rows, test rows) pairs: folds over objects, or the official split."""
    if split is not None:
        split = np.asarray(split)
        return [(np.flatnonzero(split == "train"), np.flatnonzero(split == "test"))]
    eval_rows = np.flatnonzero(is_eval)
    skf = StratifiedKFold(n_splits=n_splits, shuffle=True, random_state=seed)
    out = []
    for _, te in skf.split(eval_rows, y[eval_rows]):
        # every array of an object not under test trains, scored or not
        test_groups = groups[eval_rows[te]]
        out.append((np.flatnonzero(~np.isin(groups, test_groups)), eval_rows[te]))
    return out


def run_benchmark(
    X: ArrayLike,
    y: ArrayLike,
    methods: list[str],
    *,
    groups: ArrayLike | None = None,
    is_eval: ArrayLike | None = None,
    split: ArrayLike | None = None,
    failed: ArrayLike | None = None,
    n_splits: int = 10,
    random_state: int = 0,
    progress: bool = False,
    seed: Any = UNSET,
) -> list[BenchResult]:
    """Stratified k-fold accuracy, fit and predict time of each method.

    Parameters
    ----------
    X : array_like of shape (n_samples, n_joints)
        Joint-angle arrays.
    y : array_like of shape (n_samples,)
    methods : list of str
        Names from :data:`tentaclass.bench.METHODS`.
    groups : array_like of shape (n_samples,), optional
        Object each array was measured on. Folds split objects, never arrays of
        one object, and a method trains on every array of its training objects.
    is_eval : array_like of bool, shape (n_samples,), optional
        The arrays that are scored (at most one per object); default all.
        Others only train (extra wraps of training objects, e.g. with noise, or
        every array of an object left out of the scoring): a method trains on
        every array of every object not under test.
    split : array_like of {"train", "test"}, optional
        An official train/test split instead of k folds.
    failed : array_like of bool, shape (n_samples,), optional
        Wraps the generator could not complete (NaN after the last placed
        link). They never train and are never shown to a method; where scored
        they count as errors (predicted ``"failed"``).
    n_splits : int, default=10
    random_state : int, default=0
        Shuffles the folds.
    progress : bool, default=False
        Show a rich progress bar on stderr.
    seed : int, optional
        Deprecated alias of ``random_state``.

    Returns
    -------
    results : list of BenchResult
        One per method, in order. A method that fails carries its error message
        and NaN accuracy instead of stopping the run.

    Examples
    --------
    >>> from tentaclass.datasets import reference_tentacle
    >>> X, y = reference_tentacle(16, n_starts=10, return_X_y=True)
    >>> [r.accuracy for r in run_benchmark(X, y, ["thesis"], n_splits=5)]
    [1.0]
    """
    random_state = renamed("random_state", random_state, "seed", seed, default=0)
    flags = None if failed is None else np.asarray(failed, bool)
    if flags is not None and flags.any():
        X = np.where(flags[:, None], 0.0, np.asarray(X, dtype=float))
    X = as_float_array(X, "X", min_ndim=2)
    flags = np.zeros(len(X), bool) if flags is None else flags
    y = np.asarray(y)
    if X.ndim != 2 or len(y) != len(X):
        raise InputError(f"X must be (n_samples, n_joints) with one label each, got {X.shape}")
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        raise InputError(f"unknown method(s) {unknown}; choose from {', '.join(METHODS)}")
    groups = np.arange(len(y)) if groups is None else np.asarray(groups)
    is_eval = np.ones(len(y), bool) if is_eval is None else np.asarray(is_eval, bool)
    folds = _splits(y, groups, is_eval, split, n_splits, random_state)
    results = []
    bar: Any = None
    if progress:
        from rich.progress import Progress

        bar = Progress(transient=True)
        bar.start()
        task = bar.add_task("benchmark", total=len(methods) * len(folds))
    try:
        for name in methods:
            results.append(_run_one(name, X, y, folds, bar, task if bar else None, groups, flags))
    finally:
        if bar is not None:
            bar.stop()
    return results


def _run_one(
    name: str,
    X: FloatArray,
    y: np.ndarray,
    folds: list[tuple[np.ndarray, np.ndarray]],
    bar: Any,
    task: Any,
    groups: np.ndarray,
    failed: np.ndarray,
) -> BenchResult:
    fit_s = pred_s = 0.0
    y_true, y_pred, accs = [], [], []
    try:
        proto = make_method(name)
        for tr, te in folds:
            if bar is not None:
                bar.update(task, description=f"{name}")
            est = clone(proto)
            tr = tr[~failed[tr]]
            shown = te[~failed[te]]
            t0 = time.perf_counter()
            if "groups" in inspect.signature(est.fit).parameters:  # honest calibration
                est.fit(X[tr], y[tr], groups=groups[tr])
            else:
                est.fit(X[tr], y[tr])
            t1 = time.perf_counter()
            pred = np.full(len(te), "failed", dtype=object)
            if shown.size:
                pred[~failed[te]] = est.predict(X[shown])
            t2 = time.perf_counter()
            fit_s += t1 - t0
            pred_s += t2 - t1
            y_true.append(y[te])
            y_pred.append(pred)
            accs.append(float(np.mean(pred == y[te])))
            if bar is not None:
                bar.advance(task)
    except Exception as exc:  # a failing method is reported, the others still run
        return BenchResult(name, np.nan, np.nan, fit_s, pred_s, 0, 0, np.array([]), np.array([]),
                           error=f"{type(exc).__name__}: {exc}")  # fmt: skip
    n_test = sum(len(t) for t in y_true)
    yt, yp = np.concatenate(y_true), np.concatenate(y_pred)
    return BenchResult(
        method=name,
        accuracy=float(np.mean(yt == yp)),
        accuracy_std=float(np.std(accs)),
        fit_seconds=fit_s,
        predict_seconds=pred_s,
        n_train=int(np.mean([len(tr) for tr, _ in folds])),
        n_test=n_test,
        y_true=yt,
        y_pred=yp,
    )


def results_markdown(results: list[BenchResult], title: str = "") -> str:
    """The results as a markdown table (accuracy, fold std, fit and predict time)."""
    head = f"### {title}\n\n" if title else ""
    lines = [
        "| method | accuracy | fold std | fit s | predict s | what |",
        "|---|---|---|---|---|---|",
    ]
    for r in results:
        what = METHODS[r.method].description if r.method in METHODS else ""
        if r.error:
            lines.append(f"| {r.method} | failed | | | | {r.error} |")
            continue
        lines.append(
            f"| {r.method} | {r.accuracy:.1%} | {r.accuracy_std:.1%} | "
            f"{r.fit_seconds:.2f} | {r.predict_seconds:.2f} | {what} |"
        )
    return head + "\n".join(lines) + "\n"


def confusion_figure(result: BenchResult, max_labels: int = 80) -> Any:
    """Confusion matrix of one result as a matplotlib Figure (not shown)."""
    from matplotlib.figure import Figure

    from ..plot import plot_confusion_matrix

    n = len(np.unique(np.concatenate([result.y_true, result.y_pred]).astype(str)))
    side = min(24.0, max(5.0, 0.28 * n + 2.5)) if n <= max_labels else 9.0
    fig = Figure(figsize=(side + 1.2, side), layout="constrained")
    ax = fig.subplots()
    plot_confusion_matrix(result.y_true, result.y_pred, ax=ax, max_labels=max_labels)
    ax.set_title(f"{result.method}: accuracy {result.accuracy:.1%}")
    return fig
