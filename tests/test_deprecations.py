"""Every renamed public name still works for one release, warns, and names its new name."""

import json
import shutil
import zipfile

import numpy as np
import pytest
from click.testing import CliRunner

from tentaclass import fourier_features, wrap, wrap_many
from tentaclass.bench import run_benchmark
from tentaclass.classifiers import FourierClassifier
from tentaclass.cli.main import cli
from tentaclass.datasets import (
    chain_wraps,
    drawn_shapes,
    mpeg7_tentacle,
    reference_tentacle,
    synthetic_tentacle,
    thesis_scanner,
)
from tentaclass.errors import InputError
from tentaclass.features import AngleSpectrum, FourierFeatures
from tentaclass.io import load_model, save_model
from tentaclass.scanner import ScannerModel
from tentaclass.scanner.descriptors import feature_names, features_matrix, measure, object_features
from tentaclass.shapes import square

SQUARE = np.tile([0, 0, 0, np.pi / 2], 4)


@pytest.fixture(scope="module")
def Xy():
    return reference_tentacle(16, n_starts=4, return_X_y=True)


def renamed(old, new, category=DeprecationWarning):
    """Expect one warning that names both the old and the new name."""
    return pytest.warns(category, match=rf"{old}.* is deprecated.*use {new}")


# -- n_coeffs -> n_harmonics -----------------------------------------------------------------


def test_fourier_features_n_coeffs():
    with renamed("n_coeffs=", "n_harmonics="):
        old = fourier_features(SQUARE, n_coeffs=3)
    np.testing.assert_array_equal(old, fourier_features(SQUARE, n_harmonics=3))
    with pytest.warns(DeprecationWarning), pytest.raises(InputError, match="not n_coeffs"):
        fourier_features(SQUARE, n_harmonics=3, n_coeffs=3)


@pytest.mark.parametrize("cls", [FourierFeatures, AngleSpectrum])
def test_transformers_n_coeffs_and_n_coeffs_(cls, Xy):
    X, _ = Xy
    new = cls(n_harmonics=3).fit(X)
    with renamed("n_coeffs=", "n_harmonics=", FutureWarning):
        old = cls(n_coeffs=3).fit(X)
    np.testing.assert_array_equal(old.transform(X), new.transform(X))
    with renamed("n_coeffs_", "n_harmonics_", FutureWarning):
        assert old.n_coeffs_ == new.n_harmonics_ == 3
    assert not hasattr(cls(), "n_coeffs_")  # unfitted: no alias either, and no warning


def test_fourier_classifier_n_coeffs(Xy):
    X, y = Xy
    with renamed("n_coeffs=", "n_harmonics=", FutureWarning):
        old = FourierClassifier(n_coeffs=4).fit(X, y)
    assert old.transform(X).shape == (len(X), 4)
    with pytest.warns(FutureWarning), pytest.raises(InputError, match="not n_coeffs"):
        FourierClassifier(n_harmonics=4, n_coeffs=4).fit(X, y)


def test_scanner_model_and_descriptors_n_coeffs():
    d = thesis_scanner()
    with renamed("n_coeffs=", "n_harmonics=", FutureWarning):
        old = ScannerModel(n_coeffs=3).fit(d.grids, d.target)
    assert old.feature_names_ == ScannerModel(n_harmonics=3).fit(d.grids, d.target).feature_names_
    with renamed("n_coeffs=", "n_harmonics="):
        assert feature_names(("hull",), n_coeffs=2) == feature_names(("hull",), n_harmonics=2)
    g = measure(np.ones((5, 5), dtype=bool))
    with renamed("n_coeffs=", "n_harmonics="):
        a = object_features(g, n_coeffs=2)
    with renamed("n_coeffs=", "n_harmonics="):
        b = features_matrix([g], n_coeffs=2)
    np.testing.assert_array_equal(a, object_features(g, n_harmonics=2))
    np.testing.assert_array_equal(b[0], a)


def test_model_files_with_the_old_names_load(tmp_path, Xy):
    """A file written before the rename (parameter n_coeffs, attribute n_coeffs_) still loads."""
    X, y = Xy
    model = FourierClassifier(n_harmonics=4, spread=0.5).fit(X, y)
    path = save_model(model, tmp_path / "new.tcm")
    with zipfile.ZipFile(path) as zf:
        members = {n: zf.read(n) for n in zf.namelist()}
    meta = json.loads(members["metadata.json"])
    text = json.dumps(meta)
    assert '"n_harmonics"' in text
    old = json.loads(
        text.replace('"n_harmonics', '"n_coeffs').replace('"n_coeffs": "deprecated", ', "")
    )
    for node in _estimator_nodes(old):
        assert "n_harmonics" not in node["params"]
    members["metadata.json"] = json.dumps(old).encode()
    with zipfile.ZipFile(tmp_path / "old.tcm", "w") as zf:
        for n, b in members.items():
            zf.writestr(n, b)
    loaded = load_model(tmp_path / "old.tcm")
    assert loaded.n_harmonics == 4 and loaded.n_coeffs == "deprecated"
    np.testing.assert_array_equal(loaded.predict_proba(X), model.predict_proba(X))


def _estimator_nodes(value):
    if isinstance(value, dict):
        if "__estimator__" in value:
            yield value
        for v in value.values():
            yield from _estimator_nodes(v)
    elif isinstance(value, list):
        for v in value:
            yield from _estimator_nodes(v)


