import json

import numpy as np
import pytest
from click.testing import CliRunner

from tentaclass.cli.main import cli
from tentaclass.cli.options import parse_angle, parse_angle_list

SQUARE = "0 0 0 pi/2 0 0 0 pi/2 0 0 0 pi/2 0 0 0 pi/2"


def run(*args):
    return CliRunner().invoke(cli, list(args), catch_exceptions=False)


@pytest.mark.parametrize(
    "text, value",
    [
        ("pi/2", np.pi / 2),
        ("2*pi/3", 2 * np.pi / 3),
        ("-pi/8", -np.pi / 8),
        ("2pi", 2 * np.pi),
        ("1.5", 1.5),
        ("-.5e1", -5.0),
        ("PI", np.pi),
        ("3/4", 0.75),
        ("+pi", np.pi),
    ],
)
def test_parse_angle(text, value):
    assert parse_angle(text) == pytest.approx(value)


@pytest.mark.parametrize("text", ["x", "pi*pi", "__import__('os')", "1/0", "nan", "inf", "pi/", ""])
def test_parse_angle_refuses_everything_else(text):
    with pytest.raises(ValueError):
        parse_angle(text)


def test_parse_angle_list_separators():
    np.testing.assert_allclose(parse_angle_list("[0, pi/2; 1]"), [0, np.pi / 2, 1])


def test_classify_square_table():
    r = run("classify", SQUARE)
    assert r.exit_code == 0
    lines = r.output.splitlines()
    assert lines[0].split() == ["index", "class", "probability"]
    assert lines[1].split()[:2] == ["0", "SQUARE"]


def test_classify_json():
    r = run("classify", "--json", SQUARE)
    rows = json.loads(r.output)
    assert rows[0]["label"] == "square"
    assert rows[0]["probability"] == pytest.approx(
        max(v for k, v in rows[0].items() if k.startswith("p_"))
    )


def test_classify_csv_and_npy_files(tmp_path):
    from tentaclass.datasets import thesis_tentacle

    X, y = thesis_tentacle(64, return_X_y=True)
    rolled = np.roll(X, 5, axis=1)
    npy = tmp_path / "a.npy"
    np.save(npy, rolled)
    csv = tmp_path / "a.csv"
    csv.write_text(
        "# header comment\n" + "\n".join(",".join(repr(float(v)) for v in row) for row in rolled)
    )
    for path in (npy, csv):
        rows = json.loads(run("classify", "--json", "--file", str(path)).stdout)
        assert [r["label"] for r in rows] == y.tolist()


def test_classify_any_chain_length():
    circle = " ".join(["2*pi/24"] * 24)
    assert "CIRCLE" in run("classify", circle).output


@pytest.mark.parametrize(
    "args, message",
    [
        (["classify", "0 0 x"], "not a number"),
        (["classify", "0 0"], "at least 3"),
        (["classify"], "give ANGLES or --file, or pipe angle arrays into stdin"),
        (["classify", "--file", "missing.csv"], "does not exist"),
        (["demo", "--noise", "nan", "--no-figures"], "finite"),
        (["demo", "--noise", "inf", "--no-figures"], "inf is not in the range 0<=x<=6.28"),
        (["demo", "--random-state", "-1", "--no-figures"], "--random-state"),
    ],
)
def test_classify_bad_input_one_line_error(args, message):
    r = run(*args)
    assert r.exit_code != 0
    assert message in r.output
    assert "Traceback" not in r.output


def test_classify_bad_files(tmp_path):
    ragged = tmp_path / "r.csv"
    ragged.write_text("0 0 pi\n0 0 pi pi\n")
    bad = tmp_path / "b.npy"
    bad.write_bytes(b"not numpy")
    nan = tmp_path / "n.npy"
    np.save(nan, np.array([[0, np.nan, 1.0]]))
    cplx = tmp_path / "c.npy"
    np.save(cplx, np.array([[1j, 0, 0, 1.0]]))  # the imaginary part must not be dropped
    for path, message in (
        (ragged, "different numbers"),
        (bad, "not a readable"),
        (nan, "NaN"),
        (cplx, "real numbers"),
    ):
        r = run("classify", "--file", str(path))
        assert r.exit_code == 1, r.output
        assert message in r.output
        assert len(r.output.strip().splitlines()) == 1


def test_demo_runs_and_writes_figures(tmp_path):
    r = run("demo", "--out", str(tmp_path))
    assert r.exit_code == 0
    for label in ("SQUARE", "CIRCLE", "TRIANGLE", "RECTANGLE"):
        assert label in r.output
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "capture_error.png",
        "grasp_spectra.png",
        "thesis_circle.png",
        "thesis_rectangle.png",
        "thesis_square.png",
        "thesis_triangle.png",
        "wraps.png",
    ]


