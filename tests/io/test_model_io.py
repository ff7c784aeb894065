import hashlib
import io
import json
import zipfile

import numpy as np
import pytest
from sklearn.pipeline import Pipeline, make_pipeline

from tentaclass.classifiers import (
    FourierClassifier,
    PNNClassifier,
    RBFNetworkClassifier,
    TentacleClassifier,
)
from tentaclass.datasets import reference_tentacle, thesis_tentacle
from tentaclass.errors import InputError, ModelFileError
from tentaclass.features import FourierFeatures
from tentaclass.io import load_model, model_info, save_model
from tentaclass.io._model_file import FORMAT_NAME, FORMAT_VERSION


@pytest.fixture(scope="module")
def data():
    X, y = reference_tentacle(32, n_starts=4, return_X_y=True)
    rng = np.random.default_rng(0)
    T = np.roll(X, 3, axis=1) + rng.normal(0, 0.05, X.shape)
    return X, y, T


def fourier_pnn(**features):
    return make_pipeline(FourierFeatures(**features), PNNClassifier(spread=0.5))


def fitted_models(X, y):
    return {
        "tentacle-pnn": fourier_pnn(detrend=True).fit(X, y),
        "tentacle-pnn-auto-f32": make_pipeline(
            FourierFeatures(),
            PNNClassifier(spread="auto", dtype="float32", reject_below=1e-6),
        ).fit(X, y),
        "tentacle-rbf": make_pipeline(FourierFeatures(8), RBFNetworkClassifier()).fit(X, y),
        "tentacle-rbf-forward": make_pipeline(
            FourierFeatures(normalize=True), RBFNetworkClassifier(centers="forward", n_centers=5)
        ).fit(X, y),
        "fourier-pnn": FourierClassifier(spread=0.5, detrend=True).fit(X, y),
        "fourier-rbf": FourierClassifier(n_harmonics=8, classifier=RBFNetworkClassifier()).fit(
            X, y
        ),
        "pipeline": make_pipeline(FourierFeatures(6), PNNClassifier(spread=0.3)).fit(X, y),
        # step names as scikit-learn allows them: any distinct strings without "__"
        "named-pipeline": Pipeline(
            [("fourier-features", FourierFeatures(6)), ("pnn 1", PNNClassifier(spread=0.3))]
        ).fit(X, y),
        "pnn": PNNClassifier(spread=0.3).fit(X, y),
        "rbf": RBFNetworkClassifier(centers="kmeans", n_centers=6, random_state=0).fit(X, y),
    }


@pytest.mark.parametrize(
    "name",
    [
        "tentacle-pnn",
        "tentacle-pnn-auto-f32",
        "tentacle-rbf",
        "tentacle-rbf-forward",
        "fourier-pnn",
        "fourier-rbf",
        "pipeline",
        "named-pipeline",
        "pnn",
        "rbf",
    ],
)
def test_round_trip_predicts_exactly_alike(tmp_path, data, name):
    X, y, T = data
    model = fitted_models(X, y)[name]
    loaded = load_model(save_model(model, tmp_path / "m.tcm"))
    assert type(loaded) is type(model)
    np.testing.assert_array_equal(loaded.predict_proba(T), model.predict_proba(T))
    np.testing.assert_array_equal(loaded.predict(T), model.predict(T))
    np.testing.assert_array_equal(loaded.classes_, model.classes_)
    assert loaded.classes_.dtype == model.classes_.dtype
    assert loaded.get_params(deep=False).keys() == model.get_params(deep=False).keys()


