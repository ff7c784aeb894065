import json
import zipfile

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.linear_model import LogisticRegression
from sklearn.naive_bayes import GaussianNB
from sklearn.neighbors import KNeighborsClassifier

from tentaclass.classifiers import PNNClassifier
from tentaclass.datasets import thesis_scanner
from tentaclass.errors import InputError, ModelFileError
from tentaclass.io import load_model, model_info, save_model
from tentaclass.scanner import ScannerModel, default_model, inspect
from tentaclass.scanner.model import FORMAT_VERSION
from tentaclass.scanner.simulate import draw_shape

THESIS = thesis_scanner()


def _l_and_t(n=4, seed=0):
    """A user's classes: L-shapes and T-shapes, a handful of each at random places."""
    rng = np.random.default_rng(seed)
    grids, labels = [], []
    for i in range(2 * n):
        g = np.zeros((30, 30), dtype=bool)
        s = int(rng.integers(10, 16))
        r, c = rng.integers(1, 29 - s, size=2)
        if i % 2 == 0:
            g[r : r + s, c : c + s // 3] = True
            g[r + s - s // 3 : r + s, c : c + s] = True
            labels.append("L")
        else:
            g[r : r + s // 3, c : c + s] = True
            g[r : r + s, c + s // 3 : c + 2 * s // 3] = True
            labels.append("T")
        grids.append(np.rot90(g, int(rng.integers(4))))
    return grids, labels


def test_fit_predict_on_thesis_grids():
    model = ScannerModel().fit(THESIS.grids, THESIS.target)
    assert model.classes_.tolist() == ["circle", "rectangle", "square", "triangle"]
    assert model.predict(THESIS.grids).tolist() == THESIS.target.tolist()
    proba = model.predict_proba(THESIS.grids)
    assert proba.shape == (16, 4)
    np.testing.assert_allclose(proba.sum(axis=1), 1.0)
    assert model.features_.shape == (16, len(model.feature_names_))


def test_user_classes_with_outline_descriptors():
    grids, labels = _l_and_t(4, seed=0)
    model = ScannerModel(descriptors=("hull", "outline", "region")).fit(grids, labels)
    test_grids, test_labels = _l_and_t(6, seed=1)
    assert (model.predict(test_grids) == np.array(test_labels)).mean() >= 0.9
    r = inspect(test_grids[0], model)
    assert r.label == test_labels[0]


def test_any_sklearn_classifier_and_sklearn_api():
    model = ScannerModel(LogisticRegression())
    assert clone(model).get_params()["descriptors"] == ("hull",)
    model.fit(list(THESIS.grids) * 2, list(THESIS.target) * 2)
    assert model.score(THESIS.grids, THESIS.target) >= 0.75


def test_default_model_is_shared_and_trained():
    assert default_model() is default_model()
    assert default_model().features_.shape[0] == 16 + 400


@pytest.mark.parametrize(
    "clf", [None, KNeighborsClassifier(1), PNNClassifier(spread=0.3), LogisticRegression()]
)
def test_save_load_roundtrip(tmp_path, clf):
    model = ScannerModel(clf).fit(list(THESIS.grids) * 2, list(THESIS.target) * 2)
    path = tmp_path / "m.tcm"
    model.save(path)
    loaded = ScannerModel.load(path)
    np.testing.assert_array_equal(loaded.features_, model.features_)
    np.testing.assert_array_equal(
        loaded.predict_proba(THESIS.test_grids), model.predict_proba(THESIS.test_grids)
    )
    assert loaded.get_params()["n_harmonics"] == model.n_harmonics
    assert loaded.nominal_sizes() == model.nominal_sizes()
    assert type(load_model(path)) is ScannerModel  # the one model-file format
    assert model_info(path)["estimator"] == "ScannerModel"


def test_save_refuses_classifiers_it_cannot_store(tmp_path):
    model = ScannerModel(GaussianNB()).fit(THESIS.grids, THESIS.target)
    with pytest.raises(InputError, match="cannot save a GaussianNB"):
        model.save(tmp_path / "m.tcm")


def test_load_refuses_other_models(tmp_path):
    from tentaclass.classifiers import TentacleClassifier
    from tentaclass.datasets import thesis_tentacle

    X, y = thesis_tentacle(16, return_X_y=True)
    path = save_model(TentacleClassifier().fit(X, y), tmp_path / "t.tcm")
    with pytest.raises(ModelFileError, match="holds a TentacleClassifier, not a scanner model"):
        ScannerModel.load(path)


def _legacy_save(model, path):
    """The former .npz format, as earlier releases wrote it."""
    clf = model.classifier_
    meta = {
        "format": "tentaclass-scanner-model",
        "version": FORMAT_VERSION,
        "classes": model.classes_.tolist(),
        "descriptors": list(model.descriptors),
        "n_points": model.n_points,
        "n_coeffs": model.n_harmonics,
        "feature_names": model.feature_names_,
        "classifier": {"name": type(clf).__name__, "params": clf.get_params(deep=False)},
    }
    with open(path, "wb") as fh:
        np.savez_compressed(
            fh,
            features=model.features_,
            labels=model.labels_.astype(str),
            sizes=model.sizes_,
            metadata=np.array(json.dumps(meta)),
        )


def test_former_npz_files_load_with_a_deprecation_warning(tmp_path):
    model = ScannerModel().fit(THESIS.grids, THESIS.target)
    path = tmp_path / "old.npz"
    _legacy_save(model, path)
    with pytest.warns(DeprecationWarning, match="save the model again"):
        loaded = ScannerModel.load(path)
    np.testing.assert_allclose(
        loaded.predict_proba(THESIS.grids), model.predict_proba(THESIS.grids)
    )


def _saved(tmp_path):
    path = tmp_path / "m.npz"
    _legacy_save(ScannerModel().fit(THESIS.grids, THESIS.target), path)
    with np.load(path, allow_pickle=False) as npz:
        return path, {k: npz[k] for k in npz.files}


def _rewrite(path, arrays):
    with open(path, "wb") as fh:
        np.savez(fh, **arrays)


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (
            lambda a: a.update(
                metadata=np.array(json.dumps({**json.loads(str(a["metadata"])), "version": 99}))
            ),
            "unknown format version 99",
        ),
        (
            lambda a: a.update(
                metadata=np.array(json.dumps({**json.loads(str(a["metadata"])), "format": "other"}))
            ),
            "not a tentaclass",
        ),
        (lambda a: a.update(metadata=np.array("{not json")), "not valid JSON"),
        (lambda a: a.pop("labels"), "missing"),
        (lambda a: a.update(features=a["features"][:, :3]), "feature columns"),
        (lambda a: a.update(features=a["features"].astype(np.float32)), "float64"),
        (lambda a: a.update(labels=a["labels"][:5]), "labels must be"),
        (
            lambda a: a.update(labels=np.where(a["labels"] == "circle", "star", a["labels"])),
            "classes",
        ),
        (
            lambda a: a.update(
                metadata=np.array(
                    json.dumps(
                        {**json.loads(str(a["metadata"])), "classifier": {"name": "os.system"}}
                    )
                )
            ),
            "classifier must be",
        ),
        (
            lambda a: a.update(
                metadata=np.array(
                    json.dumps(
                        {
                            **json.loads(str(a["metadata"])),
                            "classifier": {"name": "PNNClassifier", "params": {"spread": -1}},
                        }
                    )
                )
            ),
            "spread",
        ),
    ],
)
def test_load_refuses_bad_files(tmp_path, change, match):
    path, arrays = _saved(tmp_path)
    change(arrays)
    _rewrite(path, arrays)
    with pytest.raises(ModelFileError, match=match):
        ScannerModel.load(path)


def test_load_refuses_damaged_and_foreign_files(tmp_path):
    path, _ = _saved(tmp_path)
    data = path.read_bytes()
    (tmp_path / "cut.npz").write_bytes(data[: len(data) // 2])
    ScannerModel().fit(THESIS.grids, THESIS.target).save(tmp_path / "m.tcm")
    (tmp_path / "cut.tcm").write_bytes((tmp_path / "m.tcm").read_bytes()[:-40])
    (tmp_path / "text.npz").write_text("hello")
    np.save(tmp_path / "array.npy", np.zeros(3))
    with zipfile.ZipFile(tmp_path / "zip.npz", "w") as z:
        z.writestr("readme.txt", "not ours")
    for name in ["cut.npz", "text.npz", "array.npy", "zip.npz", "missing.npz", "cut.tcm"]:
        with pytest.raises(ModelFileError):
            ScannerModel.load(tmp_path / name)


def test_load_names_a_directory_and_a_missing_file(tmp_path):
    with pytest.raises(ModelFileError, match="is a directory, not a model file"):
        ScannerModel.load(tmp_path)
    with pytest.raises(FileNotFoundError, match=r"none\.tcm: no such model file"):
        ScannerModel.load(tmp_path / "none.tcm")


def test_pickled_arrays_are_refused(tmp_path):
    path, arrays = _saved(tmp_path)
    arrays["labels"] = arrays["labels"].astype(object)
    _rewrite(path, arrays)
    with pytest.raises(ModelFileError):
        ScannerModel.load(path)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"descriptors": ("hull", "colour")}, "descriptors"),
        ({"descriptors": ()}, "at least one"),
        ({"n_harmonics": 40}, "n_harmonics"),
        ({"n_points": 2}, "n_points"),
    ],
)
def test_bad_parameters(kwargs, match):
    with pytest.raises(InputError, match=match):
        ScannerModel(**kwargs).fit(THESIS.grids, THESIS.target)


