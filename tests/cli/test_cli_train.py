import json
import zipfile

import numpy as np
import pytest
from click.testing import CliRunner

from tentaclass.cli.main import cli
from tentaclass.datasets import reference_tentacle
from tentaclass.io import load_model


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


def one_line_error(r, message):
    assert r.exit_code != 0, r.output
    assert message in r.output, r.output
    assert "Traceback" not in r.output
    assert len(r.output.strip().splitlines()) == 1, r.output


@pytest.fixture(scope="module")
def training():
    X, y = reference_tentacle(24, n_starts=4, return_X_y=True)
    rng = np.random.default_rng(0)
    Xs = np.concatenate([np.roll(X, k, axis=1) for k in (0, 5, 11)])
    return Xs + rng.normal(0, 0.02, Xs.shape), np.tile(y, 3)


@pytest.fixture
def npz(tmp_path, training):
    X, y = training
    path = tmp_path / "train.npz"
    np.savez(path, X=X, y=y)
    return path


def classify_json(model, X, tmp_path):
    f = tmp_path / "q.npy"
    np.save(f, X)
    r = run("classify", "--json", "--model", model, "--file", f)
    assert r.exit_code == 0, r.output
    return [row["label"] for row in json.loads(r.output)]


@pytest.mark.parametrize("classifier", ["pnn", "rbf"])
def test_train_then_classify_round_trip(tmp_path, npz, training, classifier):
    X, y = training
    out = tmp_path / "m.tcm"
    r = run("train", "--data", npz, "--out", out, "--classifier", classifier)
    assert r.exit_code == 0, r.output
    line = r.output.strip()
    assert len(line.splitlines()) == 1
    assert line.startswith(f"{classifier}: 4 classes (circle, rectangle, square, triangle)")
    assert f"{X.shape[0]} samples of 24 joints" in line
    assert "training accuracy 1.000" in line
    model = load_model(out)
    query = np.roll(X[:8], 3, axis=1)
    assert classify_json(out, query, tmp_path) == model.predict(query).tolist() == y[:8].tolist()


def test_options_reach_the_model(tmp_path, npz):
    out = tmp_path / "m.tcm"
    r = run(
        "train",
        "--data",
        npz,
        "--out",
        out,
        "--spread",
        "0.7",
        "--n-harmonics",
        "5",
        "--no-detrend",
    )
    assert r.exit_code == 0, r.output
    assert "spread 0.7," in r.output
    model = load_model(out)
    assert model.n_harmonics == 5 and model.detrend is False and model.spread == 0.7
    assert model.transform(np.zeros((1, 24)) + 2 * np.pi / 24).shape == (1, 5)


def test_csv_with_pi_expressions_header_and_comments(tmp_path):
    square = ["0", "0", "0", "pi/2"] * 4
    circle = ["pi/8"] * 16
    tri = (["0"] * 4 + ["2*pi/3"]) * 2 + ["0"] * 5 + ["2pi/3"]
    lines = ["# thesis shapes", ",".join(f"q{i}" for i in range(16)) + ",label"]
    for name, row in (("square", square), ("circle", circle), ("triangle", tri)):
        for k in range(3):
            lines.append(",".join(row[k:] + row[:k]) + f",{name}  # rolled {k}")
    csv = tmp_path / "d.csv"
    csv.write_text("\n".join(lines) + "\n")
    out = tmp_path / "m.tcm"
    r = run("train", "--data", csv, "--out", out, "--spread", "0.5")
    assert r.exit_code == 0, r.output
    assert "3 classes (circle, square, triangle), 9 samples of 16 joints" in r.output
    r = run("classify", "--model", out, " ".join(square[7:] + square[:7]))
    assert r.output.splitlines()[1].split()[:2] == ["0", "SQUARE"]


def test_integer_labels_from_npz(tmp_path, training):
    X, y = training
    path = tmp_path / "int.npz"
    codes = np.unique(y, return_inverse=True)[1] + 10
    np.savez(path, X=X, y=codes)
    out = tmp_path / "m.tcm"
    assert run("train", "--data", path, "--out", out).exit_code == 0
    assert load_model(out).classes_.tolist() == [10, 11, 12, 13]
    r = run("classify", "--model", out, "--file", _save(tmp_path, X[:2]))
    assert r.exit_code == 0 and r.output.splitlines()[1].split()[1] == str(codes[0])


def _save(tmp_path, X):
    f = tmp_path / "x.npy"
    np.save(f, X)
    return f


def test_chain_length_mismatch_is_one_line_error(tmp_path, npz):
    out = tmp_path / "m.tcm"
    run("train", "--data", npz, "--out", out)
    r = run("classify", "--model", out, " ".join(["pi/8"] * 16))
    one_line_error(r, "m.tcm was trained for a chain of 24 links; these arrays have 16 joint")
    assert r.exit_code == 1


