"""Physical grasps per second (MuJoCo), 64 links, with and without worker processes.

Run: ``python benchmarks/bench_physics.py [--grasps 6] [--jobs 2] [--folder PATH]``.

Each grasp closes a 64-link chain on an MPEG-7 silhouette (the thesis's four
shapes when the data is absent) from a random start, with a link length of
the perimeter over 64; the time includes building the MuJoCo model (convex
decomposition, compiling) and the simulation. The quasi-static grasp
(geometry only, no MuJoCo) of the same chains is timed alongside. The reference in the same run
is a geometric ``wrap(mode="hug")`` of the same chain and start (its kernel
compiled and the worker processes started before timing). Serial and
parallel runs are interleaved and the best of the repeats kept. MuJoCo is
single-threaded; BLAS is pinned to one thread with threadpoolctl.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import markdown_table

from tentaclass import PlanarChain, shapes, wrap
from tentaclass.physics import grasp_many

MPEG7 = (Path(__file__).resolve().parents[1] / "../shared/data/mpeg7-part-b").resolve()


def load(n: int, folder: Path, seed: int):
    rng = np.random.default_rng(seed)
    if folder.is_dir():
        outlines, _, _ = shapes.load_mpeg7(folder, max_vertices=1000)
        pick = rng.choice(len(outlines), n, replace=False)
        return [outlines[i] for i in pick], rng.uniform(0, 1, n), "MPEG-7"
    base = [shapes.square(4), shapes.rectangle(6, 2), shapes.circle(2, 256),
            shapes.triangle(side=5)]  # fmt: skip
    return (base * n)[:n], rng.uniform(0, 1, n), "thesis shapes"


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser()
    ap.add_argument("--grasps", type=int, default=6)
    ap.add_argument("--links", type=int, default=64)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--folder", type=Path, default=MPEG7)
    args = ap.parse_args(argv)
    outlines, starts, source = load(args.grasps, args.folder, 0)
    n = args.links
    lengths = [float(np.sum(np.hypot(*(np.roll(o, -1, 0) - o).T))) / n for o in outlines]
    best = {"serial": np.inf, "parallel": np.inf, "quasi": np.inf, "geometric": np.inf}
    sims = []
    with threadpool_limits(1, user_api="blas"):
        # warm up: compile the geometric kernel, start the (reused) worker processes
        wrap(outlines[0], n, lengths[0], mode="hug")
        small = shapes.square(2.0)
        grasp_many([small] * args.jobs, PlanarChain([0.5] * 8), 0.0, n_jobs=args.jobs)
        grasp_many([small], PlanarChain([0.5] * 8), 0.0, n_jobs=1)
        for _ in range(args.repeat):
            for mode in ("serial", "parallel", "quasi", "geometric"):
                t0 = time.perf_counter()
                if mode == "geometric":
                    for o, ln, s in zip(outlines, lengths, starts, strict=True):
                        wrap(o, n, ln, start=s, mode="hug")
                elif mode == "quasi":
                    chains = [PlanarChain([ln] * n) for ln in lengths]
                    grasp_many(outlines, chains, starts, method="quasi-static")
                else:
                    chains = [PlanarChain([ln] * n) for ln in lengths]
                    jobs = 1 if mode == "serial" else args.jobs
                    sims = grasp_many(outlines, chains, starts, n_jobs=jobs)
                best[mode] = min(best[mode], time.perf_counter() - t0)
    k = len(outlines)
    sim_time = np.array([g.sim_time for g in sims])
    steps = np.array([g.steps for g in sims])
    complete = np.mean([g.complete for g in sims])
    rows = [
        ["physical, 1 process", f"{k / best['serial']:.2f}", f"{best['serial'] / k:.2f}",
         f"{best['serial'] / best['geometric']:.0f}"],
        [f"physical, {args.jobs} processes", f"{k / best['parallel']:.2f}",
         f"{best['parallel'] / k:.2f}", f"{best['parallel'] / best['geometric']:.0f}"],
        ["quasi-static (`quasi_static_grasp`), 1 process", f"{k / best['quasi']:.2f}",
         f"{best['quasi'] / k:.2f}", f"{best['quasi'] / best['geometric']:.0f}"],
        ["geometric hug wrap (reference)", f"{k / best['geometric']:.1f}",
         f"{best['geometric'] / k:.3f}", "1"],
    ]  # fmt: skip
    print(f"{k} grasps of {source} outlines, {n} links, best of {args.repeat}:")
    print(markdown_table(["", "grasps / s", "s / grasp", "x reference time"], rows))
    print(f"simulated time per grasp: median {np.median(sim_time):.1f} s "
          f"({np.median(steps):.0f} steps of 4 ms), complete {complete:.0%}")  # fmt: skip
    return {"best": best, "sim_time": sim_time.tolist(), "steps": steps.tolist()}


if __name__ == "__main__":
    main()
