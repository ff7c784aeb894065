import json

import numpy as np
import pytest
from click.testing import CliRunner

from tentaclass.cli.scan import scan
from tentaclass.datasets import thesis_scanner
from tentaclass.scanner import ScannerModel
from tentaclass.scanner.io import write_pbm

BELT = np.zeros((14, 12), dtype=np.uint8)
BELT[1:4, 1:4] = 1  # square
BELT[6:12, 2:5] = 1  # rectangle ...
BELT[8, 3] = 0  # ... with a hole
TEXT = "".join("".join(map(str, r)) + "\n" for r in BELT)


def _lines(result):
    return [json.loads(line) for line in result.stdout.splitlines()]


def test_text_from_stdin_one_json_line_per_object():
    result = CliRunner().invoke(scan, ["-"], input=TEXT)
    assert result.exit_code == 0, result.output
    objs = _lines(result)
    assert [(o["id"], o["label"], o["accept"]) for o in objs] == [
        (0, "square", True),
        (1, "rectangle", False),
    ]
    assert objs[1]["defects"][0]["kind"] == "hole"
    assert "scanned 14 rows: 2 objects, 1 accepted, 1 rejected" in result.stderr


def test_raw_bytes_with_width_and_json_summary(tmp_path):
    path = tmp_path / "belt.raw"
    path.write_bytes(BELT.tobytes())
    result = CliRunner().invoke(scan, [str(path), "--width", "12", "--summary", "json"])
    assert result.exit_code == 0, result.output
    *objs, last = _lines(result)
    assert len(objs) == 2
    assert last["summary"]["objects"] == 2 and last["summary"]["defects"] == {"hole": 1}
    assert result.stderr == ""
    small = CliRunner().invoke(
        scan, [str(path), "--width", "12", "--min-area", "10", "--summary", "json"]
    )
    *objs, last = _lines(small)
    assert [o["label"] for o in objs] == ["rectangle"] and last["summary"]["ignored"] == 1


def test_pbm_and_nominal_size(tmp_path):
    path = tmp_path / "belt.pbm"
    write_pbm(path, BELT)
    result = CliRunner().invoke(scan, [str(path), "--nominal-size", "5"])
    assert result.exit_code == 0, result.output
    assert [o["accept"] for o in _lines(result)] == [False, False]


def test_bad_value_keeps_objects_already_written():
    text = TEXT + "000000000000\n" * 2 + "0000x0000000\n"
    result = CliRunner().invoke(scan, ["-", "--chunk-rows", "15"], input=text)
    assert result.exit_code == 1
    assert len(_lines(result)) == 2  # emitted before the bad line was read
    assert result.stderr.strip().splitlines() == [
        "Error: line 17 (row 16), column 4: 'x', expected 0 or 1"
    ]
    assert "Traceback" not in result.output


@pytest.mark.parametrize(
    ("args", "data", "message"),
    [
        (["-"], "", "empty stream"),
        (["-", "--width", "5"], b"\x00\x01\x00", "truncated stream"),
        (["-"], "0101\n011\n", "has 3 pixels, expected 4"),
        (["/nonexistent/belt.txt"], None, "cannot open"),
        (["-", "--format", "png"], "0101\n", "not an image Pillow can identify"),  # was a repr
        (["-"], b"P5\n4 2\n255\nabcdefgh", "unsupported Netpbm image P5"),  # was "'P'"
        (["-", "--width", "4"], "0110\n", "use --format text"),  # text read as raw bytes
    ],
)
def test_bad_input_one_line_error(args, data, message):
    result = CliRunner().invoke(scan, args, input=data)
    assert result.exit_code == 1
    assert message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_usage_errors():
    assert CliRunner().invoke(scan, []).exit_code == 2
    assert CliRunner().invoke(scan, ["-", "--simulate", "3"]).exit_code == 2
    assert CliRunner().invoke(scan, ["-", "--write-belt", "x.pbm"]).exit_code == 2


def test_simulate_annotate_and_model(tmp_path):
    d = thesis_scanner()
    model_path = tmp_path / "model.tcm"
    ScannerModel().fit(d.grids, d.target).save(model_path)
    png, pbm = tmp_path / "belt.png", tmp_path / "belt.pbm"
    result = CliRunner().invoke(
        scan,
        [
            "--simulate",
            "6",
            "--random-state",
            "3",
            "--annotate",
            str(png),
            "--write-belt",
            str(pbm),
            "--model",
            str(model_path),
        ],
    )
    assert result.exit_code == 0, result.output
    assert len(_lines(result)) == 6
    assert png.read_bytes()[:4] == b"\x89PNG" and pbm.read_bytes()[:2] == b"P4"
    again = CliRunner().invoke(scan, [str(pbm), "--model", str(model_path)])
    assert again.stdout == result.stdout


