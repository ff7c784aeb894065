"""Wrong input gives one line and a non-zero exit code, never a traceback."""

from importlib.resources import files

import numpy as np
import pytest
from click.testing import CliRunner

from tentaclass.cli.main import cli


def run(*args):
    return CliRunner().invoke(cli, list(args), catch_exceptions=False, prog_name="tentaclass")


def one_line(r):
    lines = [line for line in r.output.splitlines() if line.strip()]
    assert len(lines) == 1, r.output
    assert lines[0].startswith("Error: ")
    return lines[0]


@pytest.mark.parametrize(
    "args, command, message",
    [
        (["nosuch"], "tentaclass", "No such command 'nosuch'"),
        (["--bogus"], "tentaclass", "No such option '--bogus'"),
        (["wrap", "--links", "0"], "tentaclass wrap", "'--links': 0 is not in the range"),
        (["wrap", "--shape", "circle", "--size", "nan"], "tentaclass wrap", "radius must be"),
        (["wrap", "--shape", "polygon"], "tentaclass wrap", "--shape polygon needs --vertices"),
        (["train"], "tentaclass train", "Missing option '--out'"),
        (["train", "--data", "missing.npz", "--out", "m.tcm"], "tentaclass train", "missing.npz"),
        (["classify", "nan 0 0"], "tentaclass classify", "'nan' is not a number"),
        (["classify", "--reject-below", "2", "0 0 0 pi/2"], "tentaclass classify", "0<=x<=1"),
        (["scan", "--simulate", "-3"], "tentaclass scan", "-3 is not in the range"),
        (["bench", "--folds", "1"], "tentaclass bench", "1 is not in the range"),
        (["demo", "--noise", "-1"], "tentaclass demo", "-1.0 is not in the range"),
        (["serve", "--port", "-1"], "tentaclass serve", "-1 is not in the range"),
        (["grasp", "--links", "10" * 11], "tentaclass grasp", "at most 496 links (one body nested"),
        (["bench", "--links", "10" * 11], "tentaclass bench", "not in the range 3<=x<=100000"),
        (["bench", "--samples", "10" * 11], "tentaclass bench", "not in the range 8<=x<=100000000"),
        (
            ["bench", "--noise", "1e300"],
            "tentaclass bench",
            "1e+300 is not in the range 0<=x<=6.28",
        ),
        (["demo", "--noise", "1e300"], "tentaclass demo", "1e+300 is not in the range 0<=x<=6.28"),
        (["wrap", "--noise", "1e300"], "tentaclass wrap", "1e+300 is not in the range 0<=x<=6.28"),
        (
            ["wrap", "--plot", "no/such/dir/w.png"],
            "tentaclass wrap",
            "'no/such/dir' does not exist",
        ),
        (["grasp", "--gif", "no/such/g.gif"], "tentaclass grasp", "'no/such' does not exist"),
        (["train", "--out", "no/such/m.tcm"], "tentaclass train", "'no/such' does not exist"),
        (
            ["scan", "--annotate", "no/a.png"],
            "tentaclass scan",
            "'--annotate': the folder 'no' does",
        ),
        (
            ["scan", "--write-belt", "no/b.pbm"],
            "tentaclass scan",
            "'--write-belt': the folder 'no'",
        ),
        (
            ["classify", "--reject-below", "nan", "0 0 0 pi/2"],
            "tentaclass classify",
            "'--reject-below': must be a finite number, got nan",
        ),
        (["wrap", "--start", "nan"], "tentaclass wrap", "'--start': must be a finite number"),
        (["wrap", "--offset", "inf"], "tentaclass wrap", "'--offset': must be a finite number"),
        (["grasp", "--friction", "nan"], "tentaclass grasp", "'--friction': must be a finite"),
        (["scan", "-", "--contrast", "nan"], "tentaclass scan", "'--contrast': must be a finite"),
        (
            ["classify", "--out-dir", "labels", "0 0 0 pi/2"],
            "tentaclass classify",
            "--out-dir needs --files",
        ),
        (
            ["classify", "--files", "*.csv", "--out-dir", "labels", "--reject"],
            "tentaclass classify",
            "--reject does not go with --files",
        ),
        (
            ["classify", "--files", "*.csv", "--out-dir", "labels", "--json"],
            "tentaclass classify",
            "--json does not go with --files",
        ),
        (["scan", "-", "--out-dir", "objects"], "tentaclass scan", "--out-dir needs --files"),
        (
            ["scan", "-", "--random-state", "3"],
            "tentaclass scan",
            "--random-state needs --simulate",
        ),
        (
            ["scan", "--simulate", "2", "--dtype", "uint8"],
            "tentaclass scan",
            "--dtype describes an input file; --simulate has none",
        ),
        (
            ["wrap", "--shape", "circle", "--vertices", "0,0 1,0 0,1"],
            "tentaclass wrap",
            "--vertices is for --shape polygon or triangle, not circle",
        ),
        (
            ["grasp", "--shape", "polygon", "--vertices", "0,0 1,0 0,1", "--size", "3"],
            "tentaclass grasp",
            "give either --size or --vertices, not both",
        ),
        # figure formats are checked before any work (they failed after it, scan after
        # printing every object)
        (["wrap", "--plot", "w.xyz"], "tentaclass wrap", "'w.xyz': cannot write .xyz; use .eps"),
        (
            ["scan", "--simulate", "2", "--annotate", "b.xyz"],
            "tentaclass scan",
            "'--annotate': 'b.xyz': cannot write .xyz; use .eps",
        ),
        (["grasp", "--gif", "g.png"], "tentaclass grasp", "'g.png': cannot write .png; use .gif"),
        # a number beyond float64 was read as inf, then refused as "NaN or infinite" (exit 1)
        (["classify", "1e400 0 0 pi/2"], "tentaclass classify", "'1e400' is too large: not a"),
        # ... as was a product or quotient beyond float64 (1e308*pi: 'ANGLES contains 1 NaN or
        # infinite value(s)', exit 1); pi/1e400 was read as 0
        (["classify", "1e308*pi 0 0 pi"], "tentaclass classify", "'1e308*pi' is too large: not"),
        (["classify", "1/1e-320 0 0 pi"], "tentaclass classify", "'1/1e-320' is too large: not"),
        (["classify", "pi/1e400 0 0 pi"], "tentaclass classify", "'pi/1e400' is too large: not"),
        # options of one dataset given with another (they were ignored)
        (
            ["bench", "--name", "SwedishLeaf"],
            "tentaclass bench",
            "--name: applies to --dataset ucr only, not to --dataset reference",
        ),
        (
            ["bench", "--dataset", "ArrowHead", "--ucr-path", "."],
            "tentaclass bench",
            "--ucr-path: applies to --dataset ucr only, not to --dataset ArrowHead",
        ),
        (
            ["bench", "--dataset", "synthetic", "--data-dir", "mpeg7"],
            "tentaclass bench",
            "--data-dir: applies to --dataset mpeg7 only, not to --dataset synthetic",
        ),
        # a threshold that is no finite number was refused by the scanner once the first rows
        # were read (exit code 1); --files without --out-dir after loading the model (exit 1)
        (
            ["scan", "-", "--threshold", "nan"],
            "tentaclass scan",
            "--threshold: must be a finite number or auto, binary, fixed or adaptive, got 'nan'",
        ),
        (["scan", "-", "--threshold", "1e400"], "tentaclass scan", "finite number or auto"),
        (["scan", "--files", "*.pbm"], "tentaclass scan", "--files needs --out-dir, the folder"),
        (["classify", "--files", "*.npy"], "tentaclass classify", "--files needs --out-dir"),
        # a belt --simulate cannot make was an error of exit code 1
        (
            ["scan", "--simulate", "1", "--width", "3"],
            "tentaclass scan",
            "lanes of 3 pixels are too narrow for objects of circumradius up to 20.0",
        ),
        # an empty name was the current folder (or, for a file, failed once the work was done)
        (["train", "--out", ""], "tentaclass train", "'--out': the file name is empty"),
        (
            ["classify", "--files", "*.npy", "--out-dir", ""],
            "tentaclass classify",
            "'--out-dir': the folder name is empty (give '.' for the current folder)",
        ),
        (["bench", "--out", ""], "tentaclass bench", "the folder name is empty"),
        # options of one dataset or protocol given with another (they were ignored; the
        # README's mpeg7 example read as if --jobs -1 wrapped the default protocol on every core)
        (
            ["bench", "--dataset", "ArrowHead", "--folds", "5"],
            "tentaclass bench",
            "--folds: applies to --dataset reference, synthetic, mpeg7 only, not to --dataset "
            "ArrowHead",
        ),
        (
            ["bench", "--copies", "3"],
            "tentaclass bench",
            "--copies: applies to --dataset mpeg7 only, not to --dataset reference",
        ),
        (
            ["bench", "--dataset", "synthetic", "--samples", "40", "--protocol", "one-lap"],
            "tentaclass bench",
            "--protocol: applies to --dataset mpeg7 only, not to --dataset synthetic",
        ),
        (
            ["bench", "--dataset", "mpeg7", "--jobs", "-1"],
            "tentaclass bench",
            "--jobs: applies to --protocol one-lap only, not to --protocol fixed-chain",
        ),
        (
            ["bench", "--dataset", "mpeg7", "--protocol", "one-lap", "--laps", "1,2"],
            "tentaclass bench",
            "--laps: applies to --protocol fixed-chain only, not to --protocol one-lap",
        ),
        (
            ["bench", "--mode", "hug"],
            "tentaclass bench",
            "--mode: applies to --dataset synthetic, mpeg7 only, not to --dataset reference",
        ),
    ],
)
def test_usage_errors_take_one_line(args, command, message):
    r = run(*args)
    assert r.exit_code == 2
    line = one_line(r)
    assert message in line
    assert line.endswith(f"(see '{command} -h')")