def test_default_recogniser_round_trips(tmp_path, default_recognisers):
    """The default TentacleClassifier, saved without knowing its internals."""
    from tentaclass.datasets import synthetic_tentacle

    model, rejecting = default_recognisers["default"], default_recognisers["reject"]
    t = synthetic_tentacle(40, 16, laps=(0.5, 2.5), noise=(0.0, 0.02), random_state=1)
    T = t.data[np.isfinite(t.data).all(axis=1)]
    loaded = load_model(save_model(model, tmp_path / "default.tcm"))
    assert type(loaded) is TentacleClassifier
    np.testing.assert_array_equal(loaded.predict_proba(T), model.predict_proba(T))
    np.testing.assert_array_equal(loaded.predict(T), model.predict(T))
    again = load_model(save_model(rejecting, tmp_path / "reject.tcm"))
    np.testing.assert_array_equal(again.predict(T), rejecting.predict(T))


@pytest.mark.parametrize(
    "labels",
    [
        np.array([3, 3, 7, 7]),
        np.array([True, True, False, False]),
        np.array(["b", "b", "a", "a"]),
        np.array(["x", "x", "é", "é"], dtype=object),
        np.array([1.0, 1.0, 2.0, 2.0]),
        np.array([3, 3, 7, 7], dtype=np.uint8),
    ],
)
def test_labels_of_any_type(tmp_path, labels):
    X = [[0.0], [0.1], [1.0], [1.1]]
    clf = PNNClassifier(unknown_label=-1).fit(X, labels)
    loaded = load_model(save_model(clf, tmp_path / "m.tcm"))
    assert loaded.classes_.dtype == clf.classes_.dtype
    assert loaded.predict(X).tolist() == labels.tolist()


def test_metadata_contents(tmp_path, data):
    X, y, _ = data
    model = fourier_pnn().fit(X, y)
    path = save_model(model, tmp_path / "m.tcm", info={"chain": {"n_links": 32}})
    with zipfile.ZipFile(path) as zf:
        meta = json.loads(zf.read("metadata.json"))
        names = sorted(zf.namelist())
        blobs = {n: zf.read(n) for n in names}
    assert meta["format"] == FORMAT_NAME == "tentaclass-model"
    assert meta["format_version"] == FORMAT_VERSION == 2
    assert isinstance(meta["library_version"], str)
    assert meta["info"] == {"chain": {"n_links": 32}}
    pipe = meta["estimator"]
    assert pipe["__estimator__"] == "Pipeline"
    steps = pipe["params"]["steps"]
    assert [s["__tuple__"][1]["__estimator__"] for s in steps] == [
        "FourierFeatures",
        "PNNClassifier",
    ]
    pnn = steps[1]["__tuple__"][1]["state"]
    assert pnn["spread_"] == 0.5 and "_pt" not in pnn  # caches are rebuilt, not stored
    patterns = meta["arrays"][pnn["patterns_"]["__array__"]]
    assert patterns["shape"] == [16, 16] and patterns["dtype"] == "<f8"
    member = pnn["patterns_"]["__array__"] + ".npy"
    assert patterns["sha256"] == hashlib.sha256(blobs[member]).hexdigest()
    assert names == sorted(["metadata.json", *(f"{n}.npy" for n in meta["arrays"])])
    info = model_info(path)
    assert info["chain"] == {"n_links": 32} and info["estimator"] == "Pipeline"


def test_never_pickles(tmp_path, data):
    X, y, _ = data
    path = save_model(PNNClassifier().fit(X, y), tmp_path / "m.tcm")
    with zipfile.ZipFile(path) as zf:
        for name in zf.namelist():
            if name.endswith(".npy"):
                np.lib.format.read_array(io.BytesIO(zf.read(name)), allow_pickle=False)


# ---------------------------------------------------------------- bad files


@pytest.fixture
def good(tmp_path, data):
    X, y, _ = data
    return save_model(fourier_pnn().fit(X, y), tmp_path / "good.tcm")


def rewrite(src, dst, meta_fn=None, members_fn=None):
    """Copy a model file, editing its metadata and/or members."""
    with zipfile.ZipFile(src) as zf:
        members = {n: zf.read(n) for n in zf.namelist()}
    meta = json.loads(members["metadata.json"])
    if meta_fn:
        meta_fn(meta)
    members["metadata.json"] = json.dumps(meta).encode()
    if members_fn:
        members_fn(members)
    with zipfile.ZipFile(dst, "w") as zf:
        for n, b in members.items():
            zf.writestr(n, b)
    return dst


