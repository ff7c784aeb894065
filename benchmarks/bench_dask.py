"""Throughput on a Dask LocalCluster of 1 and of 2 worker processes: the scaling ratio.

Three jobs, each timed on both clusters in turn (min of interleaved repeats):

- wrap generation: ``wrap_many`` on a dask array of start points (64 links,
  taut, a 240-vertex wavy outline), chunks of 5 000 wraps;
- featurise + predict: 10^7 joint-angle arrays (16 joints) in Parquet files,
  streamed two ways: ``classify --files`` (one task per file, record batches
  of 65 536 arrays, label files written) and the library path
  (``read_parquet_rows`` -> ``FourierClassifier.predict`` on the dask array
  -> class counts, as one reduction per class, and as one reduction of all
  the counts: "predict, one count", one task per block of four row groups).
  The peak RSS of every worker process is sampled every 0.1 s (workers that
  have run every job; ``bench_dask_memory.py`` measures the predict job alone
  on fresh workers);
- scanning belts: ``scan --files`` over 20 belt PBM files.

The clusters are the ones ``--scheduler local`` starts
(``tentaclass._dask.local_cluster``, "tuned"): worker processes of one thread
each, started with OMP/MKL/OPENBLAS_NUM_THREADS=1 (distributed's default
``pre-spawn-environ``), glibc's malloc thresholds at 32 MiB and Dask's
periodic bookkeeping turned down; the driver's BLAS is pinned to one thread
with threadpoolctl. ``--compare`` also runs every job as before ("defaults":
Dask's own cluster settings, one block per row group, each handed whole to
the classifier), one setup's clusters
after the other's in each repeat, so that the overhead of the two can be
compared in one run.

Besides the times, each job reports where the CPU went: the worker processes,
and this driver process by thread (its event loop, where the scheduler, the
client's messages and the nannies run; its main thread, the client building
graphs; the memory sampler, kept out of both), the tasks the workers ran, the
scheduler's transitions and the bytes the workers sent each other. With
spare cores the driver's CPU costs nothing; with none (2 workers on 2 cores)
it is taken from the workers, so the scaling to expect is about
2 W1 / (W2 + D): W the workers' CPU seconds with 1 and 2 workers, D the
driver's with 2. The machine's load average is printed before and after:
other processes on the cores spoil the 2-worker figure first. Run::

    .venv/bin/python benchmarks/bench_dask.py --repeat 3 --big-repeat 2   # full size
    .venv/bin/python benchmarks/bench_dask.py --arrays 1000000 --wraps 20000 --repeat 1 \
        --workdir /tmp/tc-bench-dask-small --compare --jobs wraps "predict, one count"
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import shutil
import tempfile
import threading
import time
from pathlib import Path

import dask
import dask.array as da
import numpy as np
import psutil
import pyarrow as pa
import pyarrow.parquet as pq
from distributed import Client, LocalCluster
from threadpoolctl import threadpool_limits

import tentaclass as tc
from tentaclass._dask import BLOCK_ROWS, WORKER_MALLOC, local_cluster
from tentaclass.cli._files import classify_files, scan_files
from tentaclass.datasets import reference_tentacle
from tentaclass.scanner.io import write_pbm
from tentaclass.scanner.simulate import make_belt

N_JOINTS = 16

#: Seconds each cluster is watched with no job running.
IDLE_SECONDS = 3.0


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


def _worker_counters(dask_worker) -> tuple[int, int]:
    """Tasks a worker has run and bytes it has sent to other workers, so far."""
    return dask_worker.state.executed_count, dask_worker.transfer_outgoing_bytes_total


def _transitions(dask_scheduler) -> int:
    return dask_scheduler.transition_counter


class RssMonitor:
    """Peak resident memory of the worker processes (every 0.1 s; USS every 2 s), and the CPU split.

    CPU (user + system seconds) of the worker processes, and of this driver
    process by thread: its event loop ("loop": the scheduler, the client's
    messages and the nannies of both clusters share it), the main thread
    ("client": building and optimising graphs, the job's own code) and the
    sampler itself (left out of both). Also the tasks the workers ran, the
    bytes they sent each other and the scheduler's task transitions.
    """

    def __init__(self, client: Client):
        self.client = client
        self.procs = [psutil.Process(p) for p in client.run(os.getpid).values()]
        self.peak_one = self.peak_sum = self.peak_uss = 0
        self.idle = sum(p.memory_info().rss for p in self.procs)
        self.cpu = self.loop_cpu = self.client_cpu = self.other_cpu = self.sampler_cpu = 0.0
        self.driver_cpu = 0.0
        self.tasks = self.bytes = self.transitions = 0
        self._driver = psutil.Process()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True, name="rss-sampler")

    def _counters(self) -> tuple[int, int, int]:
        per = self.client.run(_worker_counters).values()
        return (sum(t for t, _ in per), sum(b for _, b in per),
                self.client.run_on_scheduler(_transitions))  # fmt: skip

    def _threads(self) -> dict[str, float]:
        names = {t.native_id: t.name for t in threading.enumerate()}
        out = {"loop": 0.0, "client": 0.0, "other": 0.0}
        for t in self._driver.threads():
            name = names.get(t.id, "")
            if name == self._thread.name:
                continue
            key = "client" if name == "MainThread" else "loop" if name == "IO loop" else "other"
            out[key] += t.user_time + t.system_time
        return out

    def _run(self) -> None:
        tick = 0
        start = time.thread_time()
        while not self._stop.is_set():
            rss, uss = [], []
            for p in self.procs:
                try:
                    rss.append(p.memory_info().rss)
                    if tick % 20 == 0:  # unique pages: slower to read, every 2 s
                        uss.append(p.memory_full_info().uss)
                except psutil.Error:
                    pass
            if rss:
                self.peak_one = max(self.peak_one, max(rss))
                self.peak_sum = max(self.peak_sum, sum(rss))
            if uss:
                self.peak_uss = max(self.peak_uss, sum(uss))
            tick += 1
            time.sleep(0.1)
        self.sampler_cpu = time.thread_time() - start

    def _cpu(self) -> float:
        return sum(sum(p.cpu_times()[:2]) for p in self.procs)

    def __enter__(self) -> RssMonitor:
        self._before = self._counters()
        self._threads0 = self._threads()
        self.cpu = -self._cpu()
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        self._thread.join()
        self.cpu += self._cpu()
        threads = self._threads()
        self.loop_cpu, self.client_cpu, self.other_cpu = (
            threads[k] - self._threads0.get(k, 0.0) for k in ("loop", "client", "other")
        )
        self.driver_cpu = self.loop_cpu + self.client_cpu + self.other_cpu
        after = self._counters()
        self.tasks, self.bytes, self.transitions = (
            a - b for a, b in zip(after, self._before, strict=True)
        )


def _whole_blocks() -> None:
    """A row-wise function gets each block whole, as before blocks were sliced."""
    import tentaclass._dask

    tentaclass._dask.SLICE_BYTES = 2**62


def make_cluster(k: int, setup: str) -> LocalCluster:
    """The cluster of ``--scheduler local`` ("tuned"), or one with Dask's own settings."""
    if setup == "tuned":
        return local_cluster(k)
    environ = {f"distributed.nanny.pre-spawn-environ.{e}": v for e, v in WORKER_MALLOC.items()}
    with dask.config.set(environ):
        return LocalCluster(n_workers=k, threads_per_worker=1, processes=True,
                            dashboard_address=":0", silence_logs=logging.ERROR)  # fmt: skip


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
    ap.add_argument(
        "--compare", action="store_true",
        help="also run every job as before: Dask's own cluster settings, one block per "
        "row group, blocks handed whole to the classifier (each repeat: one setup's "
        "clusters, then the other's)",
    )  # fmt: skip
    ap.add_argument("--jobs", nargs="+", default=None, help="a subset of the jobs, by name")
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
    setups = ["defaults", "tuned"] if args.compare else ["tuned"]
    block_rows = {"defaults": None, "tuned": BLOCK_ROWS}

    def wraps(client, setup):
        lazy = tc.wrap_many(outline, 64, link, starts=da.from_array(starts, chunks=5000))
        return int(client.compute(lazy.complete.sum()).result())

    def classify_cli(client, setup, out):
        shutil.rmtree(out, ignore_errors=True)
        done = classify_files(str(cli_dir / "*.parquet"), out, client, model)
        return sum(n for _, _, n in done)

    def predict_lib(client, setup):
        labels = model.predict(tc.read_parquet_rows(parquet, block_rows=block_rows[setup]))
        counts = client.compute([(labels == c).sum() for c in model.classes_], sync=True)
        return int(sum(counts))

    def predict_lib_one(client, setup):
        labels = model.predict(tc.read_parquet_rows(parquet, block_rows=block_rows[setup]))
        counts = da.equal.outer(labels, model.classes_).sum(axis=0)
        return int(client.compute(counts, sync=True).sum())

    def scan(client, setup, out):
        shutil.rmtree(out, ignore_errors=True)
        done = scan_files(
            str(args.workdir / "belts" / "*.pbm"),
            out,
            client,
            None,
            {"fmt": None, "width": None, "chunk_rows": 1024, "scanner": {}},
        )
        return sum(s["rows"] for s in done), sum(s["objects"] for s in done)

    names = ["wraps", "classify --files", "predict (library)", "predict, one count", "scan --files"]
    wanted = names if args.jobs is None else args.jobs
    unknown = sorted(set(wanted) - set(names))
    if unknown:
        ap.error(f"--jobs: unknown {unknown}; the jobs are {names}")
    big_jobs = ("classify --files", "predict (library)", "predict, one count")
    times: dict[tuple[str, str, int], float] = {}
    rss: dict[tuple[str, str, int], tuple[int, int, int, int]] = {}
    mons: dict[tuple[str, str, int], RssMonitor] = {}
    counts = {}
    idle: dict[tuple[str, int], tuple[float, float]] = {}
    for rep in range(max(args.repeat, args.big_repeat)):
        for setup in setups if rep % 2 == 0 else setups[::-1]:
            clusters = {}
            for k in (1, 2):
                cluster = make_cluster(k, setup)
                client = Client(cluster)
                client.run(lambda: __import__("tentaclass.cli.main"))
                if setup == "defaults":
                    client.run(_whole_blocks)
                clusters[k] = (cluster, client)
                # compile the wrap kernel and load everything once on every worker
                client.compute(
                    tc.wrap_many(
                        outline, 64, link, starts=da.from_array(starts[: 200 * k], chunks=200)
                    ).angles
                ).result()
            for k in (1, 2):
                _, client = clusters[k]
                # the cluster's own CPU when no job runs (both clusters up, as in the jobs)
                mon = RssMonitor(client)
                with mon:
                    time.sleep(IDLE_SECONDS)
                idle[setup, k] = (1000 * mon.driver_cpu / IDLE_SECONDS,
                                  1000 * mon.cpu / IDLE_SECONDS / k)  # fmt: skip
                print(
                    f"{setup:<8} idle {k} worker(s): driver {idle[setup, k][0]:.1f} ms/s, "
                    f"each worker {idle[setup, k][1]:.1f} ms/s of CPU",
                    flush=True,
                )
                jobs = {
                    "wraps": lambda c=client, s=setup: wraps(c, s),
                    "classify --files": lambda c=client, s=setup, k=k: classify_cli(
                        c, s, args.workdir / f"o{k}"
                    ),
                    "predict (library)": lambda c=client, s=setup: predict_lib(c, s),
                    "predict, one count": lambda c=client, s=setup: predict_lib_one(c, s),
                    "scan --files": lambda c=client, s=setup, k=k: scan(
                        c, s, args.workdir / f"s{k}"
                    ),
                }
                for job in wanted:
                    if rep >= (args.big_repeat if job in big_jobs else args.repeat):
                        continue
                    mon = RssMonitor(client)
                    t = time.perf_counter()
                    with mon:
                        counts[job] = jobs[job]()
                    dt = time.perf_counter() - t
                    key = (job, setup, k)
                    if dt < times.get(key, np.inf):
                        times[key], mons[key] = dt, mon
                    if job != "wraps":
                        old = rss.get(key, (0, 0, 0, 0))
                        rss[key] = (
                            max(old[0], mon.peak_one),
                            max(old[1], mon.peak_sum),
                            max(old[2], mon.peak_uss),
                            mon.idle,
                        )
                    print(
                        f"{setup:<8} {job:<18} {k} worker(s): {dt:7.2f} s, worker CPU "
                        f"{mon.cpu:6.2f} s, driver CPU {mon.driver_cpu:5.2f} s (loop "
                        f"{mon.loop_cpu:.2f}, client {mon.client_cpu:.2f}), sampler "
                        f"{mon.sampler_cpu:.2f} s, {mon.tasks} tasks, {mon.transitions} "
                        f"transitions, {mon.bytes / 2**20:.1f} MiB between workers",
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
        "scan --files": ("belt rows/s", counts.get("scan --files", (0, 0))[0]),
    }
    rows = []
    for setup in setups:
        for job in wanted:
            unit, n = units[job]
            m1, m2 = mons[job, setup, 1], mons[job, setup, 2]
            t1, t2 = times[job, setup, 1], times[job, setup, 2]
            mem = rss.get((job, setup, 2))
            rows.append(
                {
                    "job": job,
                    "setup": setup,
                    "unit": unit,
                    "n": n,
                    "rate_1": n / t1,
                    "rate_2": n / t2,
                    "ratio": t1 / t2,
                    "seconds_1": t1,
                    "seconds_2": t2,
                    "worker_cpu_seconds_1": m1.cpu,
                    "worker_cpu_seconds_2": m2.cpu,
                    "driver_cpu_seconds_1": m1.driver_cpu,
                    "driver_cpu_seconds_2": m2.driver_cpu,
                    "loop_cpu_seconds_2": m2.loop_cpu,
                    "client_cpu_seconds_2": m2.client_cpu,
                    "sampler_cpu_seconds_2": m2.sampler_cpu,
                    "tasks_2": m2.tasks,
                    "transitions_2": m2.transitions,
                    "bytes_between_workers_2": m2.bytes,
                    "driver_ms_per_task_2": 1000 * m2.driver_cpu / max(m2.tasks, 1),
                    "driver_share_2": m2.driver_cpu / (m2.driver_cpu + m2.cpu),
                    "rate_per_cpu_second": n / m1.cpu,
                    "cpu_share_2": m2.cpu / (2 * t2),
                    "peak_rss_worker_MiB": None if mem is None else mem[0] / 2**20,
                    "peak_rss_all_workers_MiB": None if mem is None else mem[1] / 2**20,
                    "peak_uss_all_workers_MiB": None if mem is None else mem[2] / 2**20,
                    "idle_rss_all_workers_MiB": None if mem is None else mem[3] / 2**20,
                }
            )
    print(f"\nload average before {load_before}, after {load_after}, cores {os.cpu_count()}")
    print(f"check counts: {counts}")
    for (setup, k), (d, w) in sorted(idle.items()):
        print(f"idle CPU, {setup}, {k} worker(s): driver {d:.1f} ms/s, each worker {w:.1f} ms/s")
    print(
        "\n| job | setup | size | 1 worker | 2 workers | ratio | worker CPU s, 1 / 2 "
        "| driver CPU s, 1 / 2 | 2 workers: driver loop / client / sampler CPU s "
        "| 2 workers: tasks, driver ms per task, driver share of the job's CPU "
        "| MiB between workers | CPU share, 2 "
        "| 2 workers: peak RSS one / all (idle all), peak USS all |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        mem = (
            "-"
            if r["peak_rss_worker_MiB"] is None
            else f"{r['peak_rss_worker_MiB']:.0f} / {r['peak_rss_all_workers_MiB']:.0f} "
            f"({r['idle_rss_all_workers_MiB']:.0f}), {r['peak_uss_all_workers_MiB']:.0f} MiB"
        )
        print(
            f"| {r['job']} | {r['setup']} | {r['n']:,} | {r['rate_1']:,.0f} {r['unit']} | "
            f"{r['rate_2']:,.0f} {r['unit']} | {r['ratio']:.2f}x | "
            f"{r['worker_cpu_seconds_1']:.2f} / {r['worker_cpu_seconds_2']:.2f} | "
            f"{r['driver_cpu_seconds_1']:.2f} / {r['driver_cpu_seconds_2']:.2f} | "
            f"{r['loop_cpu_seconds_2']:.2f} / {r['client_cpu_seconds_2']:.2f} / "
            f"{r['sampler_cpu_seconds_2']:.2f} | {r['tasks_2']}, "
            f"{r['driver_ms_per_task_2']:.1f} ms, {r['driver_share_2']:.1%} | "
            f"{r['bytes_between_workers_2'] / 2**20:.1f} | "
            f"{r['cpu_share_2']:.0%} | {mem} |"
        )
    if args.json is not None:
        args.json.write_text(
            json.dumps(
                {
                    "rows": rows,
                    "idle_ms_per_s": {f"{s} {k}": v for (s, k), v in idle.items()},
                    "load_before": load_before,
                    "load_after": load_after,
                },
                indent=1,
            )
        )


if __name__ == "__main__":
    main()
