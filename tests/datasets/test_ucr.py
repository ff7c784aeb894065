"""load_ucr reads UCR .tsv and UEA .ts files and names every line it cannot read."""

import numpy as np
import pytest

from tentaclass.datasets import load_ucr
from tentaclass.errors import InputError


def _data_set(tmp_path, train, test=None, ext="tsv"):
    folder = tmp_path / "Toy"
    folder.mkdir()
    for split, text in (("TRAIN", train), ("TEST", train if test is None else test)):
        path = folder / f"Toy_{split}.{ext}"
        if isinstance(text, bytes):
            path.write_bytes(text)
        else:
            path.write_text(text)
    return folder


def test_reads_both_formats_alike(tmp_path):
    tsv = load_ucr(_data_set(tmp_path, "a\t0\t1\t2\nb\t2\t1.5\t0\n"))
    (tmp_path / "ts").mkdir()
    text = "@univariate true\n@data\n0,1,2:a\n2,1.5,0:b\n"
    ts = load_ucr(_data_set(tmp_path / "ts", text, ext="ts"))
    np.testing.assert_array_equal(tsv.data, [[0, 1, 2], [2, 1.5, 0]] * 2)
    np.testing.assert_array_equal(ts.data, tsv.data)
    assert tsv.target.tolist() == ts.target.tolist() == ["a", "b", "a", "b"]


@pytest.mark.parametrize(
    ("train", "ext", "match"),
    [
        # were read as series of 0 values, or with '' as a class
        ("1 0 1 2\n2 2 1 0\n", "tsv", r"Toy_TRAIN.tsv: no tab on any line: UCR .tsv files hold"),
        ("1,0,1,2\n2,2,1,0\n", "tsv", "no tab on any line"),
        ("1\t0\t1\n2\n", "tsv", r"Toy_TRAIN.tsv: line 2 holds a label and no values"),
        ("1\t0\t1\n\t2\t1\n", "tsv", r"Toy_TRAIN.tsv: line 2 has no class label"),
        ("@data\n1,2,3:\n", "ts", r"Toy_TRAIN.ts: line 2 has no class label"),
        ("@data\n:a\n", "ts", r"Toy_TRAIN.ts: line 2 holds a label and no values"),
        # was 'multivariate .ts files are not supported'
        ("@data\n1,2,3\n", "ts", r"Toy_TRAIN.ts: line 2 has no ':' before a class label"),
        # was a UnicodeDecodeError
        (b"\xff\xfe\x00\x01", "tsv", r"Toy_TRAIN.tsv: not a UTF-8 text file"),
        ("1\t0\tx\t2\n", "tsv", r"line 1: a value is not a number \(.*'x'\)"),
        ("1\t0\t1\t2\n2\t2\t1\n", "tsv", r"series of different lengths \(\[2, 3\] values\)"),
        ("", "tsv", "no series in the file"),
    ],
)
def test_unreadable_files_are_named(tmp_path, train, ext, match):
    with pytest.raises(InputError, match=match):
        load_ucr(_data_set(tmp_path, train, ext=ext))


@pytest.mark.parametrize(
    ("path", "match"), [(None, "got None"), (7, "got 7"), ("", "path is an empty string")]
)
def test_a_path_that_is_not_a_file_name_is_named(path, match):
    with pytest.raises(InputError, match=match):
        load_ucr(path)
