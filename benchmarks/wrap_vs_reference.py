"""Wrap throughput of this tree against a reference tree, interleaved on one machine.

Run: ``python benchmarks/wrap_vs_reference.py REFERENCE_SRC [--outlines 100]
[--rounds 3] [--n 64] [--modes taut hug]``. Two worker processes, one importing
``tentaclass`` from this tree and one from ``REFERENCE_SRC``, run
:func:`bench_wrap.main`'s loop in turn (one BLAS thread each); a load drift
then hits both alike, so the ratio of their best rounds is meaningful even
when the absolute speeds are not. The cache of supports is emptied before
each round: every round pays for building them, as a first call does.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _worker() -> None:
    from threadpoolctl import threadpool_limits

    sys.path.insert(0, str(HERE))
    import bench_wrap

    from tentaclass.wrapping import _surface

    with threadpool_limits(1):
        for line in sys.stdin:
            mode, n, n_outlines = line.split()
            _surface._build.cache_clear()  # every round builds every support
            with contextlib.redirect_stdout(io.StringIO()):
                rows = bench_wrap.main(n_outlines=int(n_outlines), ns=(int(n),), modes=(mode,))
                rows[0]["machine"] = bench_wrap.machine()
            print(json.dumps(rows[0]), flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reference", help="the reference tree's src directory")
    ap.add_argument("--outlines", type=int, default=100)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--n", type=int, default=64)
    ap.add_argument("--modes", nargs="+", default=["taut", "hug"])
    args = ap.parse_args()
    sys.path.insert(0, str(HERE))
    from _timing import markdown_table

    trees = {"this": str(HERE.parent / "src"), "reference": str(Path(args.reference).resolve())}
    procs = {}
    for name, src in trees.items():
        env = dict(os.environ, PYTHONPATH=src, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
        procs[name] = subprocess.Popen(
            [sys.executable, __file__, "--worker"], stdin=subprocess.PIPE,
            stdout=subprocess.PIPE, text=True, env=env,
        )  # fmt: skip
    best: dict[tuple[str, str], float] = {}
    best_cpu: dict[tuple[str, str], float] = {}
    seen = ""

    try:
        for mode in args.modes:
            for _ in range(args.rounds):
                for name, proc in procs.items():
                    assert proc.stdin is not None and proc.stdout is not None
                    proc.stdin.write(f"{mode} {args.n} {args.outlines}\n")
                    proc.stdin.flush()
                    row = json.loads(proc.stdout.readline())
                    key = (mode, name)
                    best[key] = max(best.get(key, 0.0), row["wraps_per_s"])
                    best_cpu[key] = max(best_cpu.get(key, 0.0), row["wraps_per_cpu_s"])
                    seen = row["machine"]
    finally:
        for proc in procs.values():
            if proc.stdin is not None:
                proc.stdin.close()
            proc.wait()
    print(f"n = {args.n}, {args.outlines} outlines x 100 starts, best of {args.rounds} "
          f"interleaved rounds; a worker's {seen}")  # fmt: skip
    print(markdown_table(
        ["mode", "this (wraps/s)", "reference (wraps/s)", "ratio",
         "this (wraps/CPU s)", "reference (wraps/CPU s)", "ratio (CPU)"],
        [[m, f"{best[(m, 'this')]:,.0f}", f"{best[(m, 'reference')]:,.0f}",
          f"{best[(m, 'this')] / best[(m, 'reference')]:.2f}",
          f"{best_cpu[(m, 'this')]:,.0f}", f"{best_cpu[(m, 'reference')]:,.0f}",
          f"{best_cpu[(m, 'this')] / best_cpu[(m, 'reference')]:.2f}"] for m in args.modes],
    ))  # fmt: skip


if __name__ == "__main__":
    if sys.argv[1:] == ["--worker"]:
        _worker()
    else:
        main()
