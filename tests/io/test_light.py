"""The light reader predicts exactly as the full load, without scikit-learn."""

import copy
import subprocess
import sys
import warnings
from importlib.resources import as_file, files

import numpy as np
import pytest
from click.testing import CliRunner
from sklearn.exceptions import ConvergenceWarning
from sklearn.neural_network import MLPClassifier
from sklearn.pipeline import FeatureUnion, make_pipeline
from sklearn.preprocessing import StandardScaler

import tentaclass.io._light as light_module
from tentaclass.classifiers import FourierClassifier, PNNClassifier, TentacleClassifier
from tentaclass.cli.main import cli
from tentaclass.datasets import synthetic_tentacle, thesis_tentacle
from tentaclass.errors import InputError
from tentaclass.features import AngleSpectrum, FourierFeatures
from tentaclass.io import (
    _deploy,
    best_class_score,
    bundled_links,
    bundled_model,
    load_model,
    save_model,
)
from tentaclass.io._light import _read_light, load_light


def wraps(n_links, n=60, seed=1):
    """Wraps of every kind a chain meets: partial to several laps, approach, noise."""
    t = synthetic_tentacle(
        n, n_links, laps=(0.4, 3.0), offset=(0, 3), noise=(0.0, 0.03), random_state=seed
    )
    return t.data[np.isfinite(t.data).all(axis=1)]


def assert_same(light, full, X):
    assert light is not None
    assert type(light).__module__ == "tentaclass.io._light"
    np.testing.assert_array_equal(light.predict(X), full.predict(X))
    np.testing.assert_array_equal(light.predict_proba(X), full.predict_proba(X))
    np.testing.assert_array_equal(light.classes_, full.classes_)
    assert light.n_features_in_ == full.n_features_in_


