"""Throughput of the streaming line scanner on a synthetic belt of 2048-pixel lines.

End to end (segmentation, features, classification, defects) in lines per
second, against scipy.ndimage.label (8-connected) on the same image as the
yardstick, on one core. Run::

    .venv/bin/python benchmarks/bench_scanner.py            # full size
    .venv/bin/python benchmarks/bench_scanner.py --lines 2000 --repeat 1

The belt holds objects of the four thesis classes (circumradius 6-20 px, a
third damaged) at random places; ``--per-1000`` sets how many objects pass per
1000 lines over the whole width (the per-object work, ~0.5 ms, dominates on
busy belts; segmentation dominates on quiet ones).
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np
from scipy import ndimage

from tentaclass.scanner import LineScanner, default_model
from tentaclass.scanner.simulate import make_objects


def make_test_belt(
    n_lines: int, width: int = 2048, per_1000: float = 10.0, seed: int = 0
) -> tuple[np.ndarray, int]:
    """A belt with about ``per_1000`` objects per 1000 lines, from a pool of 256 objects."""
    rng = np.random.default_rng(seed)
    pool = make_objects(
        256, shape=(44, 44), radius_range=(6.0, 20.0), damaged_fraction=0.33, random_state=seed
    )
    crops = []
    for g in pool.grids:
        rows = np.nonzero(g.any(axis=1))[0]
        cols = np.nonzero(g.any(axis=0))[0]
        crops.append(g[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1])
    image = np.zeros((n_lines, width), dtype=bool)
    lanes = width // 48
    busy = np.zeros((lanes, n_lines + 4), dtype=bool)  # rows taken in each lane
    placed = 0
    for _ in range(round(n_lines * per_1000 / 1000)):
        crop = crops[int(rng.integers(len(crops)))]
        h, w = crop.shape
        for _attempt in range(10):
            lane = int(rng.integers(lanes))
            top = int(rng.integers(0, n_lines - h))
            if not busy[lane, max(top - 2, 0) : top + h + 2].any():
                break
        else:
            continue
        busy[lane, top : top + h] = True
        left = lane * 48 + 2
        image[top : top + h, left : left + w] = crop
        placed += 1
    return image, placed


def _best(fn, repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main(
    n_lines: int = 50_000,
    width: int = 2048,
    per_1000: float = 10.0,
    chunk_rows: int = 4096,
    repeat: int = 3,
    seed: int = 0,
) -> dict:
    """Run the benchmark; print and return a dict of the numbers."""
    image, n_objects = make_test_belt(n_lines, width, per_1000, seed)
    model = default_model()
    structure = np.ones((3, 3), dtype=bool)
    found = []

    def run_scanner() -> None:
        scanner = LineScanner(width, model, max_height=256)
        out = []
        for i in range(0, n_lines, chunk_rows):
            out += scanner.feed(image[i : i + chunk_rows])
        out += scanner.close()
        found[:] = out

    def run_label() -> None:
        ndimage.label(image, structure)

    t_scan = _best(run_scanner, repeat)
    t_label = _best(run_label, repeat)
    result = {
        "lines": n_lines,
        "width": width,
        "objects_placed": n_objects,
        "objects_found": len(found),
        "rejected": sum(not o.accept for o in found),
        "chunk_rows": chunk_rows,
        "scanner_lines_per_s": round(n_lines / t_scan),
        "scanner_objects_per_s": round(len(found) / t_scan),
        "ndimage_label_lines_per_s": round(n_lines / t_label),
        "scanner_over_label_time": round(t_scan / t_label, 2),
        "cpu_count": os.cpu_count(),
    }
    print(json.dumps(result, indent=2))
    return result


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--lines", type=int, default=50_000)
    p.add_argument("--width", type=int, default=2048)
    p.add_argument("--per-1000", type=float, default=10.0)
    p.add_argument("--chunk-rows", type=int, default=4096)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args()
    main(a.lines, a.width, a.per_1000, a.chunk_rows, a.repeat, a.seed)