def test_no_command_still_shows_the_help():
    r = run()
    assert "Commands:" in r.output and "classify" in r.output


def _empty_angle_files(folder, n):
    import pyarrow as pa
    import pyarrow.parquet as pq

    folder.mkdir()
    np.save(folder / "a.npy", np.zeros((0, n)))
    table = pa.table({f"q{i}": pa.array(np.zeros(0)) for i in range(n)})
    pq.write_table(table, folder / "b.parquet")
    (folder / "c.csv").write_text("")
    (folder / "d.txt").write_text("# comments only\n\n")
    np.save(folder / "e.npy", np.zeros(0))
    return sorted(folder.iterdir())


def test_classify_files_empty_input_gives_an_empty_table(tmp_path):
    import pyarrow.csv as pcsv
    import pyarrow.parquet as pq

    from tentaclass.io import bundled_links

    n = bundled_links()[0]
    model = str(files("tentaclass.data") / f"default-{n}.tcm")
    src = tmp_path / "in"
    inputs = _empty_angle_files(src, n)
    columns = ["index", "label", "probability", "p_circle", "p_rectangle", "p_square", "p_triangle"]
    for extra in ([], ["--model", model]):
        out = tmp_path / f"out{len(extra)}"
        r = run("classify", "--files", str(src / "*"), "--out-dir", str(out), *extra)
        assert r.exit_code == 0, r.output
        for path in inputs:
            suffix = ".parquet" if path.suffix == ".parquet" else ".csv"
            dst = out / f"{path.stem}.labels{suffix}"
            assert f"{path}: no rows -> {dst} (empty)" in r.output.splitlines()
            table = pq.read_table(dst) if suffix == ".parquet" else pcsv.read_csv(dst)
            assert table.num_rows == 0
            assert table.column_names == columns