def test_python_dash_m_entry_point():
    import subprocess
    import sys

    out = subprocess.run(
        [sys.executable, "-m", "tentaclass", "classify", "--json", SQUARE],
        capture_output=True,
        text=True,
        check=True,
    )
    assert json.loads(out.stdout)[0]["label"] == "square"


def test_garbage_npy_is_not_called_pickled(tmp_path):
    bad = tmp_path / "b.npy"
    bad.write_bytes(b"abc")  # numpy's own message claimed "pickled (object) data"
    r = run("classify", "--file", str(bad))
    assert r.exit_code == 1
    assert "no .npy header" in r.output and "pickle" not in r.output


def test_out_of_memory_is_one_line_error(monkeypatch):
    import tentaclass.datasets

    def boom(*args, **kwargs):
        raise MemoryError("Unable to allocate 262. GiB")

    monkeypatch.setattr(tentaclass.datasets, "synthetic_tentacle", boom)
    r = CliRunner().invoke(cli, ["bench", "--dataset", "synthetic", "--methods", "thesis"])
    assert r.exit_code == 1
    assert "out of memory: Unable to allocate 262. GiB" in r.output
    assert "Traceback" not in r.output and len(r.output.strip().splitlines()) == 1


def test_classify_files_outputs_have_the_permissions_of_any_new_file(tmp_path):
    import os

    np.save(tmp_path / "a.npy", np.tile([0, 0, 0, np.pi / 2], (2, 4)))
    args = ("classify", "--files", str(tmp_path / "a.npy"), "--out-dir", str(tmp_path / "o"))
    old = os.umask(0o027)
    try:
        r = run(*args)
        plain27 = tmp_path / "plain27.txt"
        plain27.write_text("")
    finally:
        os.umask(old)
    assert r.exit_code == 0, r.output
    out = tmp_path / "o" / "a.labels.csv"
    assert out.stat().st_mode & 0o777 == plain27.stat().st_mode & 0o777 == 0o640
    # written again over an existing file: that file's permissions stay
    out.chmod(0o604)
    assert run(*args).exit_code == 0
    assert out.stat().st_mode & 0o777 == 0o604


@pytest.mark.parametrize("n_links", [16, 24])  # a bundled chain length, and one without
def test_classify_files_answers_as_classify_without_a_model(tmp_path, n_links):
    import pyarrow.csv as pcsv

    from tentaclass.datasets import synthetic_tentacle

    d = synthetic_tentacle(12, n_links, laps=(0.6, 2.5), noise=0.02, random_state=4)
    np.save(tmp_path / "a.npy", d.data[np.isfinite(d.data).all(axis=1)])
    one = json.loads(run("classify", "--json", "--file", str(tmp_path / "a.npy")).stdout)
    r = run("classify", "--files", str(tmp_path / "a.npy"), "--out-dir", str(tmp_path / "o"))
    assert r.exit_code == 0, r.output
    many = pcsv.read_csv(tmp_path / "o" / "a.labels.csv").to_pylist()
    assert [row["label"] for row in many] == [row["label"] for row in one]
    for a, b in zip(many, one, strict=True):
        assert a.keys() == b.keys()
        assert [a[k] for k in a if k.startswith("p")] == pytest.approx(
            [b[k] for k in b if k.startswith("p")], rel=1e-12
        )


@pytest.mark.parametrize(
    "args, line",
    [
        (["wrap"], "grasp: once, 1.00 laps, offset 0 links"),
        (["classify", "0 0 0 pi/2 0 0 0 pi/2 0 0 0 pi/2 0 0 0 pi/2 0"], "warning: no bundled"),
        (["scan", "--simulate", "2"], "scanned "),
    ],
)
def test_quiet_leaves_only_errors_on_stderr(args, line):
    # "-q: Only errors on stderr": the grasp line, warnings and summaries were still shown
    loud = CliRunner().invoke(cli, args)
    assert loud.exit_code == 0 and line in loud.stderr
    quiet = CliRunner().invoke(cli, ["-q", *args])
    assert quiet.exit_code == 0 and quiet.stderr == ""
    assert quiet.stdout == loud.stdout
    error = CliRunner().invoke(cli, ["-q", "classify", "0 0"])
    assert error.exit_code == 1 and error.stderr.startswith("Error: ANGLES must hold")


@pytest.mark.parametrize("verbose, shown", [(0, ["WARNING: w"]), (1, ["INFO: i", "WARNING: w"])])
def test_library_loggers_set_to_info_stay_quiet_without_verbose(verbose, shown):
    # Dask's 'distributed' logger is at INFO: '--scheduler local' printed ~40 INFO lines
    import subprocess
    import sys

    code = (
        "import logging\n"
        "from tentaclass.cli.main import configure_logging\n"
        f"configure_logging({verbose}, False)\n"
        "log = logging.getLogger('distributed.scheduler')\n"
        "logging.getLogger('distributed').setLevel(logging.INFO)\n"
        "log.info('i'); log.warning('w')\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stderr.splitlines() == shown