def test_classify_with_bad_model_files(tmp_path):
    text = tmp_path / "t.tcm"
    text.write_text("hello")
    one_line_error(run("classify", "--model", text, "0 0 pi"), "not a zip archive")
    plain = tmp_path / "p.npz"
    np.savez(plain, X=np.zeros((2, 3)))
    one_line_error(run("classify", "--model", plain, "0 0 pi"), "not a tentaclass model file")
    rz = tmp_path / "r.tcm"
    with zipfile.ZipFile(rz, "w") as zf:
        zf.writestr("a.txt", "x")
    one_line_error(run("classify", "--model", rz, "0 0 pi"), "no metadata.json")
    r = run("classify", "--model", tmp_path / "missing.tcm", "0 0 pi")
    assert r.exit_code == 2 and "does not exist" in r.output  # click's usage error


def test_classify_refuses_a_bare_classifier_model(tmp_path):
    from tentaclass.classifiers import PNNClassifier
    from tentaclass.io import save_model

    path = save_model(PNNClassifier().fit([[0.0], [1.0]], [0, 1]), tmp_path / "b.tcm")
    one_line_error(run("classify", "--model", path, "0 0 pi"), "bare PNNClassifier")


def test_truncated_model_file(tmp_path, npz):
    out = tmp_path / "m.tcm"
    run("train", "--data", npz, "--out", out)
    data = out.read_bytes()
    out.write_bytes(data[: len(data) // 2])
    one_line_error(run("classify", "--model", out, " ".join(["pi/12"] * 24)), "model file")


@pytest.mark.parametrize(
    "content, name, message",
    [
        (b"not an npz", "a.npz", "not a readable .npz"),
        (None, "noy.npz", "missing ['y']"),
        (None, "obj.npz", "pickles"),
        (None, "one.npz", "only one class"),
        (None, "short.npz", "at least 3"),
        (None, "len.npz", "but 3 labels"),
        (None, "nan.npz", "NaN"),
        # a complex y was "Complex data not supported"; an empty label trained a class ''
        (None, "cplx.npz", "cplx.npz: y must hold labels (strings or integers), got complex128"),
        (None, "emptylabel.npz", "emptylabel.npz: label 2 is empty"),
        # a NaN label was scikit-learn's "Input y contains NaN.", naming no file
        (None, "nanlabel.npz", "nanlabel.npz: label 2 is nan, not a class"),
        ("0,0,pi,a\n0,0,pi,pi,b\n", "ragged.csv", "different numbers"),
        ("0,0,pi,a\n0,x,pi,b\n", "bad.csv", "line 2"),
        ("# only comments\n", "empty.csv", "no labelled angle arrays"),
        ("0,0,pi,\n0,0,pi,b\n", "nolabel.csv", "empty label"),
        ("0,0,pi,pi/2\n0,0,pi,0.5\n", "nolabels.csv", "the last column holds angles"),
        (b"\xff\xfe\x00bin", "bin.csv", "not a text file"),
    ],
)
def test_bad_training_files(tmp_path, content, name, message):
    path = tmp_path / name
    X = np.tile([0.0, 0.0, np.pi], (4, 1))
    if content is not None:
        path.write_bytes(content) if isinstance(content, bytes) else path.write_text(content)
    elif name == "noy.npz":
        np.savez(path, X=X)
    elif name == "obj.npz":
        np.savez(path, X=X, y=np.array(["a", 1, None, 2.0], dtype=object))
    elif name == "one.npz":
        np.savez(path, X=X, y=np.array(["a"] * 4))
    elif name == "short.npz":
        np.savez(path, X=X[:, :2], y=np.array(["a", "b"] * 2))
    elif name == "len.npz":
        np.savez(path, X=X, y=np.array(["a", "b", "a"]))
    elif name == "cplx.npz":
        np.savez(path, X=X, y=np.arange(4) + 1j)
    elif name == "emptylabel.npz":
        np.savez(path, X=X, y=np.array(["a", "b", "", "b"]))
    elif name == "nanlabel.npz":
        np.savez(path, X=X, y=np.array([0.0, 1.0, np.nan, 1.0]))
    elif name == "nan.npz":
        X[0, 0] = np.nan
        np.savez(path, X=X, y=np.array(["a", "b"] * 2))
    r = run("train", "--data", path, "--out", tmp_path / "m.tcm")
    one_line_error(r, message)
    assert r.exit_code == 1
    assert not (tmp_path / "m.tcm").exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--spread", "wide"], "neither 'auto' nor a number"),
        (["--spread", "-1"], "finite number > 0"),
        (["--classifier", "svm"], "'svm' is not one of"),
        (["--n-harmonics", "0"], "0"),
    ],
)
def test_bad_options_are_usage_errors(tmp_path, npz, args, message):
    r = run("train", "--data", npz, "--out", tmp_path / "m.tcm", *args)
    assert r.exit_code == 2
    assert message in r.output
    assert "Traceback" not in r.output