@pytest.mark.parametrize("n_links", bundled_links())
def test_every_bundled_model_predicts_alike(n_links):
    full, info = bundled_model(n_links)
    with as_file(files("tentaclass.data") / f"default-{n_links}.tcm") as path:
        light, light_info = load_light(path)
    X = np.vstack([wraps(n_links), np.tile([0, 0, 0, np.pi / 2], n_links // 4)])
    assert_same(light, full, X)
    np.testing.assert_array_equal(best_class_score(light, X), best_class_score(full, X))
    assert light_info == info


@pytest.fixture(scope="module")
def default_models(wraps16, default_recognisers):
    X, y = wraps16
    small = TentacleClassifier().fit(*thesis_tentacle(16, return_X_y=True))
    rejecting = default_recognisers["reject"]
    assert rejecting.spectrum_ is not None
    # every member in the blend, whatever weights the calibration chose
    blended = copy.deepcopy(default_recognisers["default"])
    # (the elastic members' descriptors are kept only where their weight was not 0)
    elastic = [1.0 if len(h) else 0.0 for h in (blended.elastic_heights_, blended.last_heights_)]
    blended.weights_ = np.array([1.0, 0.5, 1.0, *elastic])
    two = np.isin(y, ["circle", "square"])
    binary = TentacleClassifier().fit(X[two], y[two])
    binary.weights_ = np.array([1.0, 0.0, 0.5, 0.0, 0.0])
    # a model saved before the elastic member of the last lap: four members
    four = copy.deepcopy(default_recognisers["default"])
    for name in ("last_scale_", "last_heights_", "last_complexity_"):
        delattr(four, name)
    four.weights_ = four.weights_[:4]
    # a rejecting model saved before the last lap's matcher joined the rule
    one = copy.deepcopy(rejecting)
    one.reject_coef_ = rejecting.reject_coef_[[0, 1, 3, 5]]
    one.class_spread_ = rejecting.class_spread_[: len(rejecting.classes_)]
    if one.weights_[4] == 0:
        one.last_heights_, one.last_complexity_ = one.last_heights_[:0], one.last_complexity_[:0]
    return {"thesis": small, "reject": rejecting, "blended": blended, "binary": binary,
            "four": four, "reject_one": one}  # fmt: skip


@pytest.mark.parametrize("name", ["thesis", "reject", "blended", "binary", "four", "reject_one"])
def test_saved_default_models_predict_alike(tmp_path, default_models, name):
    model = default_models[name]
    path = save_model(model, tmp_path / "m.tcm")
    light, _ = load_light(path)
    X = wraps(16, 40, seed=2)
    assert_same(light, load_model(path), X)
    assert_same(light, model, X)
    assert light.reject == model.reject and light.unknown_label == model.unknown_label


@pytest.mark.parametrize("activation", ["relu", "tanh", "logistic", "identity"])
@pytest.mark.parametrize("n_classes", [2, 3])
def test_network_forward_pass_is_scikit_learns(tmp_path, activation, n_classes):
    rng = np.random.default_rng(0)
    X = rng.normal(size=(90, 7)) * [1, 2, 3, 4, 5, 6, 7]
    y = np.arange(90) % n_classes
    net = MLPClassifier((9, 5), activation=activation, max_iter=50, random_state=0)
    model = make_pipeline(StandardScaler(), net)
    with warnings.catch_warnings():  # not converged in 50 iterations: no matter here
        warnings.simplefilter("ignore", ConvergenceWarning)
        model.fit(X, y)
    light, _ = _read_light(save_model(model, tmp_path / "net.tcm"))
    T = rng.normal(size=(40, 7)) * 5
    np.testing.assert_array_equal(light.predict_proba(T), model.predict_proba(T))
    assert load_light(tmp_path / "net.tcm")[0] is None  # no predict: not a model for classify


def test_pipelines_of_the_transformers_and_a_pnn(tmp_path):
    X, y = synthetic_tentacle(80, 32, noise=0.02, random_state=0, return_X_y=True)
    union = FeatureUnion([("s", AngleSpectrum(5)), ("f", FourierFeatures(0.5, weight_power=1.0))])
    model = make_pipeline(union, StandardScaler(with_mean=False), PNNClassifier(dtype="float32"))
    model.fit(X, y)
    light, _ = load_light(save_model(model, tmp_path / "p.tcm"))
    assert_same(light, model, wraps(32))


def test_trees_it_does_not_cover_are_loaded_in_full(tmp_path, wraps16):
    X, y = wraps16
    weighted = FeatureUnion(
        [("a", AngleSpectrum()), ("f", FourierFeatures())], transformer_weights={"a": 2.0}
    )
    others = {
        "fourier": FourierClassifier(spread=0.5).fit(X, y),
        "pnn": PNNClassifier(spread=0.5).fit(X, y),
        "weighted": make_pipeline(weighted, PNNClassifier()).fit(X, y),
    }
    for name, model in others.items():
        assert load_light(save_model(model, tmp_path / f"{name}.tcm"))[0] is None, name
    # a recogniser with a member the light reader does not know (as a new blend member)
    grown = TentacleClassifier().fit(*thesis_tentacle(16, return_X_y=True))
    grown.outline_ = np.zeros(3)
    path = save_model(grown, tmp_path / "grown.tcm")
    assert load_light(path)[0] is None
    assert hasattr(load_model(path), "outline_")


def test_wrong_arrays_are_refused(tmp_path):
    light, _ = load_light(files("tentaclass.data") / "default-16.tcm")
    with pytest.raises(InputError, match="expecting 16 features"):
        light.predict(np.zeros((1, 20)))
    with pytest.raises(InputError, match="NaN"):
        light.predict_proba(np.full((1, 16), np.nan))


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


@pytest.mark.parametrize("extra", [[], ["--json"], ["--reject"]])
def test_classify_prints_the_same_with_either_reader(tmp_path, monkeypatch, default_models, extra):
    model_file = save_model(default_models["reject"], tmp_path / "m.tcm")
    arrays = tmp_path / "arrays.txt"
    np.savetxt(arrays, wraps(16, 30, seed=4))
    commands = [["--file", arrays, *extra], ["--file", arrays, "--model", model_file, *extra]]
    _deploy.bundled_predictor.cache_clear()
    light = [run("classify", *c) for c in commands]

    def nothing_light(path):
        return None, light_module._read_light(path)[1]

    monkeypatch.setattr(light_module, "load_light", nothing_light)
    _deploy.bundled_predictor.cache_clear()
    full = [run("classify", *c) for c in commands]
    _deploy.bundled_predictor.cache_clear()
    for a, b in zip(light, full, strict=True):
        assert a.exit_code == b.exit_code == 0, (a.output, b.output)
        assert a.output == b.output


def test_classify_does_not_import_scikit_learn(tmp_path):
    model_file = save_model(
        TentacleClassifier().fit(*thesis_tentacle(16, return_X_y=True)), tmp_path / "m.tcm"
    )
    square = "0 0 0 1.5708 " * 4
    for extra in ([], ["--model", str(model_file)]):
        code = (
            "import sys\nfrom tentaclass.cli.main import main\n"
            f"sys.argv = ['tentaclass', 'classify', {square!r}, *{extra!r}]\n"
            "try:\n    main()\nexcept SystemExit:\n    pass\n"
            "print('sklearn' in sys.modules, 'pandas' in sys.modules)"
        )
        out = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, check=True
        ).stdout
        assert "SQUARE" in out
        assert out.splitlines()[-1] == "False False", out
