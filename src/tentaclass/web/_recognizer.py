"""The page's recogniser: drawn outlines and measured chains -> class, and taught shapes."""

from __future__ import annotations

import json
import re
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import FourierClassifier, points_to_angles, resample_closed, save_model
from .._deprecation import UNSET, renamed
from .._typing import ArrayLike, FloatArray
from ..datasets import drawn_shapes
from ..errors import InputError
from ..features import last_lap
from ..shapes import from_stroke

#: Links of the recognition chain: a closed chain of equal links whose joints lie
#: on the outline (one lap), the array every answer is computed from.
N_LINKS = 64
#: Points of the outline a stroke is cleaned to (:func:`~tentaclass.shapes.from_stroke`).
OUTLINE_POINTS = 256
#: Fewest examples a new shape is taught with.
MIN_EXAMPLES = 3
#: Noisy copies made of each taught example (jittered and thinned strokes).
_COPIES = 8
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9 _-]{0,39}$")


def build_model() -> FourierClassifier:
    """The unfitted classifier behind the page: the one place to change it.

    A :class:`~tentaclass.FourierClassifier` (Fourier features of the joint
    angles, a PNN with its kernel width chosen on the training set) that
    answers ``"unknown"`` when the best class's mean kernel value is below
    ``1e-50``: far from every drawn example of every class.

    Examples
    --------
    >>> build_model().reject_below
    1e-50
    """
    return FourierClassifier(spread="auto", reject_below=1e-50)


def outline_angles(outline: ArrayLike) -> FloatArray:
    """Joint angles of the recognition chain: ``N_LINKS`` equal links, joints on the outline.

    Parameters
    ----------
    outline : array_like of shape (n_points, 2)
        A closed outline (e.g. from :func:`tentaclass.shapes.from_stroke`).

    Returns
    -------
    angles : ndarray of shape (N_LINKS,)

    Examples
    --------
    >>> from tentaclass.shapes import square
    >>> q = outline_angles(square(1.0))
    >>> q.shape, round(float(q.sum() / (2 * np.pi)), 9)
    ((64,), 1.0)
    """
    return points_to_angles(resample_closed(outline, N_LINKS))


@dataclass(frozen=True)
class Answer:
    """One recognition: the label (or ``"unknown"``) and the probability of each class."""

    label: str
    probabilities: dict[str, float]

    def to_dict(self) -> dict:
        """JSON-ready form."""
        return {"label": self.label, "probabilities": self.probabilities}


def _augment(stroke: FloatArray, rng: np.random.Generator) -> list[FloatArray]:
    """The stroke and noisy copies of it: jittered by 1 % of its size and thinned."""
    size = float(np.ptp(stroke, axis=0).max())
    out = [stroke]
    for _ in range(_COPIES):
        keep = np.sort(rng.choice(len(stroke), max(3, int(0.7 * len(stroke))), replace=False))
        out.append(stroke[keep] + rng.normal(0, 0.01 * size, (len(keep), 2)))
    return out


