"""``tentaclass bench``: accuracy and speed of methods on a dataset, side by side."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from .._validation import MAX_SAMPLES
from ..bench import METHODS, confusion_figure, results_markdown, run_benchmark
from ..errors import InputError
from ..wrapping import MAX_LINKS
from .options import (
    Folder,
    dask_client,
    given,
    make_folder,
    noise_option,
    note,
    random_state_option,
    scheduler_option,
)

DATASETS = ("reference", "synthetic", "mpeg7", "ucr", "ArrowHead", "OSULeaf")
DEFAULT_METHODS = "tentacle,thesis,shift-nn-lp,lap-shape-nn,1nn-euclidean,svc,minirocket"


def _load(dataset: str, links: int, mode: str, noise: float, copies: int, samples: int,
          data_dir: Path | None, random_state: int, jobs: int = 1, protocol: str = "fixed-chain",
          laps: tuple[float, float] = (1.2, 2.0),
          offset: tuple[float, float] = (0.0, 2.0),
          client: object = None, ucr_path: Path | None = None,
          ucr_name: str | None = None) -> tuple[dict, str]:  # fmt: skip
    """Arrays and benchmark keywords for a dataset name, plus a title."""
    from .. import datasets

    if dataset == "reference":
        X, y = datasets.reference_tentacle(links, n_starts=max(2, samples // 4), return_X_y=True)
        rng = np.random.default_rng(random_state)
        X = X + rng.normal(0.0, noise, X.shape)
        return {"X": X, "y": y}, f"reference shapes, {links} links, noise {noise:g}"
    if dataset == "synthetic":
        d = datasets.synthetic_tentacle(samples, n_links=links, noise=noise, laps=laps,
                                        random_state=random_state, offset=offset, mode=mode,
                                        client=client)  # fmt: skip
        kw = {"X": d.data, "y": d.target, "failed": ~d.complete}
        return kw, f"synthetic four classes, {links} links, {mode}, noise {noise:g}"
    if dataset == "mpeg7":
        folder = data_dir or Path("../shared/data/mpeg7-part-b")
        d = datasets.mpeg7_tentacle(folder, links, mode=mode, noise=noise, copies=copies,
                                    random_state=random_state, n_jobs=jobs, protocol=protocol,
                                    laps=laps, offset=offset, progress=True,
                                    client=client)  # fmt: skip
        # failed wraps stay: they count as errors
        kw = {"X": d.data, "y": d.target, "groups": d.groups, "is_eval": d.wrap_index == 0,
              "failed": ~d.complete}  # fmt: skip
        what = f"{laps[0]:g}-{laps[1]:g} laps" if protocol == "fixed-chain" else "upper bound"
        return (
            kw,
            f"MPEG-7 wraps, {protocol} ({what}), {links} links, {mode}, noise {noise:g}, "
            f"{copies} wrap(s) per shape, {int((~d.complete).sum())} failed",
        )
    if dataset == "ucr":
        if ucr_path is None:
            raise InputError("--dataset ucr needs --ucr-path: the archive's folder, a data "
                             "set's folder or its _TRAIN file")  # fmt: skip
        d = datasets.load_ucr(ucr_path, ucr_name)
        return {"X": d.data, "y": d.target, "split": d.split}, d.DESCR.rstrip(".")
    d = datasets.ucr_shapes(dataset)
    return {"X": d.data, "y": d.target, "split": d.split}, f"UCR {dataset}, official split"


#: Options that only some datasets use: parameter name -> those datasets (and, for MPEG-7,
#: the protocols that use it).
_USED_BY: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "links": (("reference", "synthetic", "mpeg7"), ("fixed-chain", "one-lap")),
    "mode": (("synthetic", "mpeg7"), ("fixed-chain", "one-lap")),
    "noise": (("reference", "synthetic", "mpeg7"), ("fixed-chain", "one-lap")),
    "samples": (("reference", "synthetic"), ()),
    "folds": (("reference", "synthetic", "mpeg7"), ("fixed-chain", "one-lap")),
    "copies": (("mpeg7",), ("fixed-chain", "one-lap")),
    "protocol": (("mpeg7",), ("fixed-chain", "one-lap")),
    "laps": (("synthetic", "mpeg7"), ("fixed-chain",)),
    "offset": (("synthetic", "mpeg7"), ("fixed-chain",)),
    "jobs": (("mpeg7",), ("one-lap",)),
    "scheduler": (("synthetic", "mpeg7"), ("fixed-chain", "one-lap")),
}


def _refuse_unused(ctx: click.Context, dataset: str, protocol: str) -> None:
    """A usage error naming the first option set that ``dataset`` (and ``protocol``) ignores."""
    for name, (datasets, protocols) in _USED_BY.items():
        flag = given(ctx, name)
        if not flag:
            continue
        if dataset not in datasets:
            where = ", ".join(datasets)
            raise click.BadParameter(
                f"applies to --dataset {where} only, not to --dataset {dataset}", param_hint=flag[0]
            )
        if dataset == "mpeg7" and protocol not in protocols:
            raise click.BadParameter(
                f"applies to --protocol {protocols[0]} only, not to --protocol {protocol}",
                param_hint=flag[0],
            )


def _pair(ctx, param, value):
    """'low,high' -> (low, high), both finite and >= 0, low <= high."""
    try:
        lo, hi = (float(v) for v in str(value).split(","))
    except ValueError:
        raise click.BadParameter(f"expected two numbers 'low,high', got {value!r}") from None
    if not (np.isfinite(lo) and np.isfinite(hi)) or lo < 0 or hi < lo:
        raise click.BadParameter(f"expected 0 <= low <= high, got {value!r}")
    return lo, hi


@click.command()
@click.option("--dataset", type=click.Choice(DATASETS), default="reference", show_default=True)
@click.option("--links", type=click.IntRange(min=3, max=MAX_LINKS), default=64,
              show_default=True)  # fmt: skip
@click.option("--mode", type=click.Choice(["taut", "hug"]), default="taut", show_default=True)
@noise_option(0.0, "Joint-angle noise sigma in radians (at most 2*pi).")
@click.option("--copies", type=click.IntRange(min=1, max=10_000), default=1,
              show_default=True,
              help="MPEG-7: wraps per shape; extra ones only train.")  # fmt: skip
@click.option("--samples", type=click.IntRange(min=8, max=MAX_SAMPLES), default=400,
              show_default=True, help="Synthetic/reference: number of arrays.")  # fmt: skip
@click.option("--methods", default=DEFAULT_METHODS, show_default=True,
              help=f"Comma-separated, from: {', '.join(METHODS)}.")  # fmt: skip
@click.option("--folds", type=click.IntRange(min=2), default=10, show_default=True)
@click.option("--data-dir", type=Folder(), default=None,
              help="MPEG-7 folder (default ../shared/data/mpeg7-part-b).")  # fmt: skip
@click.option("--out", type=Folder(),
              default=Path("bench-results"), show_default=True)  # fmt: skip
@click.option("--ucr-path", type=click.Path(exists=True, path_type=Path), default=None,
              help="UCR / UEA: the archive's folder, a data set's folder or its _TRAIN file "
              "(.tsv or .ts).")  # fmt: skip
@click.option(
    "--name",
    "ucr_name",
    default=None,
    help="UCR / UEA: the data set in --ucr-path (default: the folder's name).",
)
@click.option("--protocol", type=click.Choice(["fixed-chain", "one-lap"]), default="fixed-chain",
              show_default=True, help="MPEG-7: one chain of unit links, or one lap by a link "
              "length tuned per shape (an upper bound).")  # fmt: skip
@click.option("--laps", default="1.2,2", show_default=True, callback=_pair,
              help="Synthetic / fixed chain: laps wrapped (0.5,0.95: partial).")  # fmt: skip
@click.option("--offset", default="0,2", show_default=True, callback=_pair,
              help="Synthetic / fixed chain: range of the base's stand-off, a distance (the "
              "links are of unit length: also the approach's number of links).")  # fmt: skip
@random_state_option("Seed of the generated data and of the folds.")
@click.option("--jobs", type=click.IntRange(min=-1), default=1, show_default=True,
              help="MPEG-7, --protocol one-lap: processes tuning the link lengths (-1: all "
              "cores).")  # fmt: skip
@scheduler_option
def bench(dataset, links, mode, noise, copies, samples, methods, folds, data_dir, out, ucr_path,
          ucr_name, protocol, laps, offset, random_state, jobs, scheduler=None):  # fmt: skip
    """Stratified k-fold accuracy (or the official split), fit and predict time.

    UCR / UEA sets use their official train/test split:
    ``--dataset ucr --ucr-path DIR --name NAME --methods outline,minirocket``.

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
    only = {
        "--name": (ucr_name, "ucr"),
        "--ucr-path": (ucr_path, "ucr"),
        "--data-dir": (data_dir, "mpeg7"),
    }
    for hint, (value, needs) in only.items():
        if value is not None and dataset != needs:
            raise click.BadParameter(
                f"applies to --dataset {needs} only, not to --dataset {dataset}", param_hint=hint
            )
    _refuse_unused(click.get_current_context(), dataset, protocol)
    make_folder(out, "--out")
    with dask_client(scheduler) as client:  # generates the wraps on the cluster
        kw, title = _load(dataset, links, mode, noise, copies, samples, data_dir, random_state,
                          jobs, protocol, laps, offset, client, ucr_path, ucr_name)  # fmt: skip
    X = kw.pop("X")
    y = kw.pop("y")
    results = run_benchmark(
        X, y, names, n_splits=folds, random_state=random_state, progress=True, **kw
    )
    table = results_markdown(results, title)
    click.echo(table)
    stem = (
        f"{dataset}-{links}-{mode}-noise{noise:g}" if dataset in ("mpeg7", "synthetic") else dataset
    )
    if dataset == "ucr":
        stem = "ucr-" + title.split(" ", 1)[0]  # the data set's name
    if dataset == "mpeg7":
        stem += f"-{protocol}" + (
            f"-laps{laps[0]:g}-{laps[1]:g}" if protocol == "fixed-chain" else ""
        )
    (out / f"{stem}.md").write_text(table)
    scored = [r for r in results if not r.error]
    if scored:
        best = max(scored, key=lambda r: r.accuracy)
        confusion_figure(best).savefig(out / f"{stem}-confusion.png", dpi=100)
    note(f"wrote {out / (stem + '.md')}")