def test_text_file(tmp_path):
    p = tmp_path / "a.tcm"
    p.write_text("this is not a model\n")
    with pytest.raises(ModelFileError, match="not a zip archive"):
        load_model(p)


def test_empty_file(tmp_path):
    p = tmp_path / "a.tcm"
    p.write_bytes(b"")
    with pytest.raises(ModelFileError, match="not a zip archive"):
        load_model(p)


def test_random_zip(tmp_path):
    p = tmp_path / "a.tcm"
    with zipfile.ZipFile(p, "w") as zf:
        zf.writestr("readme.txt", "hello")
    with pytest.raises(ModelFileError, match=r"no metadata\.json"):
        load_model(p)


def test_plain_npz(tmp_path):
    p = tmp_path / "a.npz"
    np.savez(p, X=np.zeros((3, 4)), y=np.arange(3))
    with pytest.raises(ModelFileError, match=r"plain \.npz"):
        load_model(p)


def test_missing_file(tmp_path):
    # one error for every model-file problem, and still the OSError callers expect
    for read in (load_model, model_info):
        with pytest.raises(FileNotFoundError, match=r"none\.tcm: no such model file"):
            read(tmp_path / "none.tcm")
        with pytest.raises(ModelFileError, match=r"none\.tcm: no such model file"):
            read(tmp_path / "none.tcm")


@pytest.mark.parametrize(
    ("path", "match"),
    [
        (None, r"path must be a file name \(str or os.PathLike\), got None"),
        (3, "path must be a file name .*, got 3"),
        (b"m.tcm", "path must be a file name .*, got b'm.tcm'"),
        ("", "path is an empty string"),
    ],
)
def test_a_path_that_is_not_a_file_name_is_named(data, path, match):
    # these used to raise TypeError from pathlib (or read the current folder)
    X, y, _ = data
    for call in (load_model, model_info, lambda p: save_model(FourierClassifier().fit(X, y), p)):
        with pytest.raises(InputError, match=match):
            call(path)


def test_a_directory_is_not_a_model_file(tmp_path):
    for read in (load_model, model_info):
        with pytest.raises(ModelFileError, match=r"is a directory, not a model file"):
            read(tmp_path)


@pytest.mark.parametrize("cut", [0.3, 0.6, 0.9, 0.99])
def test_truncated(tmp_path, good, cut):
    data = good.read_bytes()
    p = tmp_path / "t.tcm"
    p.write_bytes(data[: int(len(data) * cut)])
    with pytest.raises(ModelFileError):
        load_model(p)


def test_flipped_bytes_anywhere_are_caught(tmp_path, good):
    data = bytearray(good.read_bytes())
    rng = np.random.default_rng(0)
    p = tmp_path / "d.tcm"
    for pos in rng.choice(len(data), 300, replace=False):
        damaged = data.copy()
        damaged[pos] ^= 0xFF
        p.write_bytes(bytes(damaged))
        try:
            model = load_model(p)
        except ModelFileError:
            continue
        # a flip that leaves the model loadable must not have changed it (e.g. zip comments)
        X, _ = reference_tentacle(32, n_starts=4, return_X_y=True)
        np.testing.assert_array_equal(model.predict_proba(X), load_model(good).predict_proba(X))


def _pnn_node(meta):
    """The PNN's record inside a saved pipeline's tree."""
    return meta["estimator"]["params"]["steps"][1]["__tuple__"][1]


def _features_node(meta):
    return meta["estimator"]["params"]["steps"][0]["__tuple__"][1]


def _array_name(meta, attribute):
    return _pnn_node(meta)["state"][attribute]["__array__"]


