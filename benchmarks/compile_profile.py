"""Where a command's first run spends its numba compile time, kernel by kernel.

Runs a ``tentaclass`` command in this process with an empty numba cache (a
temporary ``NUMBA_CACHE_DIR``) and records every compilation through numba's
event API (``numba:compile``, with the ``numba:llvm_lock`` time inside it).
A kernel's compilation includes those of the kernels it calls, compiled first;
the table shows each kernel's own share (its *exclusive* CPU time: typing,
lowering and LLVM, the callees' compilations left out) and the part of it spent
in LLVM, which optimises and generates the machine code of the callees linked
into it again. Process CPU time is used, so a busy machine disturbs it less
than the wall clock.

Usage::

    python benchmarks/compile_profile.py wrap
    python benchmarks/compile_profile.py scan --simulate 5
    python benchmarks/compile_profile.py --top 10 wrap --mode hug

Everything after the options is the command line given to ``tentaclass``.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

from _timing import markdown_table

ROOT = Path(__file__).resolve().parents[1]


class _Recorder:
    """Listens to numba's compile and LLVM events; keeps one record per compilation."""

    def __init__(self) -> None:
        self.records: list[dict[str, Any]] = []
        self._stack: list[dict[str, Any]] = []
        self._llvm_start = 0.0

    def install(self) -> None:
        from numba.core import event

        recorder = self

        class Compile(event.Listener):
            def on_start(self, ev: Any) -> None:
                d = ev.data["dispatcher"]
                name = f"{d.py_func.__module__}.{d.py_func.__qualname__}"
                args = ", ".join(str(a) for a in ev.data["args"])
                recorder._stack.append(
                    {
                        "name": name,
                        "args": args,
                        "t0": time.process_time(),
                        "child": 0.0,
                        "llvm": 0.0,
                    }
                )

            def on_end(self, ev: Any) -> None:
                rec = recorder._stack.pop()
                cpu = time.process_time() - rec.pop("t0")
                rec["excl"] = cpu - rec.pop("child")
                recorder.records.append(rec)
                if recorder._stack:
                    recorder._stack[-1]["child"] += cpu

        class Llvm(event.Listener):
            def on_start(self, ev: Any) -> None:
                recorder._llvm_start = time.process_time()

            def on_end(self, ev: Any) -> None:
                if recorder._stack:
                    recorder._stack[-1]["llvm"] += time.process_time() - recorder._llvm_start

        event.register("numba:compile", Compile())
        event.register("numba:llvm_lock", Llvm())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--top", type=int, default=25, help="kernels listed (default 25)")
    parser.add_argument("command", nargs=argparse.REMAINDER, help="tentaclass arguments")
    opts = parser.parse_args()
    if not opts.command:
        parser.error("give a tentaclass command, e.g. 'wrap' or 'scan --simulate 5'")

    cache = tempfile.TemporaryDirectory(prefix="numba-cold-")
    os.environ["NUMBA_CACHE_DIR"] = cache.name
    sys.path.insert(0, str(ROOT / "src"))
    recorder = _Recorder()
    recorder.install()
    from tentaclass.cli.main import cli

    t0, c0 = time.perf_counter(), time.process_time()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
        cli(opts.command, prog_name="tentaclass")
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    cache.cleanup()

    recs = recorder.records
    total = sum(r["excl"] for r in recs)
    print(
        f"`tentaclass {' '.join(opts.command)}`, cold numba cache: {cpu:.1f} s CPU "
        f"({wall:.1f} s wall) for the command, {total:.1f} s CPU of it compiling "
        f"({sum(r['llvm'] for r in recs):.1f} s in LLVM), {len(recs)} compilations, "
        f"load average {os.getloadavg()[0]:.1f}\n"
    )
    by: dict[str, list[Any]] = defaultdict(lambda: [0, 0.0, 0.0, set()])
    for r in recs:
        row = by[r["name"]]
        row[0] += 1
        row[1] += r["excl"]
        row[2] += r["llvm"]
        row[3].add(r["args"])
    rows = [
        [name, n, len(sigs), f"{excl:.2f}", f"{llvm:.2f}"]
        for name, (n, excl, llvm, sigs) in sorted(by.items(), key=lambda kv: -kv[1][1])
    ]
    print(
        markdown_table(
            ["kernel", "compilations", "signatures", "own CPU (s)", "of it LLVM (s)"],
            rows[: opts.top],
        )
    )


if __name__ == "__main__":
    main()