def test_bad_fit_input():
    with pytest.raises(InputError, match="one label per grid"):
        ScannerModel().fit(THESIS.grids, THESIS.target[:3])
    with pytest.raises(InputError, match="at least 2 classes"):
        ScannerModel().fit(THESIS.grids[:4], THESIS.target[:4])
    with pytest.raises(InputError, match="no object pixels"):
        ScannerModel().fit([np.zeros((3, 3)), np.ones((3, 3))], ["a", "b"])
    with pytest.raises(InputError, match="sequence of 2-D grids"):
        ScannerModel().fit(np.ones((3, 3)), ["a", "b", "c"])
    grid = draw_shape("circle", (20, 20), 10.0)
    assert ScannerModel().fit([grid, grid.T[:, :15]], ["a", "b"]).classes_.tolist() == ["a", "b"]


def test_any_flipped_byte_gives_model_file_error_or_the_same_model(tmp_path):
    path = tmp_path / "m.tcm"
    ScannerModel().fit(THESIS.grids, THESIS.target).save(path)
    data = path.read_bytes()
    reference = ScannerModel.load(path).predict_proba(THESIS.grids)
    bad = tmp_path / "bad.tcm"
    for i in range(0, len(data), 7):
        flipped = bytearray(data)
        flipped[i] ^= 0x5A
        bad.write_bytes(bytes(flipped))
        try:
            model = ScannerModel.load(bad)
        except ModelFileError:
            continue
        # only bytes the format does not use (zip timestamps, ...) may change
        np.testing.assert_array_equal(model.predict_proba(THESIS.grids), reference)


def test_user_model_from_one_size_recognises_other_sizes():
    examples = [
        draw_shape(c, (40, 40), 24.0, angle=a) for c in ("square", "circle") for a in (0, 1)
    ]
    model = ScannerModel().fit(examples, ["square", "square", "circle", "circle"])
    for size in (16.0, 20.0, 30.0, 36.0):
        for angle in (0.3, 0.9):
            assert model.predict([draw_shape("square", (64, 64), size, angle=angle)]) == "square"
            assert model.predict([draw_shape("circle", (64, 64), size, angle=angle)]) == "circle"