def _replace_array(members, name, arr):
    buf = io.BytesIO()
    np.lib.format.write_array(buf, arr, allow_pickle=arr.dtype.kind == "O")
    members[f"{name}.npy"] = buf.getvalue()
    m = json.loads(members["metadata.json"])
    m["arrays"][name].update(sha256=hashlib.sha256(buf.getvalue()).hexdigest(), dtype=arr.dtype.str)
    members["metadata.json"] = json.dumps(m).encode()


def test_checksum_mismatch(tmp_path, good):
    def tamper(members):
        name = _array_name(json.loads(members["metadata.json"]), "patterns_")
        arr = np.lib.format.read_array(io.BytesIO(members[f"{name}.npy"]))
        arr[0, 0] += 1.0
        buf = io.BytesIO()
        np.lib.format.write_array(buf, arr)
        members[f"{name}.npy"] = buf.getvalue()

    with pytest.raises(ModelFileError, match="checksum mismatch for array 'a"):
        load_model(rewrite(good, tmp_path / "x.tcm", members_fn=tamper))


def _set_class(meta, name):
    meta["estimator"]["__estimator__"] = name


def _array_spec(meta, attribute):
    return meta["arrays"][_array_name(meta, attribute)]


@pytest.mark.parametrize(
    "edit, match",
    [
        (lambda m: m.update(format_version=3), "newer than this tentaclass reads"),
        (lambda m: m.update(format_version=0), "unknown format version 0"),
        (lambda m: m.update(format_version="2"), "unknown format version"),
        (lambda m: m.pop("format_version"), "unknown format version None"),
        (lambda m: m.update(format="something-else"), "not a tentaclass model file"),
        (lambda m: _set_class(m, "SVC"), "'SVC', which is not an estimator"),
        (lambda m: _set_class(m, "os.system"), "not an estimator model files may hold"),
        (lambda m: _set_class(m, "BaseEstimator"), "not an estimator model files may hold"),
        (lambda m: _pnn_node(m).update(__estimator__="subprocess.Popen"), "not an estimator"),
        (lambda m: _pnn_node(m)["state"].update(spread_=-1.0), "spread_"),
        (lambda m: _pnn_node(m)["params"].update(spread=-1.0), "spread"),
        (lambda m: _pnn_node(m)["params"].update(bogus=1), "bad PNNClassifier parameters"),
        (lambda m: _pnn_node(m)["params"].pop("spread"), "parameters"),
        (lambda m: _pnn_node(m)["params"].update(dtype={"names": ["a"]}), "one known tag"),
        (
            lambda m: _pnn_node(m)["params"].update(dtype={"__dtype__": {"names": ["a"]}}),
            "must be a dtype string, got dict",
        ),
        (lambda m: _pnn_node(m)["params"].update(dtype={"__dtype__": "O"}), "not allowed"),
        (lambda m: _pnn_node(m)["params"].update(dtype="complex64"), "dtype"),
        (lambda m: _pnn_node(m)["state"].update(__class__=1), "cannot have the attribute"),
        (lambda m: _pnn_node(m)["state"].update(predict=1), "cannot have the attribute"),
        (lambda m: _pnn_node(m)["state"].update(_pt=1), "cannot have the attribute"),
        (lambda m: _pnn_node(m)["state"].pop("patterns_"), "patterns_"),
        (lambda m: _features_node(m)["state"].update(n_harmonics_=99), None),
        (
            lambda m: _array_spec(m, "patterns_").update(dtype={"descr": "<f8"}),
            "must be a dtype string, got dict",
        ),
        (lambda m: _array_spec(m, "patterns_").update(dtype=["<f8"]), "dtype string, got list"),
        (lambda m: _array_spec(m, "patterns_").update(dtype="|O"), "not allowed"),
        (lambda m: _array_spec(m, "patterns_").update(dtype="<M8[s]"), "not allowed"),
        (lambda m: _array_spec(m, "patterns_").update(dtype="pickle"), "not a dtype"),
        (lambda m: _array_spec(m, "patterns_").update(shape=[3, 3]), "metadata says"),
        (lambda m: m["arrays"].pop(_array_name(m, "class_count_")), "do not match the metadata"),
        (
            lambda m: _pnn_node(m)["state"].update(class_count_=_pnn_node(m)["state"]["patterns_"]),
            "used twice",
        ),
        (lambda m: _pnn_node(m)["state"].update(spread_={"__float__": "1e9"}), "nan, inf"),
        (lambda m: _pnn_node(m)["state"].update(spread_={"__tuple__": [], "x": 1}), "unknown"),
        (
            lambda m: _pnn_node(m)["state"].update(spread_={"__scalar__": [1], "dtype": "<f8"}),
            "scalar",
        ),
        (lambda m: _features_node(m)["params"].update(detrend={"__dict__": 5}), "wrong type"),
        (lambda m: m.update(info=[1]), "info must be an object"),
        # counts of the wrong type were TypeErrors when predicting
        (
            lambda m: _features_node(m)["state"].update(n_features_in_=1.5),
            "n_features_in_ must be an integer from 1 to 2\\*\\*31 - 1, got 1.5",
        ),
        (lambda m: _pnn_node(m)["state"].update(n_features_in_=None), "n_features_in_ must be"),
        (lambda m: _features_node(m)["state"].update(n_harmonics_=10**30), "n_harmonics_ must be"),
        # counts that disagree with the arrays after them failed inside predict
        (
            lambda m: _features_node(m)["state"].update(n_harmonics_=15),
            "step 'pnnclassifier' has n_features_in_ 16, but step 'fourierfeatures' gives 15",
        ),
        (
            lambda m: _features_node(m)["state"].update(n_harmonics_=17),
            "n_harmonics_ is 17, more than the 16 that n_features_in_ 32 angles have",
        ),
        (
            lambda m: m["estimator"]["params"]["steps"][0]["__tuple__"].__setitem__(0, 7),
            "Pipeline steps must be \\(name, estimator\\) pairs with distinct names",
        ),
        (
            lambda m: m["estimator"]["params"]["steps"][0]["__tuple__"].__setitem__(0, "a__b"),
            "Pipeline steps must be \\(name, estimator\\) pairs with distinct names",
        ),
    ],
)
def test_bad_metadata(tmp_path, good, edit, match):
    bad = rewrite(good, tmp_path / "x.tcm", meta_fn=edit)
    if match is None:  # a change that predicts wrongly must at least fail cleanly or agree
        try:
            model = load_model(bad)
        except ModelFileError:
            return
        X, _ = reference_tentacle(32, n_starts=4, return_X_y=True)
        with pytest.raises(ValueError):
            model.predict_proba(X)
        return
    with pytest.raises(ModelFileError, match=match):
        load_model(bad)


