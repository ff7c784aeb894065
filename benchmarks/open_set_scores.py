"""Offline harness for open-set novelty scores of ``TentacleClassifier``.

``collect`` fits ``TentacleClassifier(reject=0.05)`` once per fold (the
folds and unseen classes of ``bench_recognition.py --only open-set``) and
keeps, for the held-out training wraps and for the test wraps, every
member's class distances; ``evaluate`` then scores candidate novelty
scores cheaply: the share of unseen objects rejected at the limit giving
5 % false rejections on held-out training wraps, and AUROC on the test fold.

Run: ``python benchmarks/open_set_scores.py collect --folds 10 --dir DIR``
then ``python benchmarks/open_set_scores.py evaluate --dir DIR``.
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_recognition import MPEG7, UNSEEN, _fixed_chain_folds

MEMBERS = ("lap", "exact", "spectrum", "elastic", "last")


def collect(folds: int, out: Path, every: int = 1, start: int = 0) -> None:
    """Fit once per fold and save every member's class distances (npz per fold)."""
    from tentaclass import TentacleClassifier
    from tentaclass.classifiers import _tentacle
    from tentaclass.classifiers import _tentacle_core as _core
    from tentaclass.datasets import mpeg7_tentacle
    from tentaclass.features import last_lap, split_laps

    d = mpeg7_tentacle(MPEG7, 64, "hug", protocol="fixed-chain", laps=(1.2, 2.0),
                       offset=(0.0, 2.0), random_state=0)  # fmt: skip
    unseen = np.isin(d.target, UNSEEN)
    out.mkdir(parents=True, exist_ok=True)
    for i, (tr, te) in enumerate(_fixed_chain_folds(d, folds)):
        if i < start:
            continue
        tr = tr[~unseen[tr] & d.complete[tr]][::every]
        te = te[::every]
        kept: dict = {}
        choose = _tentacle._choose_weights

        def spy(members, y, _choose=choose, _kept=kept):
            _kept["train"] = members
            _kept["y"] = y
            return _choose(members, y)

        _tentacle._choose_weights = spy
        t0 = time.perf_counter()
        try:
            clf = TentacleClassifier(reject=0.05).fit(d.data[tr], d.target[tr], groups=d.groups[tr])
        finally:
            _tentacle._choose_weights = choose
        with open(out / f"fold{i}.pkl", "wb") as fh:
            pickle.dump((clf, kept), fh)
        te = te[d.complete[te]]
        Xv = _core._three_or_more(d.data[te].astype(float))
        split = split_laps(Xv, clf.n_points)
        closed = split.closed & _core._closes(Xv, split)
        # every member, whatever its weight (the last-lap outlines kept again)
        X3 = _core._three_or_more(d.data[tr].astype(float))
        clf.last_heights_, clf.last_complexity_ = _tentacle._elastic_descriptors(
            last_lap(X3, clf.n_points)[0]
        )
        w = clf.weights_
        clf.weights_ = np.array([1.0, 1.0, float(clf.spectrum_ is not None), 1.0, 1.0])
        te_members = clf._closed_members(Xv[closed], split.lap[closed])
        clf.weights_ = w
        pred = clf.predict(d.data[te])
        arrays = {
            "y_train": kept["y"],
            "y_test": np.searchsorted(
                clf.classes_, np.where(unseen[te], clf.classes_[0], d.target[te])
            ),
            "unseen": unseen[te][closed],
            "unseen_all": unseen[te],
            "pred_unknown": pred == "unknown",
            "closed": closed,
            "weights": clf.weights_,
            "scale": np.array([clf.scale_, clf.temperature_]),
            "coef": clf.reject_coef_,
            "threshold": np.array([clf.reject_threshold_]),
            "spread": clf.class_spread_,
        }
        arrays["y_test"] = arrays["y_test"][closed]
        for name, tr_m, te_m in zip(MEMBERS, kept["train"], te_members, strict=True):
            if tr_m is not None and te_m is not None:
                arrays[f"train_{name}"] = tr_m
                arrays[f"test_{name}"] = te_m
        np.savez(out / f"fold{i}.npz", **arrays)
        print(f"fold {i}: {time.perf_counter() - t0:.0f} s, closed {closed.mean():.3f}", flush=True)


