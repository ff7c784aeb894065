"""The methods a benchmark compares: ours and the peers, by name.

Every method is a factory returning a fresh scikit-learn classifier that takes
raw joint-angle arrays of shape ``(n_samples, n_joints)``, so all of them see
exactly the same data.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.ensemble import HistGradientBoostingClassifier
from sklearn.neighbors import KNeighborsClassifier
from sklearn.pipeline import make_pipeline, make_union
from sklearn.preprocessing import StandardScaler
from sklearn.svm import SVC

from ..classifiers import (
    FourierClassifier,
    OutlineClassifier,
    PNNClassifier,
    TentacleClassifier,
)
from ..classifiers._shift_nn import ShiftNNClassifier
from ..errors import InputError
from ..features import AngleSpectrum, FourierFeatures, LastLap


class _AeonAdapter(ClassifierMixin, BaseEstimator):
    """2-D arrays -> aeon's (n_cases, n_channels, n_timepoints) layout."""

    def __init__(self, estimator: object = None):
        self.estimator = estimator

    def fit(self, X, y):
        from sklearn.base import clone

        self.estimator_ = clone(self.estimator).fit(np.asarray(X)[:, None, :], np.asarray(y))
        self.classes_ = np.unique(y)
        return self

    def predict(self, X):
        return self.estimator_.predict(np.asarray(X)[:, None, :])


def _minirocket() -> BaseEstimator:
    try:
        from aeon.classification.convolution_based import MiniRocketClassifier
    except ImportError as exc:  # optional peer: the `bench` extra
        raise InputError("method 'minirocket' needs aeon: pip install 'tentaclass[bench]'") from exc
    return _AeonAdapter(MiniRocketClassifier(random_state=0))


@dataclass(frozen=True)
class Method:
    """A named benchmark entry."""

    name: str
    make: Callable[[], BaseEstimator]
    description: str
    ours: bool


METHODS: dict[str, Method] = {
    m.name: m
    for m in [
        Method(
            "tentacle",
            TentacleClassifier,
            "the default TentacleClassifier(): laps found and averaged; lap, last-lap and "
            "elastic outline matchers and a spectrum network blended, calibrated",
            True,
        ),
        Method(
            "thesis",
            lambda: FourierClassifier(spread=0.1),
            "thesis: |DFT| of E (2 pi ramp) + PNN, spread 0.1",
            True,
        ),
        Method(
            "fourier-1nn",
            lambda: FourierClassifier(detrend=True, classifier=KNeighborsClassifier(1)),
            "|DFT| of detrended E + 1-NN",
            True,
        ),
        Method(
            "fourier-pnn",
            lambda: FourierClassifier(
                detrend=True, weight_power=0.5, classifier=PNNClassifier(spread="auto")
            ),
            "|DFT| of detrended E, weighted by sqrt(k), + PNN with spread chosen on training",
            True,
        ),
        Method(
            "fourier-w1nn",
            lambda: FourierClassifier(
                detrend=True, weight_power=0.5, classifier=KNeighborsClassifier(1)
            ),
            "|DFT| of detrended E, weighted by sqrt(k), + 1-NN",
            True,
        ),
        Method(
            "shift-nn",
            lambda: ShiftNNClassifier(signal="turning"),
            "1-NN on the detrended turning signal, best cyclic shift and mirror (FFT)",
            True,
        ),
        Method(
            "shift-nn-lp",
            lambda: ShiftNNClassifier(signal="turning", n_harmonics=0.5, weight_power=0.5),
            "shift-nn on the lowest half of the frequencies, weighted by sqrt(k) (noise-robust)",
            True,
        ),
        Method(
            "shape-nn",
            lambda: ShiftNNClassifier(signal="shape"),
            "1-NN on the rebuilt joint polygon, best start point, rotation and mirror (FFT)",
            True,
        ),
        Method(
            "chord-shape-nn",
            lambda: ShiftNNClassifier(signal="shape", closure="chord"),
            "shape-nn, the chain closed by its gap chord (clean encoders, laps that do not close)",
            True,
        ),
        Method(
            "lap-shape-nn",
            lambda: make_pipeline(LastLap(), ShiftNNClassifier(signal="shape")),
            "last full lap + shape-nn (clean encoders: the lap is rebuilt from positions)",
            True,
        ),
        Method(
            "lap-shift-nn",
            lambda: make_pipeline(LastLap(), ShiftNNClassifier(signal="turning")),
            "last full lap (drops approach and extra laps) + shift-invariant 1-NN",
            True,
        ),
        Method(
            "lap-fourier-1nn",
            lambda: make_pipeline(
                LastLap(), FourierClassifier(detrend=True, classifier=KNeighborsClassifier(1))
            ),
            "last full lap + |DFT| of detrended E + 1-NN",
            True,
        ),
        Method(
            "lap-fourier-lp-1nn",
            lambda: make_pipeline(
                LastLap(), FourierClassifier(n_harmonics=0.5, classifier=KNeighborsClassifier(1))
            ),
            "last full lap + lowest half of the |DFT| coefficients (2 pi ramp) + 1-NN",
            True,
        ),
        Method(
            "lap-spectrum-hgb",
            lambda: make_pipeline(
                make_union(
                    make_pipeline(LastLap(), FourierFeatures(detrend=True)), AngleSpectrum()
                ),
                HistGradientBoostingClassifier(max_iter=300, random_state=0),
            ),
            "|DFT| of the last lap + |DFT| of the whole array + gradient-boosted trees",
            True,
        ),
        Method(
            "shift-nn-raw",
            lambda: ShiftNNClassifier(signal="raw"),
            "1-NN on the arrays as periodic signals, best cyclic shift and mirror (FFT)",
            True,
        ),
        Method(
            "outline",
            OutlineClassifier,
            "OutlineClassifier(): start- and mirror-invariant MiniRocket + shift-invariant 1-NN "
            "(outline series; needs aeon)",
            True,
        ),
        Method(
            "1nn-euclidean",
            lambda: KNeighborsClassifier(1),
            "peer: 1-NN, Euclidean distance on the raw arrays",
            False,
        ),
        Method(
            "svc",
            lambda: make_pipeline(StandardScaler(), SVC()),
            "peer: RBF SVC on the standardised raw arrays",
            False,
        ),
        Method("minirocket", _minirocket, "peer: MiniRocket (aeon) on the raw arrays", False),
    ]
}


def method_names() -> list[str]:
    """Names of all registered methods."""
    return list(METHODS)


def make_method(name: str) -> BaseEstimator:
    """A fresh estimator for a method name."""
    if name not in METHODS:
        raise InputError(f"unknown method {name!r}; choose from {', '.join(METHODS)}")
    return METHODS[name].make()