def test_deeply_nested_metadata_is_refused(tmp_path, good):
    deep = None
    for _ in range(200):
        deep = [deep]
    bad = rewrite(good, tmp_path / "x.tcm", meta_fn=lambda m: _pnn_node(m)["state"].update(x_=deep))
    with pytest.raises(ModelFileError, match="nested too deeply"):
        load_model(bad)


def test_inconsistent_arrays(tmp_path, good):
    def tamper(members):
        name = _array_name(json.loads(members["metadata.json"]), "class_count_")
        _replace_array(members, name, np.array([4, 4, 4, 5]))

    with pytest.raises(ModelFileError, match="inconsistent"):
        load_model(rewrite(good, tmp_path / "x.tcm", members_fn=tamper))


def test_pickled_array_is_refused(tmp_path, good):
    def tamper(members):
        name = _array_name(json.loads(members["metadata.json"]), "class_count_")
        _replace_array(members, name, np.array([{"a": 1}], dtype=object))

    with pytest.raises(ModelFileError, match="not allowed"):
        load_model(rewrite(good, tmp_path / "x.tcm", members_fn=tamper))


def test_unsupported_estimators_are_refused(tmp_path, data):
    from sklearn.exceptions import NotFittedError
    from sklearn.svm import SVC

    X, y, _ = data
    svc = make_pipeline(FourierFeatures(), SVC()).fit(X, y)
    with pytest.raises(ValueError, match="cannot save a SVC"):
        save_model(svc, tmp_path / "k.tcm")
    with pytest.raises(ValueError, match="cannot save a object"):
        save_model(object(), tmp_path / "k.tcm")
    with pytest.raises(ValueError, match="unknown_label"):
        save_model(PNNClassifier(unknown_label=object()).fit(X, y), tmp_path / "k.tcm")
    with pytest.raises(NotFittedError):
        save_model(TentacleClassifier(), tmp_path / "k.tcm")
    with pytest.raises(ValueError, match="info"):
        save_model(PNNClassifier().fit(X, y), tmp_path / "k.tcm", info={"x": float("nan")})