@pytest.mark.parametrize("command", ["wrap", "grasp"])
def test_a_mask_that_is_not_an_image_of_an_object_is_an_input_error(tmp_path, command):
    # a file that exists but holds no image (or no object) is bad input, exit code 1 as
    # for classify --model or scan: it was a usage error (exit code 2, "see -h")
    from PIL import Image

    (tmp_path / "text.png").write_text("not an image")
    (tmp_path / "empty.png").write_bytes(b"")
    Image.new("L", (20, 20), 255).save(tmp_path / "blank.png")
    for name, message in [
        ("text.png", "text.png: cannot read the image (UnidentifiedImageError"),
        ("empty.png", "empty.png: cannot read the image (UnidentifiedImageError"),
        ("blank.png", "blank.png: no object found"),
    ]:
        r = run(command, "--mask", str(tmp_path / name))
        assert r.exit_code == 1, r.output
        line = one_line(r)
        assert line.startswith(f"Error: {tmp_path / message}") and "-h'" not in line


@pytest.mark.parametrize("command", ["classify", "scan"])
def test_an_out_dir_that_cannot_be_made_is_a_usage_error_naming_the_option(tmp_path, command):
    # it was "[Errno 20] Not a directory" alone, after the inputs were read
    (tmp_path / "a.txt").write_text("0 0 0 1.5707963 " * 4 + "\n")
    (tmp_path / "file").write_text("")
    r = run(command, "--files", str(tmp_path / "a.txt"), "--out-dir", str(tmp_path / "file/out"))
    assert r.exit_code == 2
    assert one_line(r).startswith("Error: Invalid value for --out-dir: cannot create the folder")


