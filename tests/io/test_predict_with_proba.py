"""``predict_with_proba``: predict's labels and predict_proba's probabilities from one pass."""

from importlib.resources import as_file, files

import numpy as np
import pytest
from sklearn.neural_network import MLPClassifier
from sklearn.pipeline import make_pipeline

from tentaclass.classifiers import FourierClassifier, PNNCore, TentacleCore
from tentaclass.datasets import chain_wraps, synthetic_tentacle, thesis_tentacle
from tentaclass.features import FourierFeatures
from tentaclass.io import best_class_score, bundled_model
from tentaclass.io._deploy import _predict_once, predict_with_proba
from tentaclass.io._light import load_light


def wraps16():
    """Known-class wraps from partial to several laps, and wraps of a five-pointed star."""
    t = synthetic_tentacle(40, 16, laps=(0.4, 3.0), noise=(0.0, 0.05), random_state=5)
    theta = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    r = 1 + 0.4 * np.cos(5 * theta)
    star = np.c_[r * np.cos(theta), r * np.sin(theta)]
    u = chain_wraps([star], 16, n_wraps=12, laps=(1.0, 2.0), random_state=3).data
    X = np.vstack([t.data, u])
    return X[np.isfinite(X).all(axis=1)]


def counting(monkeypatch, cls, name):
    """Count the calls of ``cls.name``."""
    calls = []
    original = getattr(cls, name)

    def counted(self, *args, **kwargs):
        calls.append(1)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(cls, name, counted)
    return calls


def assert_as_predict(model, X):
    labels, proba = predict_with_proba(model, X)
    expected = model.predict(X)
    assert labels.dtype == expected.dtype
    np.testing.assert_array_equal(labels, expected)
    np.testing.assert_array_equal(proba, model.predict_proba(X))
    return labels


def test_bundled_model_full_and_light(monkeypatch):
    X = wraps16()
    full, _ = bundled_model(16)
    with as_file(files("tentaclass.data") / "default-16.tcm") as path:
        light, _ = load_light(path)
    for model in (full, light):
        assert_as_predict(model, X)
        calls = counting(monkeypatch, PNNCore, "_joint_log_likelihood")
        predict_with_proba(model, X)
        assert len(calls) == 1  # the PNN's scores once, not once for each answer
        # and the best class score (classify --reject) from the same evaluation
        labels, proba, best = _predict_once(model, X)
        assert len(calls) == 2
        monkeypatch.undo()
        np.testing.assert_array_equal(best, best_class_score(model, X))
        np.testing.assert_array_equal(labels, model.predict(X))
        np.testing.assert_array_equal(proba, model.predict_proba(X))


def test_tentacle_classifier_with_rejection(default_recognisers, tmp_path, monkeypatch):
    from tentaclass.io import save_model

    X = wraps16()
    model = default_recognisers["reject"]
    labels = assert_as_predict(model, X)
    assert "unknown" in labels.tolist() and set(labels.tolist()) - {"unknown"}
    save_model(model, tmp_path / "m.tcm")
    light, _ = load_light(tmp_path / "m.tcm")
    assert light is not None
    np.testing.assert_array_equal(assert_as_predict(light, X), labels)
    for m in (model, light):
        calls = counting(monkeypatch, TentacleCore, "_checked_scores")
        predict_with_proba(m, X)
        assert len(calls) == 1
        monkeypatch.undo()


def test_fourier_classifier_with_rejection():
    X, y = thesis_tentacle(16, return_X_y=True)
    model = FourierClassifier(detrend=True, spread=0.5, reject_below=1e-3).fit(X, y)
    Q = np.vstack([X, wraps16()])
    labels = assert_as_predict(model, Q)
    assert "unknown" in labels.tolist()


def test_other_classifiers_are_asked_in_turn():
    X, y = thesis_tentacle(16, return_X_y=True)
    model = make_pipeline(
        FourierFeatures(), MLPClassifier(hidden_layer_sizes=(4,), max_iter=2000, random_state=0)
    ).fit(np.tile(X, (3, 1)), np.tile(y, 3))
    assert_as_predict(model, wraps16())


def test_checks_the_arrays_as_predict():
    X, y = thesis_tentacle(16, return_X_y=True)
    model = FourierClassifier(spread=0.5).fit(X, y)
    with pytest.raises(ValueError, match="features"):
        predict_with_proba(model, X[:, :8])
