"""Throughput on a Dask LocalCluster of 1 and of 2 worker processes: the scaling ratio.

Three jobs, each timed on both clusters in turn (min of interleaved repeats):

- wrap generation: ``wrap_many`` on a dask array of start points (64 links,
  taut, a 240-vertex wavy outline), chunks of 5 000 wraps;
- featurise + predict: 10^7 joint-angle arrays (16 joints) in Parquet files,
  streamed two ways: ``classify --files`` (one task per file, record batches
  of 65 536 arrays, label files written) and the library path
  (``read_parquet_rows`` -> ``FourierClassifier.predict`` on the dask array
  -> class counts, as one reduction per class, and as one reduction of all
  the counts: "predict, one count", one task per row group). The peak RSS
  of every worker process is sampled every 50 ms (workers that have run
  every job; ``bench_dask_memory.py`` measures the predict job alone on
  fresh workers);
- scanning belts: ``scan --files`` over 20 belt PBM files.

The clusters are the ones ``--scheduler local`` starts
(``tentaclass._dask.local_cluster``): worker processes of one thread each,
started with OMP/MKL/OPENBLAS_NUM_THREADS=1 (distributed's default
``pre-spawn-environ``) and glibc's malloc thresholds at 32 MiB; the
driver's BLAS is pinned to one thread with threadpoolctl. The machine's load
average is printed before and after: other processes on the cores spoil the
2-worker figure first. Run::

    .venv/bin/python benchmarks/bench_dask.py                      # full size
    .venv/bin/python benchmarks/bench_dask.py --arrays 1000000 --wraps 20000 --repeat 1
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import tempfile
import threading
import time
from pathlib import Path

import dask.array as da
import numpy as np
import psutil
import pyarrow as pa
import pyarrow.parquet as pq
from distributed import Client
from threadpoolctl import threadpool_limits

import tentaclass as tc
from tentaclass._dask import local_cluster
from tentaclass.cli._files import classify_files, scan_files
from tentaclass.datasets import reference_tentacle
from tentaclass.scanner.io import write_pbm
from tentaclass.scanner.simulate import make_belt

N_JOINTS = 16


def wavy_outline(n: int = 240) -> np.ndarray:
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = 3.0 + 0.4 * np.sin(5 * t) + 0.2 * np.cos(3 * t)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def make_parquet(folder: Path, n_arrays: int, n_files: int) -> list[Path]:
    """``n_files`` Parquet files of noisy reference wraps, 65 536 arrays per row group."""
    folder.mkdir(parents=True, exist_ok=True)
    X, _ = reference_tentacle(N_JOINTS, n_starts=16, return_X_y=True)
    rng = np.random.default_rng(0)
    per = n_arrays // n_files
    paths = []
    for i in range(n_files):
        path = folder / f"log{i:03d}.parquet"
        paths.append(path)
        if path.exists() and pq.ParquetFile(path).metadata.num_rows == per:
            continue
        with pq.ParquetWriter(
            path, pa.schema([(f"q{j}", pa.float64()) for j in range(N_JOINTS)])
        ) as w:
            for lo in range(0, per, 65536):
                m = min(65536, per - lo)
                A = X[rng.integers(0, len(X), m)] + rng.normal(0.0, 0.03, (m, N_JOINTS))
                w.write_table(pa.table({f"q{j}": A[:, j] for j in range(N_JOINTS)}))
    return paths


def make_belts(folder: Path, n_belts: int, objects: int) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for i in range(n_belts):
        path = folder / f"belt{i:02d}.pbm"
        if not path.exists():
            write_pbm(path, make_belt(objects, 512, random_state=i, lanes=4).image)


class RssMonitor:
    """Peak resident memory of the worker processes (sampled every 50 ms), and their CPU time."""

    def __init__(self, client: Client):
        self.procs = [psutil.Process(p) for p in client.run(os.getpid).values()]
        self.peak_one = self.peak_sum = self.peak_uss = 0
        self.idle = sum(p.memory_info().rss for p in self.procs)
        self.cpu = self.driver_cpu = 0.0
        self._driver = psutil.Process()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        tick = 0
        while not self._stop.is_set():
            rss, uss = [], []
            for p in self.procs:
                try:
                    rss.append(p.memory_info().rss)
                    if tick % 10 == 0:  # unique pages: slower to read, every 0.5 s
                        uss.append(p.memory_full_info().uss)
                except psutil.Error:
                    pass
            if rss:
                self.peak_one = max(self.peak_one, max(rss))
                self.peak_sum = max(self.peak_sum, sum(rss))
            if uss:
                self.peak_uss = max(self.peak_uss, sum(uss))
            tick += 1
            time.sleep(0.05)

    def _cpu(self) -> float:
        return sum(sum(p.cpu_times()[:2]) for p in self.procs)

    def _driver_cpu(self) -> float:
        return sum(self._driver.cpu_times()[:2])

    def __enter__(self) -> RssMonitor:
        self.cpu = -self._cpu()
        self.driver_cpu = -self._driver_cpu()
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        self._thread.join()
        self.cpu += self._cpu()
        self.driver_cpu += self._driver_cpu()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--arrays", type=int, default=10_000_000)
    ap.add_argument("--files", type=int, default=20)
    ap.add_argument("--cli-files", type=int, default=2, help="files for classify --files")
    ap.add_argument("--wraps", type=int, default=200_000)
    ap.add_argument("--belts", type=int, default=20)
    ap.add_argument("--belt-objects", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=2, help="for wraps and scan")
    ap.add_argument("--big-repeat", type=int, default=1, help="for the Parquet jobs")
    ap.add_argument("--workdir", type=Path, default=Path(tempfile.gettempdir()) / "tc-bench-dask")
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    threadpool_limits(1)
    load_before = os.getloadavg()
    t0 = time.perf_counter()
    parquet = make_parquet(args.workdir / "parquet", args.arrays, args.files)
    make_belts(args.workdir / "belts", args.belts, args.belt_objects)
    cli_dir = args.workdir / "cli"
    shutil.rmtree(cli_dir, ignore_errors=True)
    cli_dir.mkdir()
    for path in parquet[: args.cli_files]:
        (cli_dir / path.name).symlink_to(path)
    cli_arrays = args.arrays // args.files * args.cli_files
    print(f"data ready in {time.perf_counter() - t0:.1f} s", flush=True)
    X, y = reference_tentacle(N_JOINTS, n_starts=10, return_X_y=True)
    model = tc.FourierClassifier(detrend=True, spread=0.5).fit(X, y)
    outline = wavy_outline()
    starts = np.random.default_rng(1).uniform(0, 1, args.wraps)
    link = tc.closing_link_length(outline, 64)[0]

    def wraps(client):
        lazy = tc.wrap_many(outline, 64, link, starts=da.from_array(starts, chunks=5000))
        return int(client.compute(lazy.complete.sum()).result())

    def classify_cli(client, out):
        shutil.rmtree(out, ignore_errors=True)
        done = classify_files(str(cli_dir / "*.parquet"), out, client, model, N_JOINTS)
        return sum(n for _, _, n in done)

    def predict_lib(client):
        labels = model.predict(tc.read_parquet_rows(parquet))
        counts = client.compute([(labels == c).sum() for c in model.classes_], sync=True)
        return int(sum(counts))

    def predict_lib_one(client):
        labels = model.predict(tc.read_parquet_rows(parquet))
        counts = da.equal.outer(labels, model.classes_).sum(axis=0)
        return int(client.compute(counts, sync=True).sum())

    def scan(client, out):
        shutil.rmtree(out, ignore_errors=True)
        done = scan_files(
            str(args.workdir / "belts" / "*.pbm"),
            out,
            client,
            None,
            {"fmt": None, "width": None, "chunk_rows": 1024, "scanner": {}},
        )
        return sum(s["rows"] for s in done), sum(s["objects"] for s in done)

    clusters = {}
    for k in (1, 2):
        cluster = local_cluster(k)
        client = Client(cluster)
        client.run(lambda: __import__("tentaclass.cli.main"))
        clusters[k] = (cluster, client)
        # compile the wrap kernel and load everything once on every worker
        tc.wrap_many(
            outline, 64, link, starts=da.from_array(starts[: 200 * k], chunks=200)
        ).angles.compute()
        client.compute(
            tc.wrap_many(
                outline, 64, link, starts=da.from_array(starts[: 200 * k], chunks=200)
            ).angles
        ).result()
    times: dict[tuple[str, int], float] = {}
    rss: dict[tuple[str, int], tuple[int, int]] = {}
    cpu: dict[tuple[str, int], float] = {}
    driver: dict[tuple[str, int], float] = {}
    counts = {}
    for rep in range(max(args.repeat, args.big_repeat)):
        for k in (1, 2):
            _, client = clusters[k]
            jobs = [
                ("wraps", lambda c=client: wraps(c)),
                ("classify --files", lambda c=client, k=k: classify_cli(c, args.workdir / f"o{k}")),
                ("predict (library)", lambda c=client: predict_lib(c)),
                ("predict, one count", lambda c=client: predict_lib_one(c)),
                ("scan --files", lambda c=client, k=k: scan(c, args.workdir / f"s{k}")),
            ]
            for job, run in jobs:
                big = job in ("classify --files", "predict (library)", "predict, one count")
                if rep >= (args.big_repeat if big else args.repeat):
                    continue
                mon = RssMonitor(client)
                t = time.perf_counter()
                with mon:
                    counts[job] = run()
                dt = time.perf_counter() - t
                if dt < times.get((job, k), np.inf):
                    times[job, k], cpu[job, k], driver[job, k] = dt, mon.cpu, mon.driver_cpu
                if job != "wraps":
                    old = rss.get((job, k), (0, 0, 0, 0))
                    rss[job, k] = (
                        max(old[0], mon.peak_one),
                        max(old[1], mon.peak_sum),
                        max(old[2], mon.peak_uss),
                        mon.idle,
                    )
                print(
                    f"{job:<18} {k} worker(s): {dt:7.2f} s, worker CPU {mon.cpu:7.2f} s, "
                    f"driver CPU {mon.driver_cpu:6.2f} s",
                    flush=True,
                )
    for cluster, client in clusters.values():
        client.close()
        cluster.close()
    load_after = os.getloadavg()
    units = {
        "wraps": ("wraps/s", args.wraps),
        "classify --files": ("arrays/s", cli_arrays),
        "predict (library)": ("arrays/s", args.arrays),
        "predict, one count": ("arrays/s", args.arrays),
        "scan --files": ("belt rows/s", counts["scan --files"][0]),
    }
    rows = []
    for job, (unit, n) in units.items():
        r1, r2 = n / times[job, 1], n / times[job, 2]
        mem = rss.get((job, 2))
        rows.append(
            {
                "job": job,
                "unit": unit,
                "n": n,
                "rate_1": r1,
                "rate_2": r2,
                "ratio": r2 / r1,
                "seconds_1": times[job, 1],
                "seconds_2": times[job, 2],
                "worker_cpu_seconds_1": cpu[job, 1],
                "worker_cpu_seconds_2": cpu[job, 2],
                "driver_cpu_seconds_1": driver[job, 1],
                "driver_cpu_seconds_2": driver[job, 2],
                "rate_per_cpu_second": n / cpu[job, 1],
                "cpu_share_2": cpu[job, 2] / (2 * times[job, 2]),
                "peak_rss_worker_MiB": None if mem is None else mem[0] / 2**20,
                "peak_rss_all_workers_MiB": None if mem is None else mem[1] / 2**20,
                "peak_uss_all_workers_MiB": None if mem is None else mem[2] / 2**20,
                "idle_rss_all_workers_MiB": None if mem is None else mem[3] / 2**20,
            }
        )
    print(f"\nload average before {load_before}, after {load_after}, cores {os.cpu_count()}")
    print(f"check counts: {counts}")
    print(
        "\n| job | size | 1 worker | 2 workers | ratio | worker CPU s, 1 / 2 "
        "| driver CPU s, 1 / 2 | CPU share, 2 "
        "| per CPU-second | 2 workers: peak RSS one / all (idle all), peak USS all |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        mem = (
            "-"
            if r["peak_rss_worker_MiB"] is None
            else f"{r['peak_rss_worker_MiB']:.0f} / {r['peak_rss_all_workers_MiB']:.0f} "
            f"({r['idle_rss_all_workers_MiB']:.0f}), {r['peak_uss_all_workers_MiB']:.0f} MiB"
        )
        print(
            f"| {r['job']} | {r['n']:,} | {r['rate_1']:,.0f} {r['unit']} | "
            f"{r['rate_2']:,.0f} {r['unit']} | {r['ratio']:.2f}x | "
            f"{r['worker_cpu_seconds_1']:.1f} / {r['worker_cpu_seconds_2']:.1f} | "
            f"{r['driver_cpu_seconds_1']:.2f} / {r['driver_cpu_seconds_2']:.2f} | "
            f"{r['cpu_share_2']:.0%} | {r['rate_per_cpu_second']:,.0f} | {mem} |"
        )
    if args.json is not None:
        args.json.write_text(
            json.dumps(
                {"rows": rows, "load_before": load_before, "load_after": load_after}, indent=1
            )
        )


if __name__ == "__main__":
    main()