def test_too_many_coefficients_is_one_line_error(tmp_path, npz):
    one_line_error(
        run("train", "--data", npz, "--out", tmp_path / "m.tcm", "--n-harmonics", "13"),
        "n_harmonics must be between 1 and floor(n_joints / 2) = 12",
    )


def test_train_requires_data_and_out(tmp_path):
    r = run("train", "--out", tmp_path / "m.tcm")
    one_line_error(r, "give either --data or --outlines")
    assert r.exit_code == 2  # a usage error, as the other commands' (was 1)


def test_train_n_coeffs_with_n_harmonics_is_a_usage_error(tmp_path, npz):
    r = run("train", "--data", npz, "--out", tmp_path / "m.tcm", "--n-coeffs", 3,
            "--n-harmonics", 3)  # fmt: skip
    # (the line before it says that --n-coeffs is deprecated)
    assert r.exit_code == 2 and "Traceback" not in r.output
    assert "give --n-harmonics only, not --n-coeffs as well" in r.stderr.splitlines()[-1]


@pytest.mark.parametrize("classifier", ["pnn", "rbf"])
@pytest.mark.parametrize(
    "spread, message",
    [
        # (b / spread) ** 2 raised OverflowError with a traceback
        ("1e-300", "spread 1e-300 is too small: it must be at least 1e-150"),
        # refused by the classifier once the data was read (exit code 1)
        ("1e300", "spread 1e+300 is too large: it must be at most 1e+150"),
    ],
)
def test_a_spread_beyond_the_classifiers_range_is_a_usage_error(
    tmp_path, npz, classifier, spread, message
):
    r = run("train", "--data", npz, "--out", tmp_path / "m.tcm", "--classifier", classifier,
            "--spread", spread)  # fmt: skip
    one_line_error(r, message)
    assert r.exit_code == 2
    assert not (tmp_path / "m.tcm").exists()


def _edit_info(src, dst, **changes):
    """A copy of the model file ``src`` whose metadata's info has ``changes`` (None: removed)."""
    with zipfile.ZipFile(src) as zf:
        members = {name: zf.read(name) for name in zf.namelist()}
    meta = json.loads(members["metadata.json"])
    for key, value in changes.items():
        where, _, field = key.rpartition("__")
        target = meta["info"][where] if where else meta["info"]
        if value is None:
            target.pop(field, None)
        else:
            target[field] = value
    members["metadata.json"] = json.dumps(meta).encode()
    with zipfile.ZipFile(dst, "w") as zf:
        for name, data in members.items():
            zf.writestr(name, data)
    return dst


@pytest.mark.parametrize(
    "n_links, message",
    [
        # arrays of 24 angles were then refused by the classifier ("X has 24 features, but
        # FourierClassifier is expecting 16"), arrays of 16 as "trained for a chain of 24 links"
        (16, "info says a chain of 16 links, but the model takes arrays of 24 angles"),
        (True, "info chain n_links must be an integer, got True"),  # "a chain of True links"
        (0, "info chain n_links must be at least 1, got 0"),  # "a chain of 0 links"
        ("sixteen", "info chain n_links must be an integer, got 'sixteen'"),  # ignored
    ],
)
def test_a_model_file_whose_chain_length_was_edited_is_named(tmp_path, npz, n_links, message):
    out = tmp_path / "m.tcm"
    assert run("train", "--data", npz, "--out", out).exit_code == 0
    edited = _edit_info(out, tmp_path / "e.tcm", chain__n_links=n_links)
    for n in (16, 24):
        r = run("classify", "--model", edited, " ".join(["pi/12"] * n))
        one_line_error(r, f"e.tcm: {message}")
        assert r.exit_code == 1


@pytest.mark.parametrize(
    "threshold, message",
    [
        (True, "info reject_below must be a number in [0, 1], got True"),  # rejected every array
        (-5, "info reject_below must be a number in [0, 1], got -5"),  # rejected none
        (1e300, "info reject_below must be a number in [0, 1], got 1e+300"),
        ("0.5", "info reject_below must be a number in [0, 1], got '0.5'"),  # "no threshold"
    ],
)
def test_a_model_file_whose_rejection_threshold_was_edited_is_named(
    tmp_path, npz, threshold, message
):
    out = tmp_path / "m.tcm"
    assert run("train", "--data", npz, "--out", out).exit_code == 0
    edited = _edit_info(out, tmp_path / "e.tcm", reject_below=threshold)
    r = run("classify", "--model", edited, "--reject", " ".join(["pi/12"] * 24))
    one_line_error(r, f"e.tcm: {message}")
    assert r.exit_code == 1
    # without --reject the threshold is not read
    assert run("classify", "--model", edited, " ".join(["pi/12"] * 24)).exit_code == 0
