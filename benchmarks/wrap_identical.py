"""Whether this tree's wraps equal a reference tree's, bit for bit, on a broad sample.

Run: ``python benchmarks/wrap_identical.py REFERENCE_SRC [--every 5]``. Each
tree runs the same wraps of every ``every``-th MPEG-7 silhouette (<= 1000
vertices) in its own process: per outline and mode ("taut", "hug") four
wraps of 1-3 laps, two with an approach (offset), two with a thick chain
(one of them with an approach), directions alternating, n = 64, random
starts. Every field of the batches (angles, joints, contact, laps, flags,
...) is compared byte for byte; prints "K of N changed".
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
FIELDS = ("angles", "joints", "contact", "lap", "laps", "offset_links", "heading",
          "complete", "n_placed", "closure_gap", "start_point")  # fmt: skip


def _cases(per: float, rng: np.random.Generator) -> list[dict]:
    n = 64
    ln = 0.95 * per / n
    thick = 0.95 * rng.uniform(1.5, 3) * per / n
    return [
        {"link_length": 0.95 * rng.uniform(1, 3) * per / n, "starts": rng.uniform(0, 1, 4),
         "offset": 0.0, "thickness": 0.0},
        {"link_length": ln, "starts": rng.uniform(0, 1, 2),
         "offset": rng.uniform(0.2, 3, 2) * ln, "thickness": 0.0},
        {"link_length": thick, "starts": rng.uniform(0, 1, 2),
         "offset": np.array([0.0, rng.uniform(0.5, 2) * thick]),
         "thickness": float(rng.uniform(0.05, 0.5)) * thick},
    ]  # fmt: skip


def generate(out: str, every: int) -> None:
    """Run the sample with the ``tentaclass`` on the path and save every field."""
    sys.path.insert(0, str(HERE))
    from bench_wrap import MPEG7

    from tentaclass import shapes
    from tentaclass.wrapping import wrap_many

    outlines, _, _ = shapes.load_mpeg7(MPEG7, max_vertices=1000)
    rng = np.random.default_rng(12345)
    res: dict[str, list] = {f: [] for f in FIELDS}
    meta, errors = [], []
    for i, o in enumerate(outlines[::every]):
        per = float(np.sum(np.hypot(*(np.roll(o, -1, 0) - o).T)))
        for mode in ("taut", "hug"):
            d = "ccw" if (i + (mode == "hug")) % 2 == 0 else "cw"
            for c in _cases(per, rng):
                try:
                    b = wrap_many(o, 64, c["link_length"], starts=c["starts"], offset=c["offset"],
                                  thickness=c["thickness"], mode=mode, direction=d)  # fmt: skip
                except ValueError as exc:
                    errors.append(f"{i} {mode} {exc}")
                    continue
                for f in FIELDS:
                    res[f].extend(np.asarray(getattr(b, f)))
                meta.extend(f"{i} {mode} {d}" for _ in range(len(c["starts"])))
    arrays = {f: np.array(v) for f, v in res.items()}
    np.savez(out, meta=np.array(meta), errors=np.array(errors, dtype=str), **arrays)  # type: ignore[arg-type]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reference", help="the reference tree's src directory")
    ap.add_argument("--every", type=int, default=5)
    args = ap.parse_args()
    trees = {"this": str(HERE.parent / "src"), "reference": str(Path(args.reference).resolve())}
    with tempfile.TemporaryDirectory() as tmp:
        runs = {}
        for name, src in trees.items():
            runs[name] = f"{tmp}/{name}.npz"
            env = dict(os.environ, PYTHONPATH=src)
            cmd = [sys.executable, __file__, "--generate", runs[name], str(args.every)]
            subprocess.run(cmd, env=env, check=True)
        a, b = np.load(runs["this"]), np.load(runs["reference"])
        same = a["meta"].tolist() == b["meta"].tolist()
        if not same or a["errors"].tolist() != b["errors"].tolist():
            print("the two trees ran different cases (or failed on different ones)")
            return
        n = len(a["angles"])
        changed = np.zeros(n, bool)
        for f in FIELDS:
            for q in range(n):
                changed[q] |= a[f][q].tobytes() != b[f][q].tobytes()
        modes = np.array([m.split()[1] for m in a["meta"]])
        refused = len(a["errors"])
    print(f"{int(changed.sum())} of {n} changed (taut {int(np.sum(modes == 'taut'))}, "
          f"hug {int(np.sum(modes == 'hug'))}; one MPEG-7 silhouette in {args.every}; "
          f"{refused} calls refused alike)")  # fmt: skip


if __name__ == "__main__":
    if sys.argv[1:2] == ["--generate"]:
        generate(sys.argv[2], int(sys.argv[3]))
    else:
        main()