def test_classify_file_without_rows_is_the_same_error_for_every_kind(tmp_path):
    for path in _empty_angle_files(tmp_path / "in", 16):
        r = run("classify", "--file", str(path))
        assert r.exit_code == 1
        assert one_line(r) == f"Error: {path}: no rows (no angle arrays in it)"


def test_classify_file_reads_parquet_as_classify_files_does(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    X = np.tile([0, 0, 0, np.pi / 2], (3, 4))
    pq.write_table(pa.table({f"q{i}": X[:, i] for i in range(16)}), tmp_path / "a.parquet")
    np.save(tmp_path / "a.npy", X)
    by_parquet = run("classify", "--json", "--file", str(tmp_path / "a.parquet"))
    assert by_parquet.exit_code == 0, by_parquet.output
    assert by_parquet.output == run("classify", "--json", "--file", str(tmp_path / "a.npy")).output


def test_classify_files_warns_once_per_chain_length_without_a_bundled_model(tmp_path):
    import pyarrow.csv as pcsv

    X = np.full((2, 24), 2 * np.pi / 24)
    for name in ("a", "b"):
        np.save(tmp_path / f"{name}.npy", X)
    (tmp_path / "c.csv").write_text("\n".join(",".join(["2*pi/20"] * 20) for _ in range(3)))
    r = CliRunner().invoke(cli, ["classify", "--files", str(tmp_path / "*"), "--out-dir",
                                 str(tmp_path / "o")])  # fmt: skip
    assert r.exit_code == 0, r.output
    warnings = [line for line in r.stderr.splitlines() if line.startswith("warning: ")]
    assert [w.split(" links")[0] for w in warnings] == [
        "warning: no bundled model for 20",
        "warning: no bundled model for 24",
    ]
    assert "using the one-lap reference shapes" in warnings[0]
    for name, n in (("a", 2), ("b", 2), ("c", 3)):
        labels = pcsv.read_csv(tmp_path / "o" / f"{name}.labels.csv").column("label").to_pylist()
        assert labels == ["circle"] * n


@pytest.mark.parametrize(
    "content, message",
    [
        ("0 " * 15 + "pi\n" + "0 " * 16 + "pi\n", "rows have different numbers of angles [16, 17]"),
        ("0 0\n", "arrays of 2 joint angles; a wrap has at least 3"),
        ("0 0 0 x\n", "line 1: 'x' is not a number"),
    ],
)
def test_classify_files_refuses_bad_text_files_naming_them(tmp_path, content, message):
    (tmp_path / "a.csv").write_text(content)
    r = run("classify", "--files", str(tmp_path / "a.csv"), "--out-dir", str(tmp_path / "o"))
    assert r.exit_code == 1
    assert one_line(r).startswith(f"Error: {tmp_path / 'a.csv'}")
    assert message in one_line(r)


def test_classify_files_refuses_a_text_file_of_another_chain_length_before_any_work(tmp_path):
    from tentaclass.io import bundled_links

    n = bundled_links()[0]
    model = str(files("tentaclass.data") / f"default-{n}.tcm")
    np.save(tmp_path / "a.npy", np.tile([0, 0, 0, np.pi / 2], (3, n // 4)))
    (tmp_path / "b.csv").write_text(" ".join(["pi/10"] * (n + 4)))
    out = tmp_path / "o"
    r = run("classify", "--files", str(tmp_path / "*"), "--out-dir", str(out), "--model", model)
    assert r.exit_code == 1
    assert f"b.csv: arrays of {n + 4} joint angles, but the model expects {n}" in one_line(r)
    assert not out.exists()


def test_classify_files_refuses_angles_that_are_not_radians(tmp_path):
    X = np.tile([0, 0, 0, np.pi / 2], (3, 4))
    X[1] = 1e300
    np.save(tmp_path / "a.npy", X)
    r = run("classify", "--files", str(tmp_path / "a.npy"), "--out-dir", str(tmp_path / "o"))
    assert r.exit_code == 1
    assert "array 1 holds an angle of 1e+300 rad, beyond 2**20 turns" in one_line(r)
    assert not (tmp_path / "o" / "a.labels.csv").exists()


def test_classify_refuses_angles_that_are_not_radians_as_classify_files(tmp_path):
    X = np.tile([0, 0, 0, np.pi / 2], (3, 4))
    X[1, :8], X[1, 8:] = 1e300, -1e300  # a sum that cancels: the size of each angle counts
    np.save(tmp_path / "a.npy", X)
    r = run("classify", "--file", str(tmp_path / "a.npy"))
    assert r.exit_code == 1
    assert f"{tmp_path / 'a.npy'}: array 1 holds an angle of 1e+300 rad, beyond" in one_line(r)
    r = run("classify", " ".join(["1e300"] * 16))
    assert "ANGLES: array 0 holds an angle of 1e+300 rad" in one_line(r)


def test_train_refuses_angles_that_are_not_radians(tmp_path):
    X = np.tile([0, 0, 0, np.pi / 2], (4, 4))
    X[2, 5] = -1e300
    np.savez(tmp_path / "d.npz", X=X, y=np.array(["a", "a", "b", "b"]))
    r = run("train", "--data", str(tmp_path / "d.npz"), "--out", str(tmp_path / "m.tcm"))
    assert r.exit_code == 1
    assert "d.npz: array 2 holds an angle of -1e+300 rad" in one_line(r)
    assert not (tmp_path / "m.tcm").exists()


def test_the_script_shows_warnings_on_one_line(tmp_path):
    import subprocess
    import sys

    folder = tmp_path / "shapes"
    folder.mkdir()
    (folder / "a-1.png").write_bytes(b"not an image")
    args = ["bench", "--dataset", "mpeg7", "--data-dir", str(folder)]
    r = subprocess.run(
        [sys.executable, "-m", "tentaclass", *args], capture_output=True, text=True, timeout=120
    )
    assert r.returncode == 1
    lines = r.stderr.splitlines()
    assert len(lines) == 2, r.stderr
    assert lines[0].startswith("warning: load_mpeg7 skipped 1 unreadable image(s)")
    assert lines[1].startswith("Error: no readable .png files")


@pytest.mark.parametrize(
    "args, message",
    [
        (["--laps", "1e300"], "laps: 16 links cannot close 1e+300 laps (at most 8"),
        (["--diameters", "2,1e300"], "diameters must be at most 1e+12 link lengths"),
        (["--diameters", "1e13,1e14"], "diameters must be at most 1e+12 link lengths (links"),
        (["--noise", "1e300"], "noise must be at most 2*pi radians"),
    ],
)
def test_train_outlines_refuses_sizes_beyond_reason(tmp_path, args, message):
    from tentaclass.shapes import circle, square

    np.save(tmp_path / "sq-1.npy", square(4.0))
    np.save(tmp_path / "ci-1.npy", circle(2.0))
    r = run("train", "--outlines", str(tmp_path / "*.npy"), "--links", "16",
            "--out", str(tmp_path / "m.tcm"), *args)  # fmt: skip
    assert r.exit_code == 2  # usage errors, found before the outlines are read (was 1)
    assert message in one_line(r)
    assert not (tmp_path / "m.tcm").exists()


def test_train_refuses_a_spread_too_large_to_tell_classes_apart(tmp_path):
    X = np.vstack([np.tile([0, 0, 0, np.pi / 2], (4, 4)), np.full((4, 16), 2 * np.pi / 16)])
    np.savez(tmp_path / "d.npz", X=X, y=np.array(["sq"] * 4 + ["ci"] * 4))
    r = run("train", "--data", str(tmp_path / "d.npz"), "--spread", "1e300",
            "--out", str(tmp_path / "m.tcm"))  # fmt: skip
    assert r.exit_code == 2  # a usage error, found before the data is read (was 1)
    assert "spread 1e+300 is too large: it must be at most 1e+150" in one_line(r)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--min-area", "10" * 11], "1010101010101010101010 is not in the range 1<=x<=92233"),
        (["--max-height", "10" * 11], "'--max-height': 1010101010101010101010 is not in the"),
        (["--format", "raw", "--width", "10" * 11], "not in the range 1<=x<=2147483647"),
        (["--chunk-rows", "10" * 11], "'--chunk-rows': 1010101010101010101010 is not in the range"),
        (["--simulate", "10" * 11], "not in the range 1<=x<=100000000"),
    ],
)
def test_scan_refuses_counts_too_large_for_the_kernels(tmp_path, args, message):
    # usage errors, found as the options are read: the scanner refused them once the first
    # rows were read (exit code 1)
    (tmp_path / "belt.pbm").write_text("P1\n3 2\n0 1 0\n1 1 1\n")
    r = run("scan", *args, str(tmp_path / "belt.pbm"))
    assert r.exit_code == 2
    assert message in one_line(r)


def test_an_output_file_in_a_missing_folder_is_refused_before_any_work(tmp_path):
    r = run("wrap", "--plot", str(tmp_path / "no" / "w.png"))
    assert r.exit_code == 2
    assert "Invalid value for '--plot': the folder" in one_line(r)
    assert r.stdout == ""  # no angles printed before the error
    r = run("wrap", "--links", "8", "--plot", str(tmp_path / "w.png"))
    assert r.exit_code == 0 and (tmp_path / "w.png").stat().st_size > 0


def test_classify_refuses_encoder_counts(tmp_path):
    # raw counts of a 2**24-step encoder: far beyond any joint angle in radians
    r = run("classify", " ".join(["0", "0", "0", "4194304"] * 4 + ["1e7"]))
    assert r.exit_code == 1
    assert one_line(r) == (
        "Error: ANGLES: array 0 holds an angle of 1e+07 rad, beyond 2**20 turns "
        "(6.588e+06 rad): are these joint angles in radians?"
    )


@pytest.mark.parametrize("command", ["classify", "scan"])
def test_a_model_folder_is_refused_on_one_line(tmp_path, command):
    args = ["--model", str(tmp_path)] + (["0 0 pi/2"] if command == "classify" else [])
    r = run(command, *args)
    assert r.exit_code == 2
    assert "is a directory" in one_line(r)


def test_classify_names_ragged_rows(tmp_path):
    (tmp_path / "a.csv").write_text("0 0 pi/2 0\n0 0 pi/2\n")
    r = run("classify", "--file", str(tmp_path / "a.csv"))
    assert r.exit_code == 1
    message = f"Error: {tmp_path / 'a.csv'}: rows have different numbers of angles [3, 4]"
    assert one_line(r) == message


def test_options_of_the_other_way_to_train_are_refused(tmp_path):
    data = tmp_path / "train.npz"
    np.savez(data, X=np.tile([0.0, 0.0, 0.0, np.pi / 2], (4, 4)), y=np.array(["a", "b"] * 2))
    out = str(tmp_path / "m.tcm")
    for extra, message in (
        (["--links", "16"], "--links is for --outlines"),
        (["--reject-rate", "0.1"], "--reject-rate is for --outlines"),
        (["--random-state", "1"], "--random-state is for --outlines"),
    ):
        r = run("train", "--data", str(data), "--out", out, *extra)
        assert r.exit_code == 2 and message in one_line(r)
    for extra, message in (
        (["--spread", "3"], "--spread is for --data"),
        (["--no-detrend"], "--detrend/--no-detrend is for --data"),
        (["--classifier", "rbf"], "--classifier is for --data"),
    ):
        r = run("train", "--outlines", str(tmp_path / "*.csv"), "--links", "16", "--out", out,
                *extra)  # fmt: skip
        assert r.exit_code == 2 and message in one_line(r)
    assert not (tmp_path / "m.tcm").exists()


@pytest.mark.parametrize("command", [["bench", "--samples", "8"], ["demo"]])
def test_an_output_folder_that_cannot_be_made_is_refused_before_any_work(tmp_path, command):
    blocker = tmp_path / "file"
    blocker.write_text("")
    r = run(*command, "--out", str(blocker / "results"))
    assert r.exit_code == 2
    line = one_line(r)
    assert f"cannot create the folder '{blocker / 'results'}'" in line
    assert "Not a directory" in line


def test_files_of_one_folder_sharing_a_name_are_named_as_such(tmp_path):
    np.save(tmp_path / "log.npy", np.zeros((1, 16)))
    (tmp_path / "log.csv").write_text("")
    r = run("classify", "--files", str(tmp_path / "log.*"), "--out-dir", str(tmp_path / "o"))
    assert r.exit_code == 1
    assert "files share the name 'log' (without their suffix)" in one_line(r)


def test_text_files_with_a_byte_order_mark_are_read(tmp_path):
    # spreadsheets save "CSV UTF-8" with a byte-order mark: it was "'\ufeff0' is not a number"
    row = ",".join(["0", "0", "0", "pi/2"] * 4)
    bom = tmp_path / "bom.csv"
    bom.write_bytes(b"\xef\xbb\xbf" + row.encode() + b"\n")
    r = run("classify", "--file", str(bom), "--json")
    assert r.exit_code == 0, r.output
    assert '"label": "square"' in r.output
    piped = CliRunner().invoke(cli, ["classify", "--json"], input=bom.read_bytes())
    assert piped.exit_code == 0 and piped.output == r.output
    train = tmp_path / "train.csv"
    rows = [f"{row},square" if i % 2 else f"{','.join(['pi/8'] * 16)},circle" for i in range(4)]
    train.write_bytes(b"\xef\xbb\xbf" + "\n".join(rows).encode())
    r = run("train", "--data", str(train), "--out", str(tmp_path / "m.tcm"))
    assert r.exit_code == 0 and "2 classes (circle, square)" in r.output, r.output
    latin = tmp_path / "latin.csv"
    latin.write_bytes(row.encode() + "  # é\n".encode("latin-1"))
    r = run("classify", "--file", str(latin))
    assert r.exit_code == 1 and one_line(r) == f"Error: {latin}: not a text file"


@pytest.mark.parametrize(
    "command, message",
    [
        (["scan", "-"], "Error: cannot read standard input: it is closed"),  # was a traceback
        (["classify"], "Error: give either ANGLES or --file, or pipe angle arrays into stdin"),
    ],
)
def test_a_closed_standard_input_is_one_line(command, message):
    import os
    import subprocess
    import sys

    r = subprocess.run(
        [sys.executable, "-m", "tentaclass", *command],
        capture_output=True, text=True, timeout=120, preexec_fn=lambda: os.close(0),
    )  # fmt: skip
    assert r.returncode == 1
    assert r.stderr.strip() == message


@pytest.mark.parametrize(
    "data, message",
    [
        # bytes that are not UTF-8 were read as lone surrogates: "'\udcff\udcfe' is not a number"
        (b"\xff\xfe\x00\x01", "Error: standard input: not UTF-8 text (angle arrays, one per line)"),
        # an empty pipe was told to pipe angle arrays into stdin
        (b"", "Error: standard input holds no angle arrays: give ANGLES or --file, or pipe"),
        (b"# a comment only\n\n", "Error: standard input holds no angle arrays"),
    ],
)
def test_classify_names_standard_input_that_is_binary_or_empty(data, message):
    import subprocess
    import sys

    r = subprocess.run(
        [sys.executable, "-m", "tentaclass", "classify"], input=data, capture_output=True,
        timeout=120,
    )  # fmt: skip
    assert r.returncode == 1
    assert r.stderr.decode().strip().startswith(message)
    assert len(r.stderr.decode().strip().splitlines()) == 1


def test_angles_in_degrees_are_refused(tmp_path):
    # a square in degrees (90 per corner) was a RECTANGLE with probability 1.000
    degrees = " ".join(["0 0 0 90"] * 4)
    message = "turns 57.3 laps in total, more than 16 joints can (8 laps, pi each): are these"
    r = run("classify", degrees)
    assert r.exit_code == 1 and message in one_line(r)
    np.save(tmp_path / "deg.npy", np.vstack([np.tile([0.0, 0.0, 0.0, np.pi / 2], 4)] * 2
                                            + [np.tile([0.0, 0.0, 0.0, 90.0], 4)]))  # fmt: skip
    r = run("classify", "--files", str(tmp_path / "deg.npy"), "--out-dir", str(tmp_path / "o"))
    assert r.exit_code == 1 and f"deg.npy: array 2 {message}" in one_line(r)
    data = tmp_path / "train.npz"
    X = np.vstack([np.tile([0.0, 0.0, 0.0, 90.0], 4), np.full(16, 22.5)])
    np.savez(data, X=X, y=np.array(["square", "circle"]))
    r = run("train", "--data", str(data), "--out", str(tmp_path / "m.tcm"))
    assert r.exit_code == 1 and "train.npz: array 0 turns 57.3 laps" in one_line(r)
    # a chain folded flat turns exactly n * pi: the bound itself is accepted
    assert run("classify", " ".join(["pi"] * 16)).exit_code == 0


@pytest.mark.parametrize("read_first_line", [True, False])
def test_a_reader_closing_the_pipe_early_ends_the_command_quietly(tmp_path, read_first_line):
    # `tentaclass classify ... | head -1` ended with "Error: [Errno 32] Broken pipe"
    import subprocess
    import sys

    square = np.tile([0.0, 0.0, 0.0, np.pi / 2], 4)
    rows = 20_000 if read_first_line else 1  # far more output than a pipe buffers
    np.save(tmp_path / "many.npy", np.tile(square, (rows, 1)))
    with subprocess.Popen(
        [sys.executable, "-m", "tentaclass", "classify", "--file", str(tmp_path / "many.npy")],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    ) as proc:  # fmt: skip
        assert proc.stdout is not None and proc.stderr is not None
        if read_first_line:
            assert proc.stdout.readline().split() == [b"index", b"class", b"probability"]
        proc.stdout.close()  # the reader goes before the command has written all (or any)
        stderr = proc.stderr.read()
        assert proc.wait(timeout=120) == 141
    assert stderr == b""


def test_arrays_longer_than_the_reference_shapes_name_the_limit(tmp_path):
    n = 1_000_004
    np.save(tmp_path / "long.npy", np.full((1, n), 2 * np.pi / n))
    r = run("classify", "--file", str(tmp_path / "long.npy"))
    assert r.exit_code == 1
    assert "arrays of 1,000,004 angles are longer than the reference shapes are built for " \
        "(at most 1,000,000); classify them with --model" in one_line(r)  # fmt: skip