def test_damaged_model_file(tmp_path):
    bad = tmp_path / "model.tcm"
    bad.write_bytes(b"PK\x03\x04 not really")
    result = CliRunner().invoke(scan, ["-", "--model", str(bad)], input=TEXT)
    assert result.exit_code == 1
    assert "not a tentaclass model file" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_progress_bar_when_stderr_is_a_terminal(tmp_path, monkeypatch):
    import tentaclass.cli.scan as scan_module

    original = scan_module._progress
    calls = []

    def forced(total, enabled):
        calls.append((total, enabled))
        return original(total, True)

    monkeypatch.setattr(scan_module, "_progress", forced)
    path = tmp_path / "belt.txt"
    path.write_text(TEXT)
    result = CliRunner().invoke(scan, [str(path)])
    assert result.exit_code == 0, result.output
    assert calls == [(len(TEXT), False)]  # the runner's stderr is not a terminal
    assert len(_lines(result)) == 2


def test_format_and_max_height_options():
    tall = "010\n" * 8 + "000\n"
    result = CliRunner().invoke(scan, ["-", "--format", "text", "--max-height", "5"], input=tall)
    assert result.exit_code == 0, result.output
    (obj,) = _lines(result)
    assert obj["label"] is None and obj["defects"][0]["kind"] == "too_tall"
    assert "1 rejected (unclassified 1)" in result.stderr  # not Python's "None"
    as_json = CliRunner().invoke(scan, ["-", "--max-height", "5", "--summary", "json"], input=tall)
    assert json.loads(as_json.stdout.splitlines()[-1])["summary"]["classes"] == {"unclassified": 1}
    wrong = CliRunner().invoke(scan, ["-", "--format", "pbm"], input=TEXT)
    assert wrong.exit_code == 1 and "PBM" in wrong.stderr


def test_annotate_raw_input_and_unwritable_figure(tmp_path):
    raw = tmp_path / "belt.raw"
    raw.write_bytes(BELT.tobytes())
    png = tmp_path / "belt.png"
    ok = CliRunner().invoke(scan, [str(raw), "--width", "12", "--annotate", str(png)])
    assert ok.exit_code == 0, ok.output
    assert png.read_bytes()[:4] == b"\x89PNG"
    bad = CliRunner().invoke(scan, ["-", "--annotate", str(tmp_path / "no" / "x.png")], input=TEXT)
    assert bad.exit_code == 2
    assert bad.stdout == ""  # refused before any object is scanned
    assert "Invalid value for '--annotate': the folder" in bad.stderr


def test_pbm_header_too_large_for_memory_is_one_line_error():
    from tentaclass.cli.main import cli

    header = b"P4\n99999999999 99999999999\n"  # was a MemoryError traceback
    result = CliRunner().invoke(cli, ["scan", "-"], input=header)
    assert result.exit_code == 1
    assert "PBM file 99,999,999,999 pixels wide: rows of at most" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    # a width that fits, but rows the header only claims: read in steps, found missing
    # (this was "out of memory" after asking for 256 rows of 125 MB at once)
    result = CliRunner().invoke(cli, ["scan", "-"], input=b"P4\n1000000000 1000\n")
    assert result.exit_code == 1
    assert "truncated PBM file: 1000 rows in the header, only 0 found" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_negative_seed_is_usage_error():
    result = CliRunner().invoke(scan, ["--simulate", "3", "--random-state", "-1"])
    assert result.exit_code == 2 and "--random-state" in result.stderr


def _grey_belt(dtype=np.uint16):
    img = np.full((30, 40), 50000 if dtype == np.uint16 else 200, dtype=dtype)
    img += np.linspace(0, 20, 40).astype(dtype)[None, :]  # uneven light
    img[3:9, 4:10] = 3000 if dtype == np.uint16 else 20  # dark square
    img[12:24, 20:26] = 3000 if dtype == np.uint16 else 20  # dark rectangle
    return img


