"""Throughput of the streaming line scanner on belts of 2048-pixel lines, side by side.

End to end (segmentation, features, classification, defect check) in lines
per second, fed in 4096-row chunks and one row per call (as a camera delivers
them; with ``latency=256``, so that objects completed within 256 rows are
inspected in one batch), against, on the same belt image and in the same run (interleaved
repeats, the best of each):

- ``scipy.ndimage.label`` (8-connected), which only labels: the yardstick;
- an OpenCV pipeline: ``connectedComponentsWithStats``, then per object
  ``findContours``, ``convexHull``, ``minAreaRect``, ``minEnclosingCircle``,
  ``convexityDefects``, hole count and hull Fourier features, and one batch
  classification with the same model;
- a scikit-image pipeline: ``label`` + ``regionprops`` (convex hull,
  solidity, Euler number, axes) and outline Fourier features, same classifier.

"Segmentation alone" is the scanner with every object below ``min_area``:
the run-length kernel without any per-object work.

Belts: ``sparse`` (10 objects of 12-40 px per 1000 lines), ``busy`` (150
objects of 12-30 px on 4000 lines) and ``crowded`` (2500 objects of 8-16 px
on 4000 lines, where per-object work dominates). Each belt runs with BLAS
limited to one thread and to all CPUs (threadpoolctl; ``--threads`` to
choose); the header gives the machine's load. Run::

    .venv/bin/python benchmarks/bench_scanner.py
    .venv/bin/python benchmarks/bench_scanner.py --belts busy --repeat 2
    .venv/bin/python benchmarks/bench_scanner.py --cpu-time  # on a loaded machine
"""

from __future__ import annotations

import argparse
import itertools
import os
import sys
import time
from pathlib import Path

import numpy as np
from scipy import ndimage
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).parent))
from _timing import interleaved, machine, markdown_table

from tentaclass.scanner import LineScanner, default_model
from tentaclass.scanner.descriptors import measure
from tentaclass.scanner.simulate import make_objects

BELTS = {
    # name: (lines, objects, circumradius range)
    "sparse": (20_000, 200, (6.0, 20.0)),
    "busy": (4_000, 150, (6.0, 15.0)),
    "crowded": (4_000, 2_500, (4.0, 8.0)),
}


