"""Recognition accuracy on real and synthetic shapes, ours against the peers.

Run: ``.venv/bin/python benchmarks/bench_recognition.py [--quick]`` (needs the
``bench`` extra for MiniRocket and the UCR sets, and ``../shared/data`` for
MPEG-7). Writes one markdown table per setting to ``bench-results/`` and
prints them. Every method sees the same arrays and the same folds.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from sklearn.utils import Bunch

from tentaclass.bench import confusion_figure, results_markdown, run_benchmark
from tentaclass.datasets import mpeg7_tentacle, synthetic_tentacle, ucr_shapes

MPEG7 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "mpeg7-part-b"
OURS = ["thesis", "fourier-1nn", "lap-fourier-lp-1nn", "shift-nn", "shift-nn-lp", "shape-nn",
        "chord-shape-nn", "lap-shape-nn"]  # fmt: skip
PEERS = ["1nn-euclidean", "svc", "minirocket"]


def _emit(results, title, out: Path, stem: str) -> str:
    table = results_markdown(results, title)
    print(table, flush=True)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{stem}.md").write_text(table)
    scored = [r for r in results if not r.error]
    if scored:
        best = max(scored, key=lambda r: r.accuracy)
        confusion_figure(best).savefig(out / f"{stem}-confusion.png", dpi=90)
    return table


def synthetic(out: Path, n_samples: int = 2000, folds: int = 10, n_generated: int = 20_000) -> None:
    """Four thesis classes, 16 links, noise 0.02; and partial wraps apart.

    Two protocols on the same 2000 test wraps: 10-fold within them, and
    trained on ``n_generated`` further wraps from the generator (noise drawn in
    0-0.05 rad, as a deployed model would be trained).
    """
    methods = ["thesis", "lap-fourier-1nn", "lap-shift-nn", "lap-spectrum-hgb", *PEERS]
    d = synthetic_tentacle(n_samples, 16, noise=0.02, random_state=0)
    r = run_benchmark(d.data, d.target, methods, n_splits=folds)
    _emit(r, "Synthetic four classes, 16 links, 1-2 laps, offset 0-3, noise 0.02", out,
          "synthetic-16")  # fmt: skip
    g = synthetic_tentacle(n_generated, 16, noise=(0.0, 0.05), random_state=7)
    split = np.repeat(["train", "test"], [n_generated, n_samples])
    r = run_benchmark(np.vstack([g.data, d.data]), np.concatenate([g.target, d.target]),
                      methods, split=split)  # fmt: skip
    _emit(r, f"Synthetic, trained on {n_generated} generated wraps (noise 0-0.05), tested on "
          "the same 2000 wraps (noise 0.02)", out, "synthetic-16-generated")  # fmt: skip
    p = synthetic_tentacle(n_samples, 16, laps=(0.5, 1.0), noise=0.02, random_state=1)
    r = run_benchmark(p.data, p.target, methods, n_splits=folds)
    _emit(
        r, "Synthetic partial wraps (0.5-1 lap), 16 links, noise 0.02", out, "synthetic-16-partial"
    )


def mpeg7(out: Path, ns, modes, noises, folds: int = 10, copies: int = 10, hug_copies: int = 1,
          peers=PEERS) -> None:  # fmt: skip
    """MPEG-7 one-lap wraps; methods train on ``copies`` wraps per training shape.

    Hug wraps take about 10 minutes per copy of the 1400 silhouettes on two
    cores, so hug settings use their own ``hug_copies``.
    """
    for mode in modes:
        for n in ns:
            for noise in noises:
                copies_here = copies if mode == "taut" else hug_copies
                t0 = time.perf_counter()
                d = mpeg7_tentacle(
                    MPEG7, n, mode, noise=noise, copies=copies_here, random_state=0, n_jobs=-1
                )
                gen = time.perf_counter() - t0
                jammed = np.unique(d.groups[~d.complete])  # drop shapes a chain jammed on
                keep = ~np.isin(d.groups, jammed)
                d = Bunch(**{k: v[keep] for k, v in d.items() if isinstance(v, np.ndarray)})
                r = run_benchmark(d.data, d.target, OURS + list(peers), groups=d.groups,
                                  is_eval=d.wrap_index == 0, n_splits=folds)  # fmt: skip
                title = (f"MPEG-7, {n} links, {mode}, noise {noise:g}, {copies_here} wrap(s) per "
                         f"training shape, {len(jammed)} jammed shapes dropped "
                         f"(data {gen:.0f} s)")  # fmt: skip
                _emit(r, title, out, f"mpeg7-{mode}-{n}-noise{noise:g}")
                if mode == "hug":  # the same models, scored on the laps that close
                    closed = (d.wrap_index == 0) & (d.closure_gap < 0.5)
                    r = run_benchmark(d.data, d.target, OURS + list(peers), groups=d.groups,
                                      is_eval=closed, n_splits=folds)  # fmt: skip
                    stem = f"mpeg7-{mode}-{n}-noise{noise:g}-closed"
                    _emit(r, f"{title}; scored on the {closed.sum()} wraps whose lap closes "
                          "(gap < 0.5 link)", out, stem)  # fmt: skip


def ucr(out: Path) -> None:
    """ArrowHead and OSULeaf with their official splits."""
    for name in ("ArrowHead", "OSULeaf"):
        d = ucr_shapes(name)
        r = run_benchmark(d.data, d.target, ["shift-nn-raw", "1nn-euclidean", "svc", "minirocket"],
                          split=d.split)  # fmt: skip
        _emit(r, f"UCR {name}, official split", out, f"ucr-{name}")


def main(quick: bool = False, out: Path = Path("bench-results")) -> None:
    """Run the recognition benchmarks (``quick``: a small subset for a smoke run)."""
    if quick:
        d = synthetic_tentacle(120, 16, noise=0.02, random_state=0)
        r = run_benchmark(d.data, d.target, ["thesis", "lap-fourier-1nn", "1nn-euclidean"],
                          n_splits=3)  # fmt: skip
        _emit(r, "quick synthetic", out, "quick")
        return
    synthetic(out)
    if MPEG7.is_dir():
        mpeg7(out, (16, 32, 64, 128), ("taut", "hug"), (0.0, 0.05))
    else:
        print(f"MPEG-7 data not found at {MPEG7}: skipped", file=sys.stderr)
    ucr(out)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--only", choices=["synthetic", "mpeg7", "ucr"])
    parser.add_argument("--links", default="16,32,64,128")
    parser.add_argument("--modes", default="taut,hug")
    parser.add_argument("--noises", default="0,0.05")
    parser.add_argument("--copies", type=int, default=10, help="taut wraps per MPEG-7 shape")
    parser.add_argument("--hug-copies", type=int, default=1, help="hug wraps per MPEG-7 shape")
    parser.add_argument("--peers", default=",".join(PEERS), help="peer methods to run")
    parser.add_argument("--out", type=Path, default=Path("bench-results"))
    a = parser.parse_args()
    if a.only == "mpeg7":
        mpeg7(a.out, [int(x) for x in a.links.split(",")], a.modes.split(","),
              [float(x) for x in a.noises.split(",")], copies=a.copies, hug_copies=a.hug_copies,
              peers=[p for p in a.peers.split(",") if p])  # fmt: skip
    elif a.only == "synthetic":
        synthetic(a.out)
    elif a.only == "ucr":
        ucr(a.out)
    else:
        main(a.quick, a.out)
