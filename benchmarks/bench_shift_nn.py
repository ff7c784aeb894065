"""ShiftNNClassifier predict per query against aeon's MiniRocket, side by side.

Goal: ``ShiftNNClassifier.predict`` at most 2x MiniRocket's ``predict`` time
per query, both fitted on the same training set. Data: periodic signals of
64 samples (the length of a 64-link chain's joint angles), ``--classes``
classes, each a random smooth closed curve's signal (8 harmonics, amplitudes
falling as 1/k) at a random cyclic shift, half of them mirrored, with
Gaussian noise of 0.3; ``--train`` training and ``--test`` query rows. Also
timed: the exhaustive search (``argmin`` of ``shift_distances``, an inverse
FFT per training signal and query), which ``predict`` answers identically.

Interleaved repeats, the best of each, with BLAS (and MiniRocket's numba
threads, ``n_jobs``) limited to 1 and to all CPUs (threadpoolctl); the
header gives the machine's load. Needs the ``bench`` extra (aeon)::

    .venv/bin/python benchmarks/bench_shift_nn.py [--train 1000] [--test 500]
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).parent))
from _timing import interleaved, machine, markdown_table

from tentaclass.classifiers import ShiftNNClassifier


def make_signals(
    n: int, n_classes: int = 10, n_points: int = 64, noise: float = 0.3, seed: int = 0
) -> tuple[np.ndarray, np.ndarray]:
    """Shifted, half mirrored, noisy copies of one smooth periodic signal per class."""
    shapes = np.random.default_rng(12345).normal(size=(n_classes, 8, 2)) / np.arange(1, 9)[:, None]
    rng = np.random.default_rng(seed)
    y = rng.integers(0, n_classes, n)
    t = 2 * np.pi * np.arange(n_points) / n_points
    k = np.arange(1, 9)[:, None]
    base = np.einsum("nk,kt->nt", shapes[y, :, 0], np.cos(k * t))
    base += np.einsum("nk,kt->nt", shapes[y, :, 1], np.sin(k * t))
    X = np.stack([np.roll(b, s) for b, s in zip(base, rng.integers(0, n_points, n), strict=True)])
    mirrored = rng.random(n) < 0.5
    X[mirrored] = X[mirrored, ::-1]
    return X + noise * rng.normal(size=X.shape), y


def main(n_train: int = 1000, n_test: int = 500, repeat: int = 3, n_classes: int = 10) -> list:
    """Measure and print a markdown table; returns its rows."""
    from aeon.classification.convolution_based import MiniRocketClassifier

    X_train, y_train = make_signals(n_train, n_classes, seed=0)
    X_test, y_test = make_signals(n_test, n_classes, seed=1)
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    rows = []
    for threads in sorted({1, cpus or 1}):
        with threadpool_limits(threads, user_api="blas"):
            header = machine()
            rocket = MiniRocketClassifier(random_state=0, n_jobs=threads).fit(
                X_train[:, None], y_train
            )
            shift = {
                s: ShiftNNClassifier(signal=s).fit(X_train, y_train) for s in ("turning", "raw")
            }
            runs = {
                "minirocket": lambda rocket=rocket: rocket.predict(X_test[:, None]),
                **{f"shift_{s}": (lambda c=c: c.predict(X_test)) for s, c in shift.items()},
                **{
                    f"exhaustive_{s}": (lambda c=c: np.argmin(c.shift_distances(X_test), axis=1))
                    for s, c in shift.items()
                },
            }
            best = interleaved(runs, repeat)
        acc_rocket = float(np.mean(rocket.predict(X_test[:, None]) == y_test))
        for s, c in shift.items():
            t_s, t_r, t_e = best[f"shift_{s}"], best["minirocket"], best[f"exhaustive_{s}"]
            rows.append(
                [
                    threads,
                    f'ShiftNNClassifier(signal="{s}")',
                    f"{1e3 * t_s / n_test:.3f}",
                    f"{1e3 * t_e / n_test:.3f}",
                    f"{1e3 * t_r / n_test:.3f}",
                    f"{t_s / t_r:.2f}",
                    f"{t_e / t_r:.2f}",
                    f"{np.mean(c.predict(X_test) == y_test):.3f} / {acc_rocket:.3f}",
                ]
            )
    print(
        f"ShiftNNClassifier vs MiniRocket predict, {n_train} training x {n_test} query signals "
        f"of 64 samples, {n_classes} classes; ms per query; best of {repeat}; {header}\n"
    )
    print(
        markdown_table(
            [
                "BLAS threads",
                "classifier",
                "predict (ms/query)",
                "exhaustive (ms/query)",
                "MiniRocket (ms/query)",
                "predict / MiniRocket (goal <= 2)",
                "exhaustive / MiniRocket",
                "accuracy ours / MiniRocket",
            ],
            rows,
        )
    )
    return rows


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--train", type=int, default=1000)
    p.add_argument("--test", type=int, default=500)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--classes", type=int, default=10)
    a = p.parse_args()
    main(a.train, a.test, a.repeat, a.classes)