class _Subclass(PNNClassifier):
    pass


def test_subclasses_of_allowed_estimators_are_refused(tmp_path, data):
    X, y, _ = data
    with pytest.raises(ValueError, match="cannot save a _Subclass"):
        save_model(_Subclass().fit(X, y), tmp_path / "k.tcm")


def test_any_estimator_tree_round_trips(tmp_path, data):
    import warnings

    from sklearn.linear_model import LogisticRegression
    from sklearn.neighbors import KNeighborsClassifier
    from sklearn.pipeline import make_union
    from sklearn.preprocessing import StandardScaler

    from tentaclass.classifiers import ShiftNNClassifier, modern_mlp, thesis_mlp
    from tentaclass.features import AngleSpectrum, LastLap

    X, y, T = data
    models = [
        ShiftNNClassifier(),
        make_pipeline(LastLap(), ShiftNNClassifier(signal="shape")),
        make_pipeline(
            make_union(AngleSpectrum(), make_pipeline(LastLap(16), FourierFeatures())),
            StandardScaler(),
            PNNClassifier(spread="auto"),
        ),
        make_pipeline(FourierFeatures(), modern_mlp(random_state=0, early_stopping=False)),
        make_pipeline(FourierFeatures(), thesis_mlp(random_state=0)),
        make_pipeline(FourierFeatures(), LogisticRegression()),
        make_pipeline(FourierFeatures(), KNeighborsClassifier(1)),
    ]
    for model in models:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # MLPs stopped after a few epochs
            model.fit(X, y)
        loaded = load_model(save_model(model, tmp_path / "m.tcm"))
        np.testing.assert_array_equal(loaded.predict(T), model.predict(T))
        if hasattr(model, "predict_proba"):
            np.testing.assert_array_equal(loaded.predict_proba(T), model.predict_proba(T))


def test_numpy_values_keep_their_types(tmp_path, data):
    X, y, _ = data
    model = PNNClassifier(dtype=np.float32, unknown_label=np.int16(-1)).fit(X, y)
    model.extra_ = {"a": (np.float32(0.5), float("inf")), "b": [np.arange(3), "x"]}
    loaded = load_model(save_model(model, tmp_path / "m.tcm"))
    assert loaded.dtype == np.float32 and type(loaded.unknown_label) is np.int16
    a, b = loaded.extra_["a"], loaded.extra_["b"]
    assert type(a) is tuple and type(a[0]) is np.float32 and a[1] == float("inf")
    np.testing.assert_array_equal(b[0], np.arange(3))


@pytest.mark.parametrize("kind", ["pnn", "rbf"])
def test_version_1_files_are_still_read(kind):
    from pathlib import Path

    here = Path(__file__).parent / "data"
    model = load_model(here / f"v1-tentacle-{kind}.tcm")
    X, _ = reference_tentacle(16, n_starts=2, return_X_y=True)
    # the same numbers up to rounding (the features may be summed in another order)
    np.testing.assert_allclose(
        model.predict_proba(X),
        np.load(here / f"v1-tentacle-{kind}-proba.npy"),
        rtol=1e-6,
        atol=1e-12,
    )
    assert model_info(here / f"v1-tentacle-{kind}.tcm")["format_version"] == 1