def make_test_belt(
    n_lines: int,
    n_objects: int,
    radius_range: tuple[float, float],
    width: int = 2048,
    seed: int = 0,
) -> tuple[np.ndarray, int]:
    """A belt with ``n_objects`` from a pool of 256 (a third damaged), in lanes, not touching."""
    rng = np.random.default_rng(seed)
    size = int(2 * radius_range[1] + 6)
    pool = make_objects(
        256, shape=(size, size), radius_range=radius_range, damaged_fraction=0.33, random_state=seed
    )
    crops = []
    for g in pool.grids:
        rows = np.nonzero(g.any(axis=1))[0]
        cols = np.nonzero(g.any(axis=0))[0]
        crops.append(g[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1])
    lane_w = max(c.shape[1] for c in crops) + 3
    image = np.zeros((n_lines, width), dtype=bool)
    lanes = width // lane_w
    free = np.zeros(lanes, dtype=int)  # next free row of each lane
    placed = 0
    for _ in range(n_objects):
        crop = crops[int(rng.integers(len(crops)))]
        h, w = crop.shape
        lane = int(np.argmin(free + rng.integers(0, 8, lanes)))
        spacing = min(n_lines * lanes // n_objects, n_lines - 2 * h) - h
        top = int(free[lane] + rng.integers(2, 2 + max(4, spacing)))
        if top + h >= n_lines:
            continue
        left = lane * lane_w + 1
        image[top : top + h, left : left + w] = crop
        free[lane] = top + h + 2
        placed += 1
    return image, placed


def _hull_fourier(points: np.ndarray, n_harmonics: int = 8) -> np.ndarray:
    z = points[:, 0] + 1j * points[:, 1]
    spec = np.abs(np.fft.fft(z - z.mean(), 64 if len(z) < 64 else len(z)))
    out = spec[1 : n_harmonics + 1]
    return out / (spec[1] + 1e-12) if out.size == n_harmonics else np.resize(out, n_harmonics)


def opencv_pipeline(image: np.ndarray, model, n_harmonics: int) -> np.ndarray:
    """Label, measure each object's contour, hull and defects with OpenCV; classify."""
    import cv2

    n, lab, stats, _ = cv2.connectedComponentsWithStats(
        image.view(np.uint8), connectivity=8, ltype=cv2.CV_32S
    )
    feats = []
    for k in range(1, n):
        x, y, w, h, area = stats[k]
        m = (lab[y : y + h, x : x + w] == k).astype(np.uint8)
        contours, hier = cv2.findContours(np.pad(m, 1), cv2.RETR_CCOMP, cv2.CHAIN_APPROX_NONE)
        outer = max(contours, key=len)
        hull = cv2.convexHull(outer)
        (_, _), (rw, rh), _ = cv2.minAreaRect(hull)
        _, radius = cv2.minEnclosingCircle(hull)
        hull_area = cv2.contourArea(hull) + 0.5
        perimeter = cv2.arcLength(hull, True) + 1e-9
        holes = int((hier[0][:, 3] != -1).sum()) if hier is not None else 0
        deepest = 0.0
        if len(outer) > 3:
            try:
                d = cv2.convexityDefects(outer, cv2.convexHull(outer, returnPoints=False))
                deepest = (
                    float(d.reshape(-1, 4)[:, 3].max()) / 256 if d is not None and d.size else 0.0
                )
            except cv2.error:
                pass
        long, short = max(rw, rh) + 1, min(rw, rh) + 1
        feats.append(
            [
                hull_area / (long * short),
                short / long,
                4 * np.pi * hull_area / perimeter**2,
                hull_area / (np.pi * (radius + 0.5) ** 2),
                1 / np.sqrt(area) + 0 * holes + 0 * deepest,
                *_hull_fourier(hull[:, 0, :].astype(float), n_harmonics),
            ]
        )
    return model.predict_features_proba(np.asarray(feats))


def skimage_pipeline(image: np.ndarray, model, n_harmonics: int) -> np.ndarray:
    """Label and measure with scikit-image regionprops (hull, Euler number, axes); classify."""
    from skimage.measure import find_contours, label, regionprops

    feats = []
    for p in regionprops(label(image, connectivity=2)):
        long = p.axis_major_length + 1
        short = p.axis_minor_length + 1
        outline = find_contours(np.pad(p.image_filled, 1).astype(float), 0.5)
        ring = max(outline, key=len)
        feats.append(
            [
                p.solidity,
                short / long,
                p.extent,
                p.eccentricity,
                1 / np.sqrt(p.area) + 0 * p.euler_number + 0 * p.orientation,
                *_hull_fourier(ring[:, ::-1], n_harmonics),
            ]
        )
    return model.predict_features_proba(np.asarray(feats))


def _on_cpu(func, key: str, best: dict[str, float]):
    """``func`` recording its best CPU time (all threads of the process) under ``key``."""

    def timed() -> None:
        t0 = time.process_time()
        func()
        best[key] = min(best[key], time.process_time() - t0)

    return timed


def main(
    belts: tuple[str, ...] = ("sparse", "busy", "crowded"),
    repeat: int = 3,
    chunk_rows: int = 4096,
    seed: int = 0,
    latency: int = 256,
    threads: tuple[int, ...] | None = None,
    cpu_time: bool = False,
) -> list[dict]:
    """Run the benchmark; print a markdown table and return its rows.

    ``threads``: BLAS thread limits to run each belt with; default 1 and all CPUs.
    ``cpu_time``: time by the process's CPU time instead of the wall clock (on
    a loaded machine, what each method costs, free of the time spent waiting
    for a core; rates are then per CPU second).
    """
    if threads is None:
        threads = tuple(sorted({1, os.cpu_count() or 1}))
    model = default_model()
    n_harmonics = model.features([measure(np.ones((3, 3), dtype=bool))]).shape[1] - 5
    results = []
    for n_threads, name in itertools.product(threads, belts):
        with threadpool_limits(n_threads, user_api="blas"):
            header = machine()
            n_lines, n_objects, radii = BELTS[name]
            image, placed = make_test_belt(n_lines, n_objects, radii, seed=seed)
            width = image.shape[1]
            found: list = []

            def scanner(
                step: int, image=image, width=width, found=found, min_area: int = 1
            ) -> None:
                s = LineScanner(
                    width,
                    model,
                    max_height=256,
                    min_area=min_area,
                    latency=latency if step == 1 else 0,
                )
                out = []
                if step == 1:
                    for row in image:
                        out += s.feed(row)
                else:
                    for i in range(0, image.shape[0], step):
                        out += s.feed(image[i : i + step])
                found[:] = out + s.close()

            runs = {
                "chunks": lambda: scanner(chunk_rows),
                "one_row": lambda: scanner(1),
                # every object below min_area: segmentation alone, nothing inspected
                "segment": lambda: scanner(chunk_rows, found=[], min_area=10**9),
                "label": lambda image=image: ndimage.label(image, np.ones((3, 3), bool)),
                "opencv": lambda image=image: opencv_pipeline(image, model, n_harmonics),
                "skimage": lambda image=image: skimage_pipeline(image, model, n_harmonics),
            }
            if cpu_time:
                best = dict.fromkeys(runs, float("inf"))
                timed = {k: _on_cpu(f, k, best) for k, f in runs.items()}
                interleaved(timed, repeat)
            else:
                best = interleaved(runs, repeat)
            rate = {k: n_lines / t for k, t in best.items()}
            results.append(
                {
                    "threads": n_threads,
                    "belt": name,
                    "lines": n_lines,
                    "objects": len(found),
                    "placed": placed,
                    **{f"{k}_lines_per_s": round(v) for k, v in rate.items()},
                    "us_per_object": 1e6 * best["chunks"] / max(len(found), 1),
                }
            )
    clock = "CPU time" if cpu_time else "wall clock"
    print(f"LineScanner, lines of 2048 px, end to end ({clock}); {header}\n")
    rows = [
        [
            r["threads"],
            r["belt"],
            f"{r['lines']:,} / {r['objects']:,}",
            f"{r['chunks_lines_per_s']:,}",
            f"{r['one_row_lines_per_s']:,}",
            f"{r['segment_lines_per_s']:,}",
            f"{r['label_lines_per_s']:,}",
            f"{r['chunks_lines_per_s'] / r['label_lines_per_s']:.2f}",
            f"{r['one_row_lines_per_s'] / r['label_lines_per_s']:.2f}",
            f"{r['segment_lines_per_s'] / r['label_lines_per_s']:.2f}",
            f"{r['chunks_lines_per_s'] / r['opencv_lines_per_s']:.2f}",
            f"{r['chunks_lines_per_s'] / r['skimage_lines_per_s']:.2f}",
            f"{r['us_per_object']:.0f}",
        ]
        for r in results
    ]
    print(
        markdown_table(
            [
                "BLAS threads",
                "belt",
                "lines / objects",
                f"scanner, {chunk_rows}-row feeds (lines/s)",
                f"scanner, 1-row feeds (latency {latency} rows)",
                "segmentation alone",
                "ndimage.label",
                "chunks / label",
                "1-row / label",
                "segmentation / label",
                "scanner / OpenCV",
                "scanner / skimage",
                "us per object (all included)",
            ],
            rows,
        )
    )
    return results


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--belts", nargs="+", default=list(BELTS), choices=list(BELTS))
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--chunk-rows", type=int, default=4096)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--latency", type=int, default=256)
    p.add_argument("--threads", nargs="+", type=int, help="BLAS thread limits (default 1 and all)")
    p.add_argument("--cpu-time", action="store_true", help="time by CPU time, not the wall clock")
    a = p.parse_args()
    threads = tuple(a.threads) if a.threads else None
    main(tuple(a.belts), a.repeat, a.chunk_rows, a.seed, a.latency, threads, a.cpu_time)
