"""Peak memory of the whole 10^7-array featurise + predict job on 2 Dask worker processes.

The job as a user runs it, in a fresh process: load a saved model
(``tentaclass.load_model``), start the ``LocalCluster`` of 2 single-threaded
worker processes that ``--scheduler local`` starts, read the Parquet files
with ``tentaclass.read_parquet_rows`` (one block per four row groups of 65 536
arrays, read one row group at a time with pyarrow in the same task as
``model.predict`` on the dask array), count the labels per class. Nothing else
is loaded on the workers: they import what unpickling the tasks needs
(the model's classes, numpy, pyarrow) and nothing more.

Sampled every 50 ms: the resident set (RSS) of every worker process and of
this driver process (which holds the client, the scheduler and the nannies),
and every 0.5 s their proportional set
(PSS: each shared page divided among the processes sharing it) and unique set
(USS: pages no other process shares). Summing RSS counts the shared library
pages once per process, so the summed RSS overstates the machine's memory use;
the summed USS leaves them out altogether; the summed PSS divides them among
all processes that map them (on a machine running other Python processes from
the same environment, those too). "USS + shared" adds the shared pages of the
largest process once to the summed USS: an estimate of what the job takes.

The data and the model are made first in a separate process (so that the
wrap generator used for the training arrays is not loaded here). Run::

    .venv/bin/python benchmarks/bench_dask_memory.py                   # 10^7 arrays
    .venv/bin/python benchmarks/bench_dask_memory.py --arrays 1000000 --files 4
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import psutil

MiB = 2**20


def prepare(workdir: Path, arrays: int, files: int) -> None:
    """Parquet files and a saved FourierClassifier (run in a child process)."""
    sys.path.insert(0, str(Path(__file__).parent))
    from bench_dask import N_JOINTS, make_parquet

    import tentaclass as tc
    from tentaclass.datasets import reference_tentacle

    make_parquet(workdir / "parquet", arrays, files)
    X, y = reference_tentacle(N_JOINTS, n_starts=10, return_X_y=True)
    model = tc.FourierClassifier(detrend=True, spread=0.5).fit(X, y)
    tc.save_model(model, workdir / "model.tcm")


class Memory:
    """Peak RSS / USS of this process and of its child processes, sampled in a thread."""

    def __init__(self) -> None:
        self.me = psutil.Process()
        self.peak: dict[str, float] = {}
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def sample(self, uss: bool = True) -> dict[str, float]:
        kids = self.me.children(recursive=True)
        out = {"driver_rss": 0.0, "workers_rss": 0.0, "one_worker_rss": 0.0}
        if uss:
            out.update(driver_uss=0.0, workers_uss=0.0, driver_pss=0.0, workers_pss=0.0)
            shared = 0.0
        for proc in [self.me, *kids]:
            try:
                rss = proc.memory_info().rss / MiB
                full = proc.memory_full_info() if uss else None
            except psutil.Error:
                continue
            who = "driver" if proc is self.me else "workers"
            out[f"{who}_rss"] += rss
            if full is not None:
                out[f"{who}_uss"] += full.uss / MiB
                out[f"{who}_pss"] += full.pss / MiB
                shared = max(shared, (full.rss - full.uss) / MiB)
            if who == "workers":
                out["one_worker_rss"] = max(out["one_worker_rss"], rss)
        out["total_rss"] = out["driver_rss"] + out["workers_rss"]
        if uss:
            out["total_pss"] = out["driver_pss"] + out["workers_pss"]
            out["total_uss"] = out["driver_uss"] + out["workers_uss"]
            # the largest process's shared pages, counted once (the others map much the same)
            out["total_uss_plus_shared"] = out["total_uss"] + shared
        out["n_children"] = len(kids)
        return out

    def _run(self) -> None:
        tick = 0
        while not self._stop.is_set():
            for key, value in self.sample(uss=tick % 10 == 0).items():
                self.peak[key] = max(self.peak.get(key, 0.0), value)
            tick += 1
            time.sleep(0.05)

    def __enter__(self) -> Memory:
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()


def job(workdir: Path, files: int, workers: int) -> dict:
    from distributed import Client

    import tentaclass as tc
    from tentaclass._dask import local_cluster

    mem = Memory()
    start = mem.sample()
    model = tc.load_model(workdir / "model.tcm")
    paths = [workdir / "parquet" / f"log{i:03d}.parquet" for i in range(files)]
    with (
        local_cluster(workers) as cluster,
        Client(cluster) as client,
    ):
        idle = mem.sample()
        t = time.perf_counter()
        with mem:
            rows = tc.read_parquet_rows(paths)
            labels = model.predict(rows)
            counts = client.compute([(labels == c).sum() for c in model.classes_], sync=True)
        seconds = time.perf_counter() - t
        after = mem.sample()
    return {
        "arrays": int(rows.shape[0]),
        "blocks": rows.numblocks[0],
        "block_rows": max(rows.chunks[0]),
        "counted": int(sum(counts)),
        "seconds": seconds,
        "workers": workers,
        "driver_before_cluster": start,
        "idle": idle,
        "peak": mem.peak,
        "after": after,
        "load_average": os.getloadavg(),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--arrays", type=int, default=10_000_000)
    ap.add_argument("--files", type=int, default=20)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--workdir", type=Path, default=Path(tempfile.gettempdir()) / "tc-bench-dask")
    ap.add_argument("--prepare", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    if args.prepare:
        prepare(args.workdir, args.arrays, args.files)
        return
    subprocess.run(
        [sys.executable, __file__, "--prepare", "--arrays", str(args.arrays),
         "--files", str(args.files), "--workdir", str(args.workdir)],
        check=True,
    )  # fmt: skip
    res = job(args.workdir, args.files, args.workers)
    peak, idle = res["peak"], res["idle"]
    print(
        f"{res['arrays']:,} arrays in {res['blocks']} blocks of <= {res['block_rows']:,} rows, "
        f"{res['seconds']:.1f} s, {res['workers']} workers, load average {res['load_average']}"
    )
    print(f"{'MiB':<28} {'idle':>8} {'peak':>8}")
    for key in ("one_worker_rss", "workers_rss", "workers_pss", "workers_uss", "driver_rss",
                "driver_pss", "driver_uss", "total_rss", "total_pss", "total_uss",
                "total_uss_plus_shared"):  # fmt: skip
        print(f"{key:<28} {idle[key]:8.0f} {peak[key]:8.0f}")
    before = res["driver_before_cluster"]["driver_rss"]
    print(f"driver before the cluster started: {before:.0f} MiB RSS")
    if args.json is not None:
        args.json.write_text(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
