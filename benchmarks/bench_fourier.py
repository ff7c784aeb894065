"""Throughput of ``fourier_features`` against numpy.fft, a per-array loop and a bare matmul.

Run: ``.venv/bin/python benchmarks/bench_fourier.py [--arrays 1000000]``;
``--against OTHER/src`` also times another tree's ``fourier_features`` (its
``tentaclass/features/fourier.py`` on this tree's helpers) in the same rounds.
All rates come from one run on the same data, the best of interleaved repeats,
so their ratios are meaningful even on a busy machine; absolute numbers are
not. Each size is measured with BLAS limited to one thread and with all
threads (threadpoolctl); the header of each table gives the threads and the
machine's load.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _timing import best_time, interleaved, machine, markdown_table
from threadpoolctl import threadpool_limits

from tentaclass.features import fourier_features


def numpy_fft_batch(q: np.ndarray) -> np.ndarray:
    """Reference (a): cumulative sum, ramp, rfft over the whole batch."""
    n = q.shape[1]
    e = np.cumsum(q, axis=1) - 2 * np.pi * np.arange(1, n + 1) / n
    return np.abs(np.fft.rfft(e, axis=1)[:, 1 : n // 2 + 1])


def thesis_loop(q: np.ndarray) -> np.ndarray:
    """Reference (b): one array at a time, as the thesis's MATLAB code did."""
    n = q.shape[1]
    ramp = 2 * np.pi * np.arange(1, n + 1) / n
    out = np.empty((q.shape[0], n // 2))
    for i, row in enumerate(q):
        out[i] = np.abs(np.fft.fft(np.cumsum(row) - ramp))[1 : n // 2 + 1]
    return out


def other_fourier_features(src: str) -> Callable[..., np.ndarray]:
    """``fourier_features`` of another tree's ``fourier.py``, run on this tree's package."""
    path = Path(src) / "tentaclass" / "features" / "fourier.py"
    spec = importlib.util.spec_from_file_location("tentaclass.features._fourier_other", path)
    if spec is None or spec.loader is None:
        raise SystemExit(f"cannot load {path}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.fourier_features


def main(
    n_arrays: int = 1_000_000,
    ns: tuple[int, ...] = (16, 64, 256),
    loop_arrays: int = 20_000,
    repeat: int = 3,
    seed: int = 0,
    against: str | None = None,
) -> list[dict]:
    """Measure and print a markdown table; returns the rows."""
    rng = np.random.default_rng(seed)
    other = None if against is None else other_fourier_features(against)
    results = []
    for threads in (1, None):
        with threadpool_limits(threads, user_api="blas"):
            header = machine()
            rows = []
            for n in ns:
                q = 2 * np.pi / n + rng.normal(0, 0.05, (n_arrays, n))
                weights = rng.normal(size=(n, n))
                runs = {
                    "ours": lambda q=q: fourier_features(q),
                    "fft": lambda q=q: numpy_fft_batch(q),
                    "bare": lambda q=q, w=weights: q @ w,
                }
                if other is not None:
                    runs["other"] = lambda q=q: other(q)
                best = interleaved(runs, repeat)
                m = min(loop_arrays, n_arrays)
                loop = best_time(lambda q=q[:m]: thesis_loop(q), 1) * n_arrays / m
                np.testing.assert_allclose(
                    fourier_features(q[:100]), numpy_fft_batch(q[:100]), atol=1e-9
                )
                r = {"threads": threads or "all", "n": n, "loop": n_arrays / loop}
                r.update({k: n_arrays / t for k, t in best.items()})
                results.append(r)
                rows.append(
                    [
                        r["n"],
                        f"{r['ours']:,.0f}",
                        f"{r['fft']:,.0f}",
                        f"{r['loop']:,.0f}",
                        f"{r['bare']:,.0f}",
                        f"{r['ours'] / r['fft']:.2f}",
                        f"{r['ours'] / r['loop']:.0f}",
                        f"{r['bare'] / r['ours']:.2f}",
                    ]
                    + ([] if other is None else [f"{r['ours'] / r['other']:.2f}"])
                )
        print(
            f"\nfourier_features, {n_arrays:,} arrays per n (arrays/s; ratios from the same run); "
            f"{header}\n"
        )
        print(
            markdown_table(
                [
                    "n",
                    "fourier_features",
                    "numpy.fft batch",
                    "per-array loop",
                    "bare matmul",
                    "speed-up vs fft (goal >= 1)",
                    "speed-up vs loop",
                    "bare / ours (goal <= 2 at n=64)",
                ]
                + ([] if other is None else ["speed-up vs --against"]),
                rows,
            )
        )
    return results


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--arrays", type=int, default=1_000_000)
    parser.add_argument("--loop-arrays", type=int, default=20_000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--against", metavar="SRC", help="another tree's src folder to time too")
    args = parser.parse_args()
    main(args.arrays, loop_arrays=args.loop_arrays, repeat=args.repeat, against=args.against)
