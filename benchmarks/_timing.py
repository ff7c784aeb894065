"""Timing helper shared by the benchmark scripts."""

from __future__ import annotations

import time
from collections.abc import Callable


def best_time(func: Callable[[], object], repeat: int = 3) -> float:
    """Best wall time of ``repeat`` calls, in seconds (the least disturbed run)."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        func()
        best = min(best, time.perf_counter() - t0)
    return best


def markdown_table(header: list[str], rows: list[list[object]]) -> str:
    """A GitHub markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def interleaved(
    runs: dict[str, Callable[[], object]],
    repeat: int = 3,
    clock: Callable[[], float] = time.perf_counter,
) -> dict[str, float]:
    """Best time of each function over ``repeat`` rounds that call them in turn.

    Interleaving makes load drifts on a shared machine hit every method alike,
    so the ratios of the minima are meaningful even when absolute times are not.
    ``clock`` is wall time by default (``time.process_time``: CPU time).
    """
    best = dict.fromkeys(runs, float("inf"))
    for _ in range(repeat):
        for key, func in runs.items():
            t0 = clock()
            func()
            best[key] = min(best[key], clock() - t0)
    return best


def machine() -> str:
    """BLAS threads in use, CPUs and the load averages, for the header of a result."""
    import os

    from threadpoolctl import threadpool_info

    blas = [f"{i['internal_api']} {i['num_threads']}" for i in threadpool_info()]
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    return (
        f"BLAS threads: {'; '.join(blas) or 'none'}; CPUs: {os.cpu_count()}; "
        f"load average (1, 5, 15 min): {load}"
    )