class Recognizer:
    """Recognises drawn outlines and measured joint angles; learns new shapes.

    Built-in classes are learned from :func:`tentaclass.datasets.drawn_shapes`;
    taught shapes are kept as their strokes in ``data_dir/taught.json`` and
    the fitted model is written with :func:`tentaclass.save_model` to
    ``data_dir/model.tcm`` after every change. Thread-safe: one lock guards
    teaching, forgetting and predicting.

    Parameters
    ----------
    data_dir : path, optional
        Where taught shapes and the model are kept; None keeps them in memory.
    n_per_class : int, default=40
        Drawn strokes per built-in class to learn from.
    random_state : int, default=0
        Seed of those strokes.
    seed : int, optional
        Deprecated alias of ``random_state``.

    Examples
    --------
    >>> from tentaclass.datasets import drawn_shapes
    >>> r = Recognizer(n_per_class=10)
    >>> r.classify_stroke(drawn_shapes(1, classes=("star",), random_state=5).strokes[0]).label
    'star'
    """

    def __init__(
        self,
        data_dir: str | Path | None = None,
        n_per_class: int = 40,
        random_state: int = 0,
        seed: Any = UNSET,
    ):
        self.data_dir = None if data_dir is None else Path(data_dir)
        self._lock = threading.RLock()
        random_state = renamed("random_state", random_state, "seed", seed, default=0)
        base = drawn_shapes(n_per_class, random_state=random_state)
        self._base_X = np.array(
            [outline_angles(from_stroke(s, OUTLINE_POINTS)) for s in base.strokes]
        )
        self._base_y = base.target.astype(object)
        self.builtin = tuple(dict.fromkeys(base.target.tolist()))
        self._taught: dict[str, list[list[list[float]]]] = {}
        self._taught_X: dict[str, FloatArray] = {}
        if self.data_dir is not None:
            self.data_dir.mkdir(parents=True, exist_ok=True)
            self._load_taught()
        self._fit()

    # ------------------------------------------------------------------ state
    @property
    def taught_file(self) -> Path | None:
        """JSON file of the taught strokes (None without a data directory)."""
        return None if self.data_dir is None else self.data_dir / "taught.json"

    @property
    def model_file(self) -> Path | None:
        """Model file written by :func:`tentaclass.save_model` (None without a data directory)."""
        return None if self.data_dir is None else self.data_dir / "model.tcm"

    def _load_taught(self) -> None:
        path = self.taught_file
        if path is None or not path.exists():
            return
        try:
            data = json.loads(path.read_text())
            for name, strokes in data["shapes"].items():
                self._taught_X[name] = self._examples(name, strokes)
                self._taught[name] = strokes
        except (ValueError, KeyError, TypeError, AttributeError) as exc:
            raise InputError(f"cannot read taught shapes from {path}: {exc}") from exc

    def _save(self) -> None:
        taught_file, model_file = self.taught_file, self.model_file
        if taught_file is None or model_file is None:  # no data directory: kept in memory
            return
        tmp = taught_file.with_suffix(".tmp")
        tmp.write_text(json.dumps({"format": "tentaclass-taught-shapes", "shapes": self._taught}))
        tmp.replace(taught_file)
        save_model(self.model_, model_file)

    def _fit(self) -> None:
        X = [self._base_X, *self._taught_X.values()]
        y = [self._base_y, *(np.full(len(v), k, object) for k, v in self._taught_X.items())]
        self.model_ = build_model().fit(np.concatenate(X), np.concatenate(y).astype(str))

    def _examples(self, name: str, strokes: list) -> FloatArray:
        rng = np.random.default_rng(len(name))
        rows = []
        for k, s in enumerate(strokes):
            try:
                stroke = np.asarray(s, dtype=float)
                from_stroke(stroke, OUTLINE_POINTS)
            except (InputError, ValueError, TypeError) as exc:
                raise InputError(f"example {k + 1} of {name!r}: {exc}") from None
            rows += [outline_angles(from_stroke(c, OUTLINE_POINTS)) for c in _augment(stroke, rng)]
        return np.array(rows)

    # --------------------------------------------------------------- teaching
    def classes(self) -> list[dict]:
        """Every class with whether it is built in and how many examples taught it."""
        with self._lock:
            out = [{"name": c, "builtin": True, "examples": None} for c in self.builtin]
            return out + [
                {"name": k, "builtin": False, "examples": len(v)} for k, v in self._taught.items()
            ]

    def teach(self, name: str, strokes: list) -> None:
        """Learn a new shape from a few drawn strokes of it.

        Raises :class:`~tentaclass.errors.InputError` for a bad or taken name,
        fewer than ``MIN_EXAMPLES`` strokes, or a stroke that is no outline.
        """
        if not isinstance(name, str) or not _NAME.match(name.strip()):
            raise InputError(
                "name must be 1-40 letters, digits, spaces, '-' or '_', starting with a "
                f"letter or digit, got {name!r}"
            )
        name = name.strip()
        if name.lower() == "unknown":
            raise InputError("name 'unknown' is the answer when nothing fits; choose another")
        if len(strokes) < MIN_EXAMPLES:
            raise InputError(
                f"teaching {name!r} needs at least {MIN_EXAMPLES} drawn examples, "
                f"got {len(strokes)}"
            )
        with self._lock:
            if name.lower() in (c["name"].lower() for c in self.classes()):
                raise NameTakenError(f"a shape named {name!r} exists already: choose another name")
            X = self._examples(name, strokes)
            self._taught_X[name] = X
            self._taught[name] = [np.asarray(s, float).tolist() for s in strokes]
            self._fit()
            self._save()

    def forget(self, name: str) -> None:
        """Remove a taught shape; built-in classes cannot be removed."""
        with self._lock:
            if name in self.builtin:
                raise InputError(f"{name!r} is built in and cannot be removed")
            if name not in self._taught:
                raise UnknownShapeError(f"no taught shape named {name!r}")
            del self._taught[name], self._taught_X[name]
            self._fit()
            self._save()

    # ------------------------------------------------------------ recognising
    def classify_angles(self, angles: ArrayLike) -> Answer:
        """Answer for one recognition-chain array of ``N_LINKS`` angles."""
        q = np.asarray(angles, dtype=float)[None]
        with self._lock:
            model = self.model_
        label = str(model.predict(q)[0])
        proba = model.predict_proba(q)[0]
        return Answer(label, {str(c): float(p) for c, p in zip(model.classes_, proba, strict=True)})

    def classify_outline(self, outline: ArrayLike) -> Answer:
        """Answer for a closed outline."""
        return self.classify_angles(outline_angles(outline))

    def classify_stroke(self, stroke: ArrayLike) -> Answer:
        """Answer for a hand-drawn stroke (cleaned by :func:`~tentaclass.shapes.from_stroke`)."""
        return self.classify_outline(from_stroke(stroke, OUTLINE_POINTS))

    def classify_chain(self, q: ArrayLike, link_lengths: ArrayLike = 1.0) -> tuple[Answer, bool]:
        """Answer for a measured chain's joint angles, from its last closed lap.

        Returns the answer and whether a full lap was found (without one the
        lap is a guess; see :func:`tentaclass.features.last_lap`).
        """
        lap, closed = last_lap(q, N_LINKS, link_lengths)
        return self.classify_angles(lap), bool(closed)


class NameTakenError(InputError):
    """A shape of that name exists already."""


class UnknownShapeError(InputError):
    """No taught shape of that name."""
