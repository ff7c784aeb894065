"""``tentaclass bench``: accuracy and speed of methods on a dataset, side by side."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from ..bench import METHODS, confusion_figure, results_markdown, run_benchmark
from .options import dask_client, finite, scheduler_option

DATASETS = ("reference", "synthetic", "mpeg7", "ArrowHead", "OSULeaf")
DEFAULT_METHODS = "thesis,fourier-1nn,fourier-pnn,shift-nn,1nn-euclidean,svc,minirocket"


def _load(dataset: str, links: int, mode: str, noise: float, copies: int, samples: int,
          data_dir: Path | None, seed: int, jobs: int = 1,
          client: object = None) -> tuple[dict, str]:  # fmt: skip
    """Arrays and benchmark keywords for a dataset name, plus a title."""
    from .. import datasets

    if dataset == "reference":
        X, y = datasets.reference_tentacle(links, n_starts=max(2, samples // 4), return_X_y=True)
        rng = np.random.default_rng(seed)
        X = X + rng.normal(0.0, noise, X.shape)
        return {"X": X, "y": y}, f"reference shapes, {links} links, noise {noise:g}"
    if dataset == "synthetic":
        d = datasets.synthetic_tentacle(samples, n_links=links, noise=noise, seed=seed,
                                        client=client)  # fmt: skip
        return {
            "X": d.data,
            "y": d.target,
        }, f"synthetic four classes, {links} links, noise {noise:g}"
    if dataset == "mpeg7":
        folder = data_dir or Path("../shared/data/mpeg7-part-b")
        d = datasets.mpeg7_tentacle(folder, links, mode=mode, noise=noise, copies=copies,
                                    seed=seed, n_jobs=jobs, client=client)  # fmt: skip
        keep = ~np.isin(d.groups, d.groups[~d.complete])  # drop shapes a chain jammed on
        kw = {"X": d.data[keep], "y": d.target[keep], "groups": d.groups[keep],
              "is_eval": d.wrap_index[keep] == 0}  # fmt: skip
        return (
            kw,
            f"MPEG-7 wraps, {links} links, {mode}, noise {noise:g}, {copies} wrap(s) per shape",
        )
    d = datasets.ucr_shapes(dataset)
    return {"X": d.data, "y": d.target, "split": d.split}, f"UCR {dataset}, official split"


@click.command()
@click.option("--dataset", type=click.Choice(DATASETS), default="reference", show_default=True)
@click.option("--links", type=click.IntRange(min=3), default=64, show_default=True)
@click.option("--mode", type=click.Choice(["taut", "hug"]), default="taut", show_default=True)
@click.option("--noise", type=click.FloatRange(min=0), default=0.0, show_default=True,
              callback=finite, help="Joint-angle noise sigma in radians.")  # fmt: skip
@click.option("--copies", type=click.IntRange(min=1), default=1, show_default=True,
              help="MPEG-7: wraps per shape; extra ones only train.")  # fmt: skip
@click.option("--samples", type=click.IntRange(min=8), default=400, show_default=True,
              help="Synthetic/reference: number of arrays.")  # fmt: skip
@click.option("--methods", default=DEFAULT_METHODS, show_default=True,
              help=f"Comma-separated, from: {', '.join(METHODS)}.")  # fmt: skip
@click.option("--folds", type=click.IntRange(min=2), default=10, show_default=True)
@click.option("--data-dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="MPEG-7 folder (default ../shared/data/mpeg7-part-b).")  # fmt: skip
@click.option("--out", type=click.Path(file_okay=False, path_type=Path),
              default=Path("bench-results"), show_default=True)  # fmt: skip
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
@click.option("--jobs", type=click.IntRange(min=-1), default=1, show_default=True,
              help="MPEG-7: processes generating the wraps (-1: all cores).")  # fmt: skip
@scheduler_option
def bench(dataset, links, mode, noise, copies, samples, methods, folds, data_dir, out, seed,
          jobs, scheduler=None):  # fmt: skip
    """Stratified k-fold accuracy (or the official split), fit and predict time.

    Writes a markdown table and the best method's confusion matrix to OUT.
    """
    names = [m.strip() for m in methods.split(",") if m.strip()]
    if not names:
        raise click.BadParameter("no method given", param_hint="--methods")
    unknown = [m for m in names if m not in METHODS]
    if unknown:
        raise click.BadParameter(f"unknown {unknown}; choose from {', '.join(METHODS)}",
                                 param_hint="--methods")  # fmt: skip
    if jobs == 0:
        raise click.BadParameter("must be -1 (all cores) or at least 1", param_hint="--jobs")
    with dask_client(scheduler) as client:  # generates the wraps on the cluster
        kw, title = _load(
            dataset, links, mode, noise, copies, samples, data_dir, seed, jobs, client
        )
    X = kw.pop("X")
    y = kw.pop("y")
    results = run_benchmark(X, y, names, n_splits=folds, seed=seed, progress=True, **kw)
    table = results_markdown(results, title)
    click.echo(table)
    out.mkdir(parents=True, exist_ok=True)
    stem = (
        f"{dataset}-{links}-{mode}-noise{noise:g}" if dataset in ("mpeg7", "synthetic") else dataset
    )
    (out / f"{stem}.md").write_text(table)
    scored = [r for r in results if not r.error]
    if scored:
        best = max(scored, key=lambda r: r.accuracy)
        confusion_figure(best).savefig(out / f"{stem}-confusion.png", dpi=100)
    click.echo(f"wrote {out / (stem + '.md')}", err=True)