@pytest.mark.parametrize(
    "edit, match",
    [
        (lambda m: m.update(estimator="SVC"), "unknown estimator kind 'SVC'"),
        (lambda m: m["classifier"].update(kind="svm"), "unknown classifier kind"),
        (lambda m: m["classes"].update(values=["a", "a", "b", "c"]), "repeat"),
        (lambda m: m["classes"].update(dtype="<M8[s]"), "classes dtype"),
        (lambda m: m["classes"].update(dtype={"a": 1}), "wrong type"),
        (lambda m: m["classes"].update(values=["a"]), "at least 2"),
        (lambda m: m["classifier"]["fitted"].update(spread_=-1.0), "spread_"),
        (lambda m: m["classifier"]["params"].update(spread=-1.0), "bad pnn parameters"),
        (lambda m: m["classifier"]["params"].update(bogus=1), "bad pnn parameters"),
        (lambda m: m["classifier"]["params"].update(dtype={"a": 1}), "bad pnn parameters"),
        (
            lambda m: m["classifier"]["params"].update(dtype={"names": ["a"], "formats": ["f8"]}),
            "bad pnn parameters",
        ),
        (lambda m: m["features"].update(n_coeffs_=99), "do not fit"),
        (lambda m: m["features"].pop("detrend"), "missing field features.'detrend'"),
        (lambda m: m["arrays"]["patterns"].update(shape=[3, 3]), "metadata says"),
        (lambda m: m["arrays"]["patterns"].update(dtype={"a": 1}), "dtype string, got dict"),
        (lambda m: m["arrays"].pop("class_count"), "do not match the metadata"),
        (lambda m: m["tentacle_params"].update(detrend="yes"), "wrong type"),
    ],
)
def test_bad_version_1_metadata(tmp_path, edit, match):
    from pathlib import Path

    good = Path(__file__).parent / "data" / "v1-tentacle-pnn.tcm"
    with pytest.raises(ModelFileError, match=match):
        load_model(rewrite(good, tmp_path / "x.tcm", meta_fn=edit))


def test_thesis_model_round_trip_across_start_points(tmp_path):
    X, y = thesis_tentacle(64, return_X_y=True)
    loaded = load_model(save_model(fourier_pnn().fit(X, y), tmp_path / "t.tcm"))
    for k in range(0, 64, 7):
        assert loaded.predict(np.roll(X, k, axis=1)).tolist() == y.tolist()


def test_bundled_models_and_their_errors():
    from tentaclass.errors import InputError
    from tentaclass.io import bundled_links, bundled_model

    links = bundled_links()
    assert {16, 40} <= set(links)
    with pytest.raises(InputError, match=r"no bundled model for a chain of 17 links: .*16"):
        bundled_model(17)
    model, info = bundled_model(16)
    assert info["chain"]["n_links"] == 16 == model.n_features_in_
    assert model_info(files_of("default-16.tcm"))["format_version"] == FORMAT_VERSION


def files_of(name):
    from importlib.resources import files

    return files("tentaclass.data") / name


def test_best_class_score_needs_class_scores(data):
    from sklearn.linear_model import LogisticRegression

    from tentaclass.errors import InputError
    from tentaclass.io import best_class_score

    X, y, T = data
    pnn = fourier_pnn().fit(X, y)
    scores = best_class_score(pnn, T)
    np.testing.assert_allclose(scores, pnn[-1].class_scores(pnn[0].transform(T)).max(axis=1))
    with pytest.raises(InputError, match="LogisticRegression"):
        best_class_score(make_pipeline(FourierFeatures(), LogisticRegression()).fit(X, y), T)


def test_every_estimator_of_the_package_may_be_saved():
    """The allow-list names every public estimator, each under its own name."""
    from sklearn.base import BaseEstimator

    from tentaclass import classifiers, features
    from tentaclass.io._model_file import _ALLOWED, _allowed_class

    own = {
        name
        for module in (classifiers, features)
        for name in module.__all__
        if isinstance(getattr(module, name), type)
        and issubclass(getattr(module, name), BaseEstimator)
    }
    assert own | {"ScannerModel"} <= set(_ALLOWED)
    for name in _ALLOWED:
        assert _allowed_class(name).__name__ == name