@pytest.mark.parametrize("fmt", ["PNG", "TIFF"])
def test_grey_16_bit_image(tmp_path, fmt):
    from PIL import Image

    path = tmp_path / f"belt.{fmt.lower()}"
    Image.fromarray(_grey_belt()).save(path)
    result = CliRunner().invoke(scan, [str(path), "--summary", "json"])
    assert result.exit_code == 0, result.output
    *objs, last = _lines(result)
    assert [o["label"] for o in objs] == ["square", "rectangle"]
    assert last["summary"]["threshold"]["polarity"] == "dark"


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
def test_annotate_grey_image(tmp_path, dtype):
    from PIL import Image

    path, png = tmp_path / "belt.png", tmp_path / "annotated.png"
    Image.fromarray(_grey_belt(dtype)).save(path)
    result = CliRunner().invoke(scan, [str(path), "--annotate", str(png), "--summary", "json"])
    assert result.exit_code == 0, result.output  # was: image must hold only 0 and 1
    assert [o["label"] for o in _lines(result)[:-1]] == ["square", "rectangle"]
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_raw_grey_stream_without_dtype_says_how_to_read_it():
    result = CliRunner().invoke(scan, ["-", "--width", "40"], input=_grey_belt(np.uint8).tobytes())
    assert result.exit_code == 1
    assert result.stderr == (
        "Error: row 0, column 0: byte value 200, expected 0 or 1 (grey levels? feed them as an "
        "array, or use --dtype uint8)\n"
    )


def test_raw_grey_stream_ending_mid_row_keeps_the_objects():
    data = _grey_belt(np.uint8).tobytes()[:-7]
    result = CliRunner().invoke(
        scan, ["-", "--width", "40", "--dtype", "uint8", "--chunk-rows", "16"], input=data
    )
    assert result.exit_code == 1
    assert [o["label"] for o in _lines(result)] == ["square", "rectangle"]
    assert (
        result.stderr.strip() == "Error: truncated stream: row 29 has only 33 of 40 bytes "
        "(40 pixels of uint8)"
    )


def test_all_white_image_says_no_object_was_found(tmp_path):
    from PIL import Image

    path = tmp_path / "white.png"
    Image.fromarray(np.full((20, 30), 255, dtype=np.uint8)).save(path)
    result = CliRunner().invoke(scan, [str(path)])
    assert result.exit_code == 0 and result.stdout == ""
    assert "no object found in 20 rows (dark objects, below" in result.stderr
    light = CliRunner().invoke(scan, [str(path), "--polarity", "light"])
    assert "no object found in 20 rows (light objects, above" in light.stderr


def test_wrong_bit_depth_and_bad_threshold(tmp_path):
    from PIL import Image

    path = tmp_path / "belt.tif"
    Image.fromarray(np.zeros((4, 5), dtype=np.float32)).save(path)
    result = CliRunner().invoke(scan, [str(path)])
    assert result.exit_code == 1 and "32-bit float pixels" in result.stderr
    bad = CliRunner().invoke(scan, [str(path), "--threshold", "otsu"])
    assert bad.exit_code == 2 and "--threshold" in bad.stderr


def test_files_read_grey_raw_input_as_one_file_does(tmp_path):
    folder = tmp_path / "belts"
    folder.mkdir()
    (folder / "grey.raw").write_bytes(_grey_belt(np.uint8).tobytes())
    opts = ["--width", "40", "--dtype", "uint8", "--threshold", "100", "--polarity", "dark"]
    single = CliRunner().invoke(scan, [str(folder / "grey.raw"), *opts])
    assert single.exit_code == 0, single.output
    assert [o["label"] for o in _lines(single)] == ["square", "rectangle"]
    many = CliRunner().invoke(
        scan, ["--files", str(folder / "*.raw"), "--out-dir", str(tmp_path / "out"), *opts]
    )
    assert many.exit_code == 0, many.output
    assert (tmp_path / "out" / "grey.jsonl").read_text().splitlines() == single.stdout.splitlines()
    # the threshold is used: one above every grey level finds the whole belt as one object
    dark = CliRunner().invoke(
        scan, ["--files", str(folder / "*.raw"), "--out-dir", str(tmp_path / "all"),
               *opts[:4], "--threshold", "250", "--polarity", "dark"],
    )  # fmt: skip
    assert dark.exit_code == 0, dark.output
    objs = [json.loads(x) for x in (tmp_path / "all" / "grey.jsonl").read_text().splitlines()]
    assert [o["area"] for o in objs] == [30 * 40]
