"""Crossing links over the MPEG-7 silhouettes, checked independently of the generator.

Run: ``python benchmarks/wrap_crossings.py [--every K]``. One chain of 64 unit
links wraps every silhouette (every K-th with ``--every``), each object scaled
so that the chain makes 1, 2 or 3 laps (calibrated by one wrap with links of
1/64 of the support's perimeter), with a random rotation, start, direction and
an offset of 0-2 links, in both modes. Each wrap is checked by
``tests/wrapping/chain_check.py`` (shapely and numpy only): "object" counts
wraps with a link meeting the outline outside the stretch between its own
joints, "self" wraps with two links crossing outside the object; in brackets
the self crossings that do not involve an approach link (a later lap must
pass the approach between the base and the start point: in the plane that
crossing is forced).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import shapely

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests" / "wrapping"))
from _timing import markdown_table  # noqa: E402
from chain_check import chain_problems, crossing_pairs  # noqa: E402

from tentaclass import shapes  # noqa: E402
from tentaclass.wrapping import wrap_many  # noqa: E402

MPEG7 = (HERE.parent / "../shared/data/mpeg7-part-b").resolve()
N_LINKS = 64


def cases(outline: np.ndarray, mode: str, rng: np.random.Generator, laps: int) -> dict:
    """The outline rotated and scaled for ``laps`` laps of unit links, and the wrap's options."""
    a = rng.uniform(0, 2 * np.pi)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    o = (outline - outline.mean(axis=0)) @ rot.T
    ref = shapely.Polygon(o).convex_hull if mode == "taut" else shapely.LinearRing(o)
    ln0 = ref.length / N_LINKS
    w0 = wrap_many(o, N_LINKS, ln0, mode=mode)[0]
    ln = ln0 * laps / w0.laps  # the link length that makes ``laps`` laps
    return {
        "outline": o / ln,
        "starts": float(rng.uniform()),
        "direction": str(rng.choice(["ccw", "cw"])),
        "offset": float(rng.uniform(0, 2)),
    }


def run(every: int = 1, modes=("taut", "hug"), laps=(1, 2, 3), seed: int = 0) -> list[dict]:
    outlines, _, names = shapes.load_mpeg7(MPEG7, max_vertices=1000)
    outlines, names = outlines[::every], names[::every]
    rows = []
    for mode in modes:
        for k in laps:
            rng = np.random.default_rng(seed + 100 * k)
            counts = {"object": 0, "self": 0, "self_no_approach": 0, "any": 0,
                      "incomplete": 0, "bad_length": 0}  # fmt: skip
            bad: list[str] = []
            got_laps = []
            t0 = time.perf_counter()
            for outline, name in zip(outlines, names, strict=True):
                c = cases(outline, mode, rng, k)
                o = c.pop("outline")
                w = wrap_many(o, N_LINKS, 1.0, mode=mode, **c)[0]
                got_laps.append(w.laps)
                p = chain_problems(o, w)
                out, _ = crossing_pairs(w.joints, outline=o)
                no_app = int(np.sum(out.min(axis=1) >= w.offset_links)) if len(out) else 0
                for key in ("object", "self", "incomplete", "bad_length"):
                    counts[key] += p[key] > 0
                counts["self_no_approach"] += no_app > 0
                worst = p["object"] or no_app or p["incomplete"] or p["bad_length"]
                counts["any"] += bool(p["object"] or p["self"])
                if worst:
                    bad.append(name)
            rows.append({"mode": mode, "laps": k, "n": len(outlines), **counts,
                         "median_laps": float(np.median(got_laps)), "bad": bad,
                         "seconds": time.perf_counter() - t0})  # fmt: skip
            r = rows[-1]
            print(f"{mode} {k}: object {r['object']} self {r['self']} "
                  f"({r['self_no_approach']}) incomplete {r['incomplete']} "
                  f"median laps {r['median_laps']:.2f} [{r['seconds']:.0f} s] "
                  f"e.g. {bad[:6]}", flush=True)  # fmt: skip
    print(markdown_table(
        ["mode", "laps", "wraps", "object", "self (not with the approach)", "any",
         "incomplete"],
        [[r["mode"], r["laps"], r["n"], r["object"], f"{r['self']} ({r['self_no_approach']})",
          r["any"], r["incomplete"]] for r in rows],
    ))  # fmt: skip
    return rows


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--every", type=int, default=1, help="use every K-th silhouette")
    ap.add_argument("--modes", default="taut,hug")
    ap.add_argument("--laps", default="1,2,3")
    args = ap.parse_args()
    run(args.every, tuple(args.modes.split(",")), tuple(int(x) for x in args.laps.split(",")))
