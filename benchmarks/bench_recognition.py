"""Recognition accuracy on real and synthetic shapes, ours against the peers.

Run: ``.venv/bin/python benchmarks/bench_recognition.py [--quick]`` (needs the
``bench`` extra for MiniRocket and the UCR sets, and ``../shared/data`` for
MPEG-7). Writes one markdown table per setting to ``bench-results/`` and
prints them. Every method sees the same arrays and the same folds.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from sklearn.utils import Bunch

from tentaclass.bench import confusion_figure, results_markdown, run_benchmark
from tentaclass.datasets import mpeg7_tentacle, synthetic_tentacle, ucr_shapes

MPEG7 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "mpeg7-part-b"
OURS = ["thesis", "fourier-1nn", "lap-fourier-lp-1nn", "shift-nn", "shift-nn-lp", "shape-nn",
        "chord-shape-nn", "lap-shape-nn"]  # fmt: skip
PEERS = ["1nn-euclidean", "svc", "minirocket"]


def _emit(results, title, out: Path, stem: str) -> str:
    table = results_markdown(results, title)
    print(table, flush=True)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{stem}.md").write_text(table)
    scored = [r for r in results if not r.error]
    if scored:
        best = max(scored, key=lambda r: r.accuracy)
        confusion_figure(best).savefig(out / f"{stem}-confusion.png", dpi=90)
    return table


def synthetic(out: Path, n_samples: int = 2000, folds: int = 10, n_generated: int = 20_000) -> None:
    """Four thesis classes, 16 links, noise 0.02; and partial wraps apart.

    Two protocols on the same 2000 test wraps: 10-fold within them, and
    trained on ``n_generated`` further wraps from the generator (noise drawn in
    0-0.05 rad, as a deployed model would be trained).
    """
    methods = ["thesis", "lap-fourier-1nn", "lap-shift-nn", "lap-spectrum-hgb", *PEERS]
    d = synthetic_tentacle(n_samples, 16, noise=0.02, random_state=0)
    r = run_benchmark(d.data, d.target, methods, n_splits=folds)
    _emit(r, "Synthetic four classes, 16 links, 1-2 laps, offset 0-3, noise 0.02", out,
          "synthetic-16")  # fmt: skip
    g = synthetic_tentacle(n_generated, 16, noise=(0.0, 0.05), random_state=7)
    split = np.repeat(["train", "test"], [n_generated, n_samples])
    r = run_benchmark(np.vstack([g.data, d.data]), np.concatenate([g.target, d.target]),
                      methods, split=split)  # fmt: skip
    _emit(r, f"Synthetic, trained on {n_generated} generated wraps (noise 0-0.05), tested on "
          "the same 2000 wraps (noise 0.02)", out, "synthetic-16-generated")  # fmt: skip
    p = synthetic_tentacle(n_samples, 16, laps=(0.5, 1.0), noise=0.02, random_state=1)
    r = run_benchmark(p.data, p.target, methods, n_splits=folds)
    _emit(
        r, "Synthetic partial wraps (0.5-1 lap), 16 links, noise 0.02", out, "synthetic-16-partial"
    )


def mpeg7(out: Path, ns, modes, noises, folds: int = 10, copies: int = 10, hug_copies: int = 1,
          peers=PEERS) -> None:  # fmt: skip
    """MPEG-7 one-lap wraps; methods train on ``copies`` wraps per training shape.

    Hug wraps take about 10 minutes per copy of the 1400 silhouettes on two
    cores, so hug settings use their own ``hug_copies``.
    """
    for mode in modes:
        for n in ns:
            for noise in noises:
                copies_here = copies if mode == "taut" else hug_copies
                t0 = time.perf_counter()
                d = mpeg7_tentacle(
                    MPEG7, n, mode, noise=noise, copies=copies_here, random_state=0, n_jobs=-1
                )
                gen = time.perf_counter() - t0
                jammed = np.unique(d.groups[~d.complete])  # drop shapes a chain jammed on
                keep = ~np.isin(d.groups, jammed)
                d = Bunch(**{k: v[keep] for k, v in d.items() if isinstance(v, np.ndarray)})
                r = run_benchmark(d.data, d.target, OURS + list(peers), groups=d.groups,
                                  is_eval=d.wrap_index == 0, n_splits=folds)  # fmt: skip
                title = (f"MPEG-7, {n} links, {mode}, noise {noise:g}, {copies_here} wrap(s) per "
                         f"training shape, {len(jammed)} jammed shapes dropped "
                         f"(data {gen:.0f} s)")  # fmt: skip
                _emit(r, title, out, f"mpeg7-{mode}-{n}-noise{noise:g}")
                if mode == "hug":  # the same models, scored on the laps that close
                    closed = (d.wrap_index == 0) & (d.closure_gap < 0.5)
                    r = run_benchmark(d.data, d.target, OURS + list(peers), groups=d.groups,
                                      is_eval=closed, n_splits=folds)  # fmt: skip
                    stem = f"mpeg7-{mode}-{n}-noise{noise:g}-closed"
                    _emit(r, f"{title}; scored on the {closed.sum()} wraps whose lap closes "
                          "(gap < 0.5 link)", out, stem)  # fmt: skip


#: Classes held out of training in the open-set setting (drawn once at random, seed 7).
UNSEEN = ("HCircle", "car", "chopper", "elephant", "face", "fountain", "key", "pencil", "pocket",
          "spring")  # fmt: skip


def _fixed_chain_folds(d, folds: int, n_folds: int = 10):
    """The first ``folds`` of the 10 stratified folds of ``tentaclass bench`` (seed 0)."""
    from sklearn.model_selection import StratifiedKFold

    skf = StratifiedKFold(n_splits=n_folds, shuffle=True, random_state=0)
    return list(skf.split(d.data, d.target))[:folds]


def fixed_chain(out: Path, folds: int = 10, noises=(0.0,), modes=("hug",), peers=()) -> str:
    """Fixed-chain 1.2-2 lap wraps: ``TentacleClassifier()`` and ``peers``, first ``folds`` folds.

    The headline protocol (64 links, offset 0-2, one wrap per silhouette,
    the folds of ``tentaclass bench``); every method sees the same arrays and
    folds. Failed wraps never train and count as errors. Prints each fold.
    """
    from sklearn.base import clone

    from tentaclass import TentacleClassifier
    from tentaclass.bench import make_method

    methods = {"tentacle": TentacleClassifier(), **{p: make_method(p) for p in peers}}
    rows = []
    for mode in modes:
        for noise in noises:
            d = mpeg7_tentacle(MPEG7, 64, mode, protocol="fixed-chain", laps=(1.2, 2.0),
                               offset=(0.0, 2.0), noise=noise, random_state=0,
                               progress=True)  # fmt: skip
            right = {m: [] for m in methods}
            fit_s = dict.fromkeys(methods, 0.0)
            pred_s = dict.fromkeys(methods, 0.0)
            for i, (tr, te) in enumerate(_fixed_chain_folds(d, folds)):
                tr = tr[d.complete[tr]]
                ok = d.complete[te]
                for name, proto in methods.items():
                    est = clone(proto)
                    t0 = time.perf_counter()
                    if name == "tentacle":
                        est.fit(d.data[tr], d.target[tr], groups=d.groups[tr])
                    else:
                        est.fit(d.data[tr], d.target[tr])
                    t1 = time.perf_counter()
                    pred = np.full(len(te), "failed", dtype=object)
                    pred[ok] = est.predict(d.data[te][ok])
                    pred_s[name] += time.perf_counter() - t1
                    fit_s[name] += t1 - t0
                    right[name].append(pred == d.target[te])
                print(f"{mode}, noise {noise:g}, fold {i}: " + ", ".join(
                    f"{m} {r[-1].mean():.3f}" for m, r in right.items()), flush=True)  # fmt: skip
            for name, r in right.items():
                a = np.concatenate(r)
                per_fold = np.std([x.mean() for x in r])
                rows.append(f"| {mode} | {noise:g} | {name} | {a.mean():.1%} "
                            f"({a.sum()} / {a.size}) | {per_fold:.1%} | {np.sum(~d.complete)} "
                            f"| {fit_s[name]:.0f} s / {pred_s[name]:.0f} s |\n")  # fmt: skip
    table = (
        f"### Fixed chain: 1.2-2 laps, 64 links, {folds} of 10 folds\n\n"
        "| mode | noise (rad) | method | accuracy | fold std | failed wraps "
        "| fit / predict, all folds |\n|---|---|---|---|---|---|---|\n" + "".join(rows)
    )
    stem = "fixed-chain-" + "-".join(modes) + "-noise" + ",".join(f"{x:g}" for x in noises)
    return _write(out, stem, table)


def open_set(out: Path, folds: int = 10, rate: float = 0.05, noise: float = 0.0) -> str:
    """Fixed-chain hug wraps, trained on 60 classes, shown all 70 (``UNSEEN`` never trained).

    ``TentacleClassifier(reject=rate)``; failed wraps never train and count
    as not rejected (unseen) or falsely rejected (known).
    """
    from tentaclass import TentacleClassifier

    d = mpeg7_tentacle(MPEG7, 64, "hug", protocol="fixed-chain", laps=(1.2, 2.0),
                       offset=(0.0, 2.0), noise=noise, random_state=0, progress=True)  # fmt: skip
    unseen = np.isin(d.target, UNSEEN)
    caught, refused, right, fit_s, pred_s = [], [], [], 0.0, 0.0
    for i, (tr, te) in enumerate(_fixed_chain_folds(d, folds)):
        tr = tr[~unseen[tr] & d.complete[tr]]
        t0 = time.perf_counter()
        clf = TentacleClassifier(reject=rate).fit(d.data[tr], d.target[tr], groups=d.groups[tr])
        t1 = time.perf_counter()
        pred = np.full(len(te), "failed", dtype=object)
        ok = d.complete[te]
        pred[ok] = clf.predict(d.data[te][ok])
        pred_s += time.perf_counter() - t1
        fit_s += t1 - t0
        u = unseen[te]
        caught.append(pred[u] == "unknown")
        refused.append(np.isin(pred[~u], ["unknown", "failed"]))
        right.append(pred[~u] == d.target[te][~u])
        print(f"fold {i}: unseen rejected {np.mean(caught[-1]):.3f}, known rejected "
              f"{np.mean(refused[-1]):.3f}", flush=True)  # fmt: skip
    c, r, known_rejected = (np.concatenate(a) for a in (caught, right, refused))
    table = (
        f"### Open set: hug, noise {noise:g}, reject={rate:g}, {folds} of 10 folds\n\n"
        "| unseen objects rejected | known objects rejected (or failed) | known objects right "
        "| fit / predict, all folds |\n|---|---|---|---|\n"
        f"| {c.mean():.1%} ({c.sum()} / {c.size}) | {known_rejected.mean():.1%} "
        f"({known_rejected.sum()} / {known_rejected.size}) | {r.mean():.1%} "
        f"| {fit_s:.0f} s / {pred_s:.0f} s |\n"
    )
    return _write(out, f"open-set-hug-noise{noise:g}", table)


def partial(out: Path, folds: int = 10, noise: float = 0.0) -> str:
    """Trained on 1.2-2 lap hug wraps, tested on partial wraps (0.5-0.95 laps) of other objects.

    Top-1 and top-3 of ``predict_proba`` over all wraps (failed ones count as
    misses), how many are reported partial by ``grasp`` and their mean confidence.
    """
    from tentaclass import TentacleClassifier

    kw = {"protocol": "fixed-chain", "offset": (0.0, 2.0), "noise": noise, "random_state": 0,
          "progress": True}  # fmt: skip
    d = mpeg7_tentacle(MPEG7, 64, "hug", laps=(1.2, 2.0), **kw)
    p = mpeg7_tentacle(MPEG7, 64, "hug", laps=(0.5, 0.95), **kw)
    top1, top3, state, conf, fit_s, pred_s = [], [], [], [], 0.0, 0.0
    for i, (tr, te) in enumerate(_fixed_chain_folds(d, folds)):
        tr = tr[d.complete[tr]]
        t0 = time.perf_counter()
        clf = TentacleClassifier().fit(d.data[tr], d.target[tr], groups=d.groups[tr])
        t1 = time.perf_counter()
        ok = te[p.complete[te]]
        proba = clf.predict_proba(p.data[ok])
        g = clf.grasp(p.data[ok])
        pred_s += time.perf_counter() - t1
        fit_s += t1 - t0
        order = clf.classes_[np.argsort(-proba, axis=1)[:, :3]]
        hit3 = np.zeros(len(te), bool)
        hit1 = np.zeros(len(te), bool)
        hit3[p.complete[te]] = (order == p.target[ok][:, None]).any(axis=1)
        hit1[p.complete[te]] = order[:, 0] == p.target[ok]
        top1.append(hit1)
        top3.append(hit3)
        state.append(g["state"])
        conf.append(g["probability"])
        print(f"fold {i}: top 3 {hit3.mean():.3f}, top 1 {hit1.mean():.3f}", flush=True)
    t1, t3, st, cf = (np.concatenate(a) for a in (top1, top3, state, conf))
    table = (
        f"### Partial wraps (0.5-0.95 laps asked), hug, noise {noise:g}, {folds} of 10 folds\n\n"
        "| top 3 | top 1 | reported partial | mean top probability | fit / predict, all folds "
        "|\n|---|---|---|---|---|\n"
        f"| {t3.mean():.1%} ({t3.sum()} / {t3.size}) | {t1.mean():.1%} "
        f"| {np.mean(st == 'partial'):.1%} | {cf.mean():.2f} | {fit_s:.0f} s / {pred_s:.0f} s |\n"
    )
    return _write(out, f"partial-hug-noise{noise:g}", table)


def _write(out: Path, stem: str, table: str) -> str:
    print(table, flush=True)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{stem}.md").write_text(table)
    return table


def ucr(out: Path) -> None:
    """ArrowHead and OSULeaf with their official splits."""
    for name in ("ArrowHead", "OSULeaf"):
        d = ucr_shapes(name)
        r = run_benchmark(d.data, d.target, ["shift-nn-raw", "1nn-euclidean", "svc", "minirocket"],
                          split=d.split)  # fmt: skip
        _emit(r, f"UCR {name}, official split", out, f"ucr-{name}")


def main(quick: bool = False, out: Path = Path("bench-results")) -> None:
    """Run the recognition benchmarks (``quick``: a small subset for a smoke run)."""
    if quick:
        d = synthetic_tentacle(120, 16, noise=0.02, random_state=0)
        r = run_benchmark(d.data, d.target, ["thesis", "lap-fourier-1nn", "1nn-euclidean"],
                          n_splits=3)  # fmt: skip
        _emit(r, "quick synthetic", out, "quick")
        return
    synthetic(out)
    if MPEG7.is_dir():
        mpeg7(out, (16, 32, 64, 128), ("taut", "hug"), (0.0, 0.05))
    else:
        print(f"MPEG-7 data not found at {MPEG7}: skipped", file=sys.stderr)
    ucr(out)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument(
        "--only", choices=["synthetic", "mpeg7", "ucr", "fixed-chain", "open-set", "partial"]
    )
    parser.add_argument(
        "--folds", type=int, default=10, help="fixed chain / open set / partial: folds run"
    )
    parser.add_argument("--reject", type=float, default=0.05, help="open set: reject= rate")
    parser.add_argument("--links", default="16,32,64,128")
    parser.add_argument("--modes", default="taut,hug")
    parser.add_argument("--noises", default="0,0.05")
    parser.add_argument("--copies", type=int, default=10, help="taut wraps per MPEG-7 shape")
    parser.add_argument("--hug-copies", type=int, default=1, help="hug wraps per MPEG-7 shape")
    parser.add_argument("--peers", default=",".join(PEERS), help="peer methods to run")
    parser.add_argument("--out", type=Path, default=Path("bench-results"))
    a = parser.parse_args()
    if a.only == "mpeg7":
        mpeg7(a.out, [int(x) for x in a.links.split(",")], a.modes.split(","),
              [float(x) for x in a.noises.split(",")], copies=a.copies, hug_copies=a.hug_copies,
              peers=[p for p in a.peers.split(",") if p])  # fmt: skip
    elif a.only == "synthetic":
        synthetic(a.out)
    elif a.only == "ucr":
        ucr(a.out)
    elif a.only == "fixed-chain":
        fixed_chain(a.out, a.folds, [float(x) for x in a.noises.split(",")], a.modes.split(","),
                    [p for p in a.peers.split(",") if p])  # fmt: skip
    elif a.only == "open-set":
        open_set(a.out, a.folds, a.reject)
    elif a.only == "partial":
        partial(a.out, a.folds)
    else:
        main(a.quick, a.out)
