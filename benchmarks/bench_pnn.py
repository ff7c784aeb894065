"""PNN prediction against scikit-learn's brute-force 1-NN and the bare matrix product.

Run: ``.venv/bin/python benchmarks/bench_pnn.py [--train 100000] [--test 100000]``.

Goal: on 100 000 training and 100 000 test arrays of 32 features,
``PNNClassifier.predict`` at least as fast as
``KNeighborsClassifier(n_neighbors=1, algorithm="brute")`` and within 2x of the
bare product ``X_test @ X_train.T`` (result discarded: the full 100 000 x
100 000 matrix would not fit in memory), timed in two layouts - 256-row blocks
with BLAS threads, and cache-sized tiles over threads as the PNN does - of
which the faster counts. All timings come from
one run on the same data, so the ratios are meaningful even on a busy machine;
absolute numbers are not. Everything runs with BLAS limited to 1 thread and
then to all CPUs (threadpoolctl); the PNN and the tiled product use as many
threads as BLAS may.

The data are Gaussian clusters (one per class) in 32 dimensions, the shape
of Fourier features of 64-link chains; the PNN spread is chosen by
``spread="auto"`` on the training set (not timed).
"""

from __future__ import annotations

import argparse
import itertools
import os
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
from sklearn.neighbors import KNeighborsClassifier
from threadpoolctl import threadpool_info, threadpool_limits

sys.path.insert(0, str(Path(__file__).parent))
from _timing import interleaved, machine, markdown_table

from tentaclass.classifiers import PNNClassifier


def make_data(n_train: int, n_test: int, n_features: int, n_classes: int, seed: int):
    """Gaussian clusters: centres at scale 3, unit noise."""
    rng = np.random.default_rng(seed)
    centres = rng.normal(0, 3, (n_classes, n_features))
    y_train = rng.integers(0, n_classes, n_train)
    y_test = rng.integers(0, n_classes, n_test)
    X_train = centres[y_train] + rng.normal(size=(n_train, n_features))
    X_test = centres[y_test] + rng.normal(size=(n_test, n_features))
    return X_train, y_train, X_test, y_test


def bare_matmul(X_test: np.ndarray, X_train: np.ndarray, block_rows: int = 256) -> None:
    """The product ``X_test @ X_train.T`` in row blocks into one reused buffer (BLAS threads)."""
    pt = np.ascontiguousarray(X_train.T)
    out = np.empty((block_rows, X_train.shape[0]), dtype=X_test.dtype)
    for lo in range(0, X_test.shape[0], block_rows):
        xb = X_test[lo : lo + block_rows]
        np.matmul(xb, pt, out=out[: xb.shape[0]])


def bare_matmul_tiled(
    X_test: np.ndarray, X_train: np.ndarray, rows: int = 256, cols: int = 2048
) -> None:
    """The same product in cache-sized tiles, row blocks spread over threads, 1 BLAS thread each."""
    pt = np.ascontiguousarray(X_train.T)
    blas = [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]
    n_threads = min([_cpus(), *blas])

    def work(part: np.ndarray) -> None:
        buf = np.empty(rows * cols, dtype=part.dtype)
        for lo in range(0, part.shape[0], rows):
            xb = part[lo : lo + rows]
            for c in range(0, pt.shape[1], cols):
                p = pt[:, c : c + cols]
                np.matmul(xb, p, out=buf[: xb.shape[0] * p.shape[1]].reshape(xb.shape[0], -1))

    parts = np.array_split(X_test, 4 * n_threads)
    with threadpool_limits(1, user_api="blas"), ThreadPoolExecutor(n_threads) as pool:
        list(pool.map(work, parts))


def _cpus() -> int:
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def main(
    n_train: int = 100_000,
    n_test: int = 100_000,
    n_features: int = 32,
    n_classes: int = 8,
    repeat: int = 3,
    seed: int = 0,
) -> list[dict]:
    """Measure and print a markdown table; returns the rows."""
    X_train, y_train, X_test, y_test = make_data(n_train, n_test, n_features, n_classes, seed)
    pnn64 = PNNClassifier(spread="auto").fit(X_train, y_train)
    spread = pnn64.spread_
    results = []
    for threads, dtype in itertools.product(sorted({1, _cpus()}), ("float64", "float32")):
        Xtr, Xte = X_train.astype(dtype), X_test.astype(dtype)
        pnn = PNNClassifier(spread=spread, dtype=dtype).fit(X_train, y_train)
        knn = KNeighborsClassifier(n_neighbors=1, algorithm="brute").fit(Xtr, y_train)
        # interleaved repeats, best of each: load drifts on a shared machine
        # hit every method alike
        runs = {
            "pnn": lambda pnn=pnn: pnn.predict(X_test),
            "knn": lambda knn=knn, Xte=Xte: knn.predict(Xte),
            "blocks": lambda Xte=Xte, Xtr=Xtr: bare_matmul(Xte, Xtr),
            "tiled": lambda Xte=Xte, Xtr=Xtr: bare_matmul_tiled(Xte, Xtr),
        }
        with threadpool_limits(threads, user_api="blas"):
            header = machine()
            best = interleaved(runs, repeat)
        t_pnn, t_knn, t_blocks, t_tiled = (best[k] for k in runs)
        t_bare = min(t_blocks, t_tiled)
        acc_pnn = float(np.mean(pnn.predict(X_test[:2000]) == y_test[:2000]))
        acc_knn = float(np.mean(knn.predict(Xte[:2000]) == y_test[:2000]))
        results.append(
            {
                "threads": threads,
                "dtype": dtype,
                "pnn": t_pnn,
                "knn": t_knn,
                "bare": t_bare,
                "bare_blocks": t_blocks,
                "bare_tiled": t_tiled,
                "acc_pnn": acc_pnn,
                "acc_knn": acc_knn,
                "machine": header,
            }
        )
    pairs = n_train * n_test
    rows = [
        [
            r["threads"],
            r["dtype"],
            f"{r['pnn']:.2f}",
            f"{r['knn']:.2f}",
            f"{r['bare']:.2f} ({r['bare_blocks']:.2f} / {r['bare_tiled']:.2f})",
            f"{pairs / r['pnn'] / 1e9:.2f}",
            f"{pairs / r['knn'] / 1e9:.2f}",
            f"{pairs / r['bare'] / 1e9:.2f}",
            f"{r['knn'] / r['pnn']:.2f}",
            f"{r['pnn'] / r['bare']:.2f}",
            f"{r['acc_pnn']:.3f} / {r['acc_knn']:.3f}",
        ]
        for r in results
    ]
    print(
        f"PNN predict, {n_train:,} training x {n_test:,} test arrays of {n_features} features, "
        f"{n_classes} classes, spread {spread:.3g} (auto); times in s, rates in 1e9 pairs/s; "
        f"{results[-1]['machine']}\n"
    )
    print(
        markdown_table(
            [
                "BLAS threads",
                "dtype",
                "PNN",
                "1-NN brute",
                "bare matmul (blocks / tiles)",
                "PNN rate",
                "1-NN rate",
                "matmul rate",
                "1-NN / PNN (goal >= 1)",
                "PNN / matmul (goal <= 2)",
                "accuracy PNN / 1-NN",
            ],
            rows,
        )
    )
    return results


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--train", type=int, default=100_000)
    parser.add_argument("--test", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    main(args.train, args.test, repeat=args.repeat)
