"""Wraps per second on MPEG-7 outlines (resampled to <= 1000 vertices), n = 16, 64, 256.

Run: ``python benchmarks/bench_wrap.py``. Each outline is wrapped from many
start points in one ``wrap_many`` call (the batched entry point), with a link
length that wraps about one lap; the time includes building each outline's
support (convex hull / closing) and the Python around the compiled walk.
Wall time and the process's CPU time are both reported: on a loaded machine
the CPU time shows the speed of one core, the wall time what a user waits.
Falls back to the thesis's four shapes when the MPEG-7 data is absent.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import machine, markdown_table

from tentaclass import shapes
from tentaclass.wrapping import wrap_many

MPEG7 = (Path(__file__).resolve().parents[1] / "../shared/data/mpeg7-part-b").resolve()


def load_outlines(n_outlines: int, max_vertices: int) -> tuple[list[np.ndarray], str]:
    if MPEG7.is_dir():
        outlines, _, _ = shapes.load_mpeg7(MPEG7, max_vertices=max_vertices)
        step = max(1, len(outlines) // n_outlines)
        return outlines[::step][:n_outlines], "MPEG-7"
    base = [shapes.square(4), shapes.rectangle(6, 2), shapes.circle(2, 256),
            shapes.triangle(side=5)]  # fmt: skip
    return (base * n_outlines)[:n_outlines], "thesis shapes"


def main(
    n_outlines: int = 200,
    starts_per_outline: int = 100,
    ns: tuple[int, ...] = (16, 64, 256),
    modes: tuple[str, ...] = ("taut", "hug"),
    max_vertices: int = 1000,
    seed: int = 0,
) -> list[dict]:
    outlines, source = load_outlines(n_outlines, max_vertices)
    rng = np.random.default_rng(seed)
    perims = [float(np.sum(np.hypot(*(np.roll(o, -1, 0) - o).T))) for o in outlines]
    wrap_many(outlines[0], 8, perims[0] / 8, starts=[0.0, 0.5])  # compile / load the cache
    rows = []
    for mode in modes:
        for n in ns:
            starts = rng.uniform(0, 1, (len(outlines), starts_per_outline))
            t0, c0 = time.perf_counter(), time.process_time()
            done = 0
            for o, p, st in zip(outlines, perims, starts, strict=True):
                b = wrap_many(o, n, 0.95 * p / n, starts=st, mode=mode)
                done += int(b.complete.sum())
            dt, dc = time.perf_counter() - t0, time.process_time() - c0
            total = len(outlines) * starts_per_outline
            rows.append({"mode": mode, "n": n, "wraps": total, "seconds": dt,
                         "wraps_per_s": total / dt, "wraps_per_cpu_s": total / dc,
                         "complete": done / total})  # fmt: skip
    print(f"Wrap throughput on {len(outlines)} {source} outlines (<= {max_vertices} vertices),"
          f" {starts_per_outline} starts each, one core; {machine()}")  # fmt: skip
    print(markdown_table(
        ["mode", "n links", "wraps", "seconds", "wraps / s", "wraps / CPU s", "complete"],
        [[r["mode"], r["n"], r["wraps"], f"{r['seconds']:.2f}", f"{r['wraps_per_s']:,.0f}",
          f"{r['wraps_per_cpu_s']:,.0f}", f"{r['complete']:.1%}"] for r in rows],
    ))  # fmt: skip
    return rows


if __name__ == "__main__":
    main()