def _limit(known: np.ndarray, rate: float) -> float:
    """The split-conformal limit: the ``1 - rate`` quantile of the known wraps' scores."""
    s = np.sort(known)
    return float(s[min(len(s) - 1, int(np.ceil((len(s) + 1) * (1 - rate))) - 1)])


def evaluate(out: Path, rate: float = 0.05) -> str:
    """Unseen and known wraps rejected, and AUROC, for each candidate score, per fold and pooled.

    Candidates: the rule of ``_fit_rejection`` over several member sets
    (``el`` is the rule of models saved before, ``el+last`` the present
    one), each single feature of :func:`_novelty_features` over the four
    distance members, and the calibrated top probability. The limit of
    every score comes from the held-out training wraps only.
    """
    from sklearn.metrics import roc_auc_score

    from tentaclass.classifiers._tentacle import _class_spreads, _fit_rejection
    from tentaclass.classifiers._tentacle_core import _blend, _novelty_features, softmax_rows

    rules = {"el": (3,), "el+last": (3, 4), "last": (4,), "el+last+lap+exact": (3, 4, 0, 1)}
    single = (3, 4, 0, 1)
    names = ["blend ratio"] + [f"{MEMBERS[j]} ratio" for j in single]
    names += [f"{MEMBERS[j]} / spread" for j in single]
    pooled: dict[str, list] = {}
    for f in sorted(out.glob("fold*.npz")):
        z = dict(np.load(f))
        y, k, w, (scale, temperature) = z["y_train"], len(z["spread"]), z["weights"], z["scale"]
        m_tr = [z.get(f"train_{n}") for n in MEMBERS]
        m_te = [z.get(f"test_{n}") for n in MEMBERS]
        b_tr, b_te = _blend(m_tr, w) / scale, _blend(m_te, w) / scale
        u = z["unseen"]
        scores = {}
        for name, idx in rules.items():
            used = [m_tr[j] for j in idx]
            spreads = [_class_spreads(m, y, k) for m in used]
            coef, limit = _fit_rejection(b_tr, used, y, spreads, rate)
            te = _novelty_features(b_te, [m_te[j] for j in idx], [sp for sp, _ in spreads])
            scores[f"rule {name}"] = (np.array([limit]), te @ coef[:-1] + coef[-1])
        spreads = [_class_spreads(m_tr[j], y, k) for j in single]
        tr = _novelty_features(b_tr, [m_tr[j] for j in single], [lo for _, lo in spreads])
        te = _novelty_features(b_te, [m_te[j] for j in single], [sp for sp, _ in spreads])
        for c, name in enumerate(names):
            scores[name] = (tr[:, c], te[:, c])
        top = (-softmax_rows(-b_tr / temperature).max(1), -softmax_rows(-b_te / temperature).max(1))
        scores["1 - top probability"] = top
        for name, (known, test) in scores.items():
            lim = known[0] if name.startswith("rule") else _limit(known, rate)
            rej = test > lim
            pooled.setdefault(name, []).append(
                (rej[u].sum(), u.sum(), rej[~u].sum(), (~u).sum(), roc_auc_score(u, test))
            )
    n = len(pooled["rule el"])
    lines = [f"| score | unseen rejected | known rejected | AUROC per fold ({n}) |"]
    lines.append("|---|---|---|---|")
    for name, rows in sorted(pooled.items(), key=lambda t: -np.mean([r[4] for r in t[1]])):
        a = np.array(rows, dtype=float)
        lines.append(
            f"| {name} | {a[:, 0].sum() / a[:, 1].sum():.1%} ({a[:, 0].sum():.0f} / "
            f"{a[:, 1].sum():.0f}) | {a[:, 2].sum() / a[:, 3].sum():.1%} | mean "
            f"{a[:, 4].mean():.3f} ({a[:, 4].min():.3f}-{a[:, 4].max():.3f}) |"
        )
    return "\n".join(lines)


if __name__ == "__main__":
    p = argparse.ArgumentParser()
    p.add_argument("what", choices=["collect", "evaluate"])
    p.add_argument("--folds", type=int, default=3)
    p.add_argument("--start", type=int, default=0)
    p.add_argument("--every", type=int, default=1)
    p.add_argument("--dir", type=Path, default=Path("bench-results/open-set-scores"))
    a = p.parse_args()
    if a.what == "collect":
        collect(a.folds, a.dir, a.every, a.start)
    else:
        print(evaluate(a.dir))