def _union_node(meta):
    """The FeatureUnion of a bundled model (the first step of its pipeline)."""
    return meta["estimator"]["params"]["steps"][0]["__tuple__"][1]["params"]


@pytest.mark.parametrize(
    "edit, match",
    [
        (lambda u: u.update(n_jobs=0), "n_jobs must be None or a non-zero int, got 0"),
        (lambda u: u.update(n_jobs=10**30), "n_jobs must be None or a non-zero int"),
        (lambda u: u.update(transformer_weights=-1), "transformer_weights must be None or a dict"),
        (
            lambda u: u["transformer_list"][0]["__tuple__"].__setitem__(0, -1),
            "FeatureUnion transformer_list must be \\(name, estimator\\) pairs",
        ),
    ],
)
def test_bad_feature_union_metadata(tmp_path, edit, match):
    # scikit-learn checks these only when transforming (ValueError, OverflowError,
    # AttributeError, TypeError there): the file is refused when read
    from importlib.resources import files

    bundled = files("tentaclass.data") / "default-16.tcm"
    bad = rewrite(bundled, tmp_path / "x.tcm", meta_fn=lambda m: edit(_union_node(m)))
    with pytest.raises(ModelFileError, match=match):
        load_model(bad)


def _mlp():
    from tentaclass.classifiers import thesis_mlp

    return thesis_mlp(max_iter=5)


def _spectrum_scaler_logistic():
    from sklearn.linear_model import LogisticRegression
    from sklearn.preprocessing import StandardScaler

    from tentaclass.features import AngleSpectrum

    return make_pipeline(AngleSpectrum(), StandardScaler(), LogisticRegression())


def _lap_knn():
    from sklearn.neighbors import KNeighborsClassifier

    from tentaclass.features import LastLap

    return make_pipeline(LastLap(24), KNeighborsClassifier(1))


def _tentacle():
    from tentaclass.classifiers import TentacleClassifier

    return TentacleClassifier(n_points=16)


@pytest.mark.parametrize(
    "make, path, key, value, match",
    [
        # one layer fewer predicted other classes, one more an IndexError
        (_mlp, (), "n_layers_", 2, "n_layers_ is 2, but the stored arrays are for 3"),
        (_mlp, (), "n_features_in_", 33, "n_features_in_ is 33, but the stored arrays are for 32"),
        (_spectrum_scaler_logistic, (1,), "n_features_in_", 18, "n_features_in_ is 18, but"),
        (_spectrum_scaler_logistic, (2,), "n_features_in_", 16, "n_features_in_ is 16, but"),
        (_spectrum_scaler_logistic, (0,), "n_harmonics_", 16, "gives 16 features"),
        (_lap_knn, (0,), "n_out_", 25, "step 'kneighborsclassifier' has n_features_in_ 24, but"),
        (_lap_knn, (1,), "n_samples_fit_", 17, "n_samples_fit_ is 17, but the stored arrays are"),
        (_tentacle, ("matcher_",), "n_features_in_", 17, "matcher_ has n_features_in_ 17, but"),
    ],
)
def test_counts_disagreeing_with_the_stored_arrays_are_refused(
    tmp_path, data, make, path, key, value, match
):
    X, y, _ = data

    def edit(meta):
        node = meta["estimator"]
        for step in path:
            if isinstance(step, int):
                node = node["params"]["steps"][step]["__tuple__"][1]
            else:
                node = node["state"][step]
        assert node["state"][key] != value
        node["state"][key] = value

    good = save_model(make().fit(X, y), tmp_path / "good.tcm")
    load_model(good)
    with pytest.raises(ModelFileError, match=match):
        load_model(rewrite(good, tmp_path / "x.tcm", meta_fn=edit))
