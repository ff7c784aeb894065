import hashlib
import io
import json
import zipfile

import numpy as np
import pytest
from sklearn.pipeline import make_pipeline

from tentaclass.classifiers import PNNClassifier, RBFNetworkClassifier, TentacleClassifier
from tentaclass.datasets import reference_tentacle, thesis_tentacle
from tentaclass.errors import ModelFileError
from tentaclass.features import FourierFeatures
from tentaclass.io import load_model, save_model
from tentaclass.io._model_file import FORMAT_NAME, FORMAT_VERSION


@pytest.fixture(scope="module")
def data():
    X, y = reference_tentacle(32, n_starts=4, return_X_y=True)
    rng = np.random.default_rng(0)
    T = np.roll(X, 3, axis=1) + rng.normal(0, 0.05, X.shape)
    return X, y, T


def fitted_models(X, y):
    return {
        "tentacle-pnn": TentacleClassifier(spread=0.5, detrend=True).fit(X, y),
        "tentacle-pnn-auto-f32": TentacleClassifier(
            classifier=PNNClassifier(spread="auto", dtype="float32", reject_below=1e-6)
        ).fit(X, y),
        "tentacle-rbf": TentacleClassifier(n_coeffs=8, classifier=RBFNetworkClassifier()).fit(X, y),
        "tentacle-rbf-forward": TentacleClassifier(
            normalize=True, classifier=RBFNetworkClassifier(centers="forward", n_centers=5)
        ).fit(X, y),
        "pipeline": make_pipeline(FourierFeatures(6), PNNClassifier(spread=0.3)).fit(X, y),
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
        "pipeline",
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
    path = save_model(TentacleClassifier(spread=0.5).fit(X, y), tmp_path / "m.tcm")
    with zipfile.ZipFile(path) as zf:
        meta = json.loads(zf.read("metadata.json"))
        assert sorted(zf.namelist()) == ["class_count.npy", "metadata.json", "patterns.npy"]
        blob = zf.read("patterns.npy")
    assert meta["format"] == FORMAT_NAME == "tentaclass-model"
    assert meta["format_version"] == FORMAT_VERSION == 1
    assert meta["estimator"] == "TentacleClassifier"
    assert meta["classes"] == {
        "dtype": "<U9",
        "values": ["circle", "rectangle", "square", "triangle"],
    }
    assert meta["features"]["n_features_in"] == 32 and meta["features"]["n_coeffs_"] == 16
    assert meta["classifier"]["kind"] == "pnn"
    assert meta["classifier"]["params"]["spread"] == 0.5
    assert meta["arrays"]["patterns"]["shape"] == [16, 16]
    assert meta["arrays"]["patterns"]["sha256"] == hashlib.sha256(blob).hexdigest()
    assert isinstance(meta["library_version"], str)


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
    return save_model(TentacleClassifier(spread=0.5).fit(X, y), tmp_path / "good.tcm")


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
    with pytest.raises(FileNotFoundError):
        load_model(tmp_path / "none.tcm")


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


def test_checksum_mismatch(tmp_path, good):
    def tamper(members):
        arr = np.lib.format.read_array(io.BytesIO(members["patterns.npy"]))
        arr[0, 0] += 1.0
        buf = io.BytesIO()
        np.lib.format.write_array(buf, arr)
        members["patterns.npy"] = buf.getvalue()

    with pytest.raises(ModelFileError, match="checksum mismatch for array 'patterns'"):
        load_model(rewrite(good, tmp_path / "x.tcm", members_fn=tamper))


@pytest.mark.parametrize(
    "edit, match",
    [
        (lambda m: m.update(format_version=2), "newer than this tentaclass reads"),
        (lambda m: m.update(format_version=0), "unknown format version 0"),
        (lambda m: m.update(format_version="1"), "unknown format version"),
        (lambda m: m.pop("format_version"), "unknown format version None"),
        (lambda m: m.update(format="something-else"), "not a tentaclass model file"),
        (lambda m: m.update(estimator="SVC"), "unknown estimator kind 'SVC'"),
        (lambda m: m["classifier"].update(kind="svm"), "unknown classifier kind"),
        (lambda m: m["classes"].update(values=["a", "a", "b", "c"]), "repeat"),
        (lambda m: m["classes"].update(dtype="<M8[s]"), "classes dtype"),
        (lambda m: m["classes"].update(values=["a"]), "at least 2"),
        (lambda m: m["classifier"]["fitted"].update(spread_=-1.0), "spread_"),
        (lambda m: m["classifier"]["params"].update(spread=-1.0), "bad pnn parameters"),
        (lambda m: m["classifier"]["params"].update(bogus=1), "bad pnn parameters"),
        (lambda m: m["features"].update(n_coeffs_=99), "do not fit"),
        (lambda m: m["features"].pop("detrend"), "missing field features.'detrend'"),
        (lambda m: m["arrays"]["patterns"].update(shape=[3, 3]), "metadata says"),
        (lambda m: m["arrays"].pop("class_count"), "do not match the metadata"),
        (lambda m: m["tentacle_params"].update(detrend="yes"), "wrong type"),
    ],
)
def test_bad_metadata(tmp_path, good, edit, match):
    with pytest.raises(ModelFileError, match=match):
        load_model(rewrite(good, tmp_path / "x.tcm", meta_fn=edit))


def test_inconsistent_arrays(tmp_path, good):
    def tamper(members):
        counts = np.array([4, 4, 4, 5])
        buf = io.BytesIO()
        np.lib.format.write_array(buf, counts)
        members["class_count.npy"] = buf.getvalue()

        def meta(m):
            m["arrays"]["class_count"]["sha256"] = hashlib.sha256(buf.getvalue()).hexdigest()
            m["arrays"]["class_count"]["dtype"] = counts.dtype.str

        m = json.loads(members["metadata.json"])
        meta(m)
        members["metadata.json"] = json.dumps(m).encode()

    with pytest.raises(ModelFileError, match="inconsistent"):
        load_model(rewrite(good, tmp_path / "x.tcm", members_fn=tamper))


def test_pickled_array_is_refused(tmp_path, good):
    def tamper(members):
        buf = io.BytesIO()
        np.lib.format.write_array(buf, np.array([{"a": 1}], dtype=object), allow_pickle=True)
        members["class_count.npy"] = buf.getvalue()
        m = json.loads(members["metadata.json"])
        m["arrays"]["class_count"]["sha256"] = hashlib.sha256(buf.getvalue()).hexdigest()
        members["metadata.json"] = json.dumps(m).encode()

    with pytest.raises(ModelFileError, match=r"not a valid \.npy"):
        load_model(rewrite(good, tmp_path / "x.tcm", members_fn=tamper))


def test_unsupported_estimators_are_refused(tmp_path, data):
    from sklearn.neighbors import KNeighborsClassifier

    X, y, _ = data
    knn = TentacleClassifier(classifier=KNeighborsClassifier(1)).fit(X, y)
    with pytest.raises(ValueError, match="KNeighborsClassifier"):
        save_model(knn, tmp_path / "k.tcm")
    with pytest.raises(ValueError, match="TentacleClassifier"):
        save_model(object(), tmp_path / "k.tcm")
    with pytest.raises(ValueError, match="unknown_label"):
        save_model(PNNClassifier(unknown_label=object()).fit(X, y), tmp_path / "k.tcm")
    from sklearn.exceptions import NotFittedError

    with pytest.raises(NotFittedError):
        save_model(TentacleClassifier(), tmp_path / "k.tcm")


def test_thesis_model_round_trip_across_start_points(tmp_path):
    X, y = thesis_tentacle(64, return_X_y=True)
    loaded = load_model(save_model(TentacleClassifier().fit(X, y), tmp_path / "t.tcm"))
    for k in range(0, 64, 7):
        assert loaded.predict(np.roll(X, k, axis=1)).tolist() == y.tolist()