# -- seed -> random_state ----------------------------------------------------------------------


def test_wrap_and_wrap_many_seed():
    with renamed("seed=", "random_state="):
        old = wrap(square(4), 16, 1.0, noise=0.1, seed=3)
    np.testing.assert_array_equal(
        old.angles, wrap(square(4), 16, 1.0, noise=0.1, random_state=3).angles
    )
    with renamed("seed=", "random_state="):
        old = wrap_many(square(4), 16, 1.0, [0.0, 0.5], noise=0.1, seed=3)
    new = wrap_many(square(4), 16, 1.0, [0.0, 0.5], noise=0.1, random_state=3)
    np.testing.assert_array_equal(old.angles, new.angles)


def test_drawn_shapes_seed():
    with renamed("seed=", "random_state="):
        old = drawn_shapes(1, classes=("star",), seed=5)
    new = drawn_shapes(1, classes=("star",), random_state=5)
    np.testing.assert_array_equal(old.strokes[0], new.strokes[0])


def test_run_benchmark_seed(Xy):
    X, y = Xy
    with renamed("seed=", "random_state="):
        old = run_benchmark(X, y, ["thesis"], n_splits=2, seed=1)
    assert (
        old[0].accuracy == run_benchmark(X, y, ["thesis"], n_splits=2, random_state=1)[0].accuracy
    )


def test_recognizer_seed():
    pytest.importorskip("fastapi")
    from tentaclass.web import Recognizer

    with renamed("seed=", "random_state="):
        old = Recognizer(n_per_class=2, seed=1)
    stroke = drawn_shapes(1, classes=("star",), random_state=5).strokes[0]
    new = Recognizer(n_per_class=2, random_state=1)
    assert old.classify_stroke(stroke).label == new.classify_stroke(stroke).label


# -- offset_links (a link count) -> offset (a distance) ----------------------------------------


def test_synthetic_tentacle_seed_and_offset_links():
    new = synthetic_tentacle(6, 16, offset=(1.0, 2.0), random_state=2)
    with renamed("seed=", "random_state="):
        a = synthetic_tentacle(6, 16, offset=(1.0, 2.0), seed=2)
    with renamed("offset_links=", "offset="):
        b = synthetic_tentacle(6, 16, offset_links=(1.0, 2.0), random_state=2)
    for d in (a, b):
        np.testing.assert_array_equal(d.data, new.data)
    assert ((new.offset >= 1.0) & (new.offset <= 2.0)).all()


def test_mpeg7_tentacle_seed_and_offset_links(mpeg7_folder, tmp_path):
    for name in ("apple-1.png", "Bone-1.png"):
        shutil.copy(mpeg7_folder / name, tmp_path / name)
    kw = dict(protocol="fixed-chain", cache=False, laps=(1.0, 1.2))
    new = mpeg7_tentacle(tmp_path, 16, offset=(1.0, 1.5), random_state=4, **kw)
    with renamed("seed=", "random_state="):
        a = mpeg7_tentacle(tmp_path, 16, offset=(1.0, 1.5), seed=4, **kw)
    with renamed("offset_links=", "offset="):
        b = mpeg7_tentacle(tmp_path, 16, offset_links=(1.0, 1.5), random_state=4, **kw)
    for d in (a, b):
        np.testing.assert_array_equal(d.data, new.data)


def test_chain_wraps_offset_links_counts_links():
    """``offset_links`` was in links; ``offset`` is a distance: links times link_length."""
    kw = dict(n_wraps=3, laps=(1.0, 1.5), random_state=0)
    new = chain_wraps([square(1.0)], 16, 0.5, offset=(1.0, 1.0), **kw)
    with renamed("offset_links=", "offset="):
        old = chain_wraps([square(1.0)], 16, 0.5, offset_links=(2.0, 2.0), **kw)
    np.testing.assert_array_equal(old.data, new.data)
    np.testing.assert_allclose(new.offset, 1.0)


# -- the command line ------------------------------------------------------------------------


def test_cli_train_n_coeffs(tmp_path, Xy):
    X, y = Xy
    np.savez(tmp_path / "t.npz", X=X, y=y)
    r = CliRunner().invoke(
        cli, ["train", "--data", str(tmp_path / "t.npz"), "--out", str(tmp_path / "m.tcm"),
              "--n-coeffs", "3"],
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "--n-coeffs" in r.stderr and "--n-harmonics" in r.stderr
    assert load_model(tmp_path / "m.tcm").n_harmonics == 3
    assert "--n-coeffs" not in CliRunner().invoke(cli, ["train", "--help"]).output


def test_cli_seed():
    runner = CliRunner()
    args = ["wrap", "--shape", "square", "--links", "12", "--noise", "0.1", "--json"]
    old = runner.invoke(cli, [*args, "--seed", "3"])
    new = runner.invoke(cli, [*args, "--random-state", "3"])
    assert old.exit_code == new.exit_code == 0, old.output
    assert "--seed" in old.stderr and "--random-state" in old.stderr
    assert json.loads(old.stdout)["angles"] == json.loads(new.stdout)["angles"]
    both = runner.invoke(cli, [*args, "--seed", "3", "--random-state", "3"])
    assert both.exit_code == 2 and "not --seed as well" in both.output
