"""Outline series: OutlineClassifier against aeon's MiniRocket and MultiRocket+Hydra
on UCR shape sets (official splits, same run), and the MPEG-7 bull's-eye test of
``shape_distances``.

    python benchmarks/bench_outline.py [--sets ArrowHead,OSULeaf] [--mpeg7 DIR] [--seeds 0,1,2]

``--sets ""`` runs the bull's-eye test alone; ``NUMBA_NUM_THREADS`` sets the
threads of the elastic matcher (the CPU time is reported too).

Needs the ``bench`` extra (aeon; MultiRocket+Hydra also needs torch). Every
classifier runs with one BLAS thread (threadpoolctl).
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_info, threadpool_limits

from tentaclass.classifiers import OutlineClassifier, bullseye_score, shape_distances
from tentaclass.datasets import ucr_shapes

PUBLISHED_BEST = {"ArrowHead": 89.73, "OSULeaf": 97.80}


def _peers():
    from aeon.classification.convolution_based import MiniRocketClassifier

    peers = {"MiniRocket": lambda s: MiniRocketClassifier(random_state=s)}
    try:
        from aeon.classification.convolution_based import MultiRocketHydraClassifier

        MultiRocketHydraClassifier(random_state=0)
        peers["MultiRocket+Hydra"] = lambda s: MultiRocketHydraClassifier(random_state=s)
    except (ImportError, ModuleNotFoundError) as exc:
        print(f"MultiRocket+Hydra left out: {exc}")
    return peers


def run_ucr(name: str, seeds: list[int]) -> list[tuple]:
    d = ucr_shapes(name)
    tr, te = d.split == "train", d.split == "test"
    Xtr, ytr, Xte, yte = d.data[tr], d.target[tr], d.data[te], d.target[te]
    rows = []
    makers = {"OutlineClassifier()": lambda s: OutlineClassifier(random_state=s), **_peers()}
    for label, make in makers.items():
        accs, fits, preds = [], [], []
        for s in seeds:
            clf = make(s)
            wide = label != "OutlineClassifier()"
            with threadpool_limits(1):
                t0 = time.perf_counter()
                clf.fit(Xtr[:, None] if wide else Xtr, ytr)
                t1 = time.perf_counter()
                p = clf.predict(Xte[:, None] if wide else Xte)
                t2 = time.perf_counter()
            accs.append(100 * np.mean(p == yte))
            fits.append(t1 - t0)
            preds.append(1000 * (t2 - t1) / len(Xte))
        rows.append((name, label, np.mean(accs), np.std(accs), np.median(fits), np.median(preds)))
        print(
            f"| {name} | {label} | {np.mean(accs):.1f} ± {np.std(accs):.1f} | "
            f"{np.median(fits):.1f} s | {np.median(preds):.2f} ms |",
            flush=True,
        )
    return rows


def _diffusion_rerank(D: np.ndarray, k: int = 10, iterations: int = 10) -> np.ndarray:
    """Re-rank by diffusion on the k-nearest-neighbour graph (a simple form of
    Yang, Prasad & Latecki's locally constrained diffusion): similarities
    W = exp(-d^2 / (s_i s_j)) with s_i the distance to the k-th neighbour, then
    A <- P A P^T + I with P the row-normalised W restricted to the k nearest.
    k and the iterations were chosen on a 35-class subset. Returns -A (a
    dissimilarity for bullseye_score)."""
    n = len(D)
    s = np.sort(D, axis=1)[:, k][:, None]
    W = np.exp(-(D**2) / (s * s.T))
    rows = np.arange(n)[:, None]
    nearest = np.argsort(D, axis=1)[:, :k]
    P = np.zeros_like(W)
    P[rows, nearest] = W[rows, nearest]
    P /= P.sum(axis=1, keepdims=True)
    A = W
    for _ in range(iterations):
        A = P @ A @ P.T + np.eye(n)
    return -A


def run_bullseye(folder: Path) -> None:
    import numba

    from tentaclass.features import outline_to_series
    from tentaclass.shapes import load_mpeg7

    outlines, labels, _ = load_mpeg7(folder)
    shape_distances(outlines[:3])  # compile (numba caches it on disk)
    t0, c0 = time.perf_counter(), time.process_time()
    with threadpool_limits(1):
        D = shape_distances(outlines)
    t, c = time.perf_counter() - t0, time.process_time() - c0
    print(
        f"| shape_distances, outlines (elastic: height functions + DP) | "
        f"{100 * bullseye_score(D, labels):.2f} % | {t:.0f} s wall, {c:.0f} s CPU "
        f"({numba.get_num_threads()} numba threads) |",
        flush=True,
    )
    t0 = time.perf_counter()
    with threadpool_limits(1):
        R = _diffusion_rerank(D)
    print(
        f"| the elastic distances re-ranked by kNN-graph diffusion (not part of the library) | "
        f"{100 * bullseye_score(R, labels):.2f} % | {time.perf_counter() - t0:.0f} s more |",
        flush=True,
    )
    ds = {}
    for sig in ("centroid", "turning"):
        X = np.array([outline_to_series(o, 128, signature=sig) for o in outlines])
        t0 = time.perf_counter()
        with threadpool_limits(1):
            ds[sig] = shape_distances(X)
        t = time.perf_counter() - t0
        print(
            f"| shape_distances, {sig} signature, 128 points | "
            f"{100 * bullseye_score(ds[sig], labels):.2f} % | {t:.0f} s |",
            flush=True,
        )
    both = sum(D / np.median(D) for D in ds.values())
    print(
        f"| centroid + turning distances (median-scaled sum) | "
        f"{100 * bullseye_score(both, labels):.2f} % | |",
        flush=True,
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sets", default="ArrowHead,OSULeaf")
    ap.add_argument("--seeds", default="0,1,2")
    ap.add_argument(
        "--mpeg7",
        default=str(
            Path(__file__).resolve().parents[1].parent / "shared" / "data" / "mpeg7-part-b"
        ),
    )
    args = ap.parse_args()
    print(
        f"load {os.getloadavg()[0]:.1f}; BLAS: "
        f"{[(i['internal_api'], i['num_threads']) for i in threadpool_info()]} (limited to 1)"
    )
    print("| set | method | accuracy % (mean ± sd over seeds) | fit | predict per series |")
    print("|---|---|---|---|---|")
    seeds = [int(s) for s in args.seeds.split(",")]
    for name in args.sets.split(","):
        if name:
            run_ucr(name, seeds)
    if Path(args.mpeg7).is_dir():
        print("| MPEG-7 bull's-eye | score | time |\n|---|---|---|")
        run_bullseye(Path(args.mpeg7))
    else:
        print(f"MPEG-7 not found at {args.mpeg7}: bull's-eye left out")


if __name__ == "__main__":
    main()
