import io

import numpy as np
import pytest

from tentaclass.errors import InputError
from tentaclass.scanner.io import read_belt, read_rows, write_pbm, write_text

IMG = np.zeros((9, 11), dtype=bool)
IMG[1:4, 2:6] = True
IMG[5:8, 7:10] = True


def _png(image, levels=(0, 255)):
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(np.where(image, levels[1], levels[0]).astype(np.uint8)).save(buf, "PNG")
    return buf.getvalue()


def _text():
    buf = io.StringIO()
    write_text(buf, IMG)
    return buf.getvalue().encode()


def _pbm():
    buf = io.BytesIO()
    write_pbm(buf, IMG)
    return buf.getvalue()


def _p1():
    rows = "\n".join(" ".join(str(int(v)) for v in r) for r in IMG)
    return f"P1\n# a comment\n{IMG.shape[1]} {IMG.shape[0]}\n{rows}\n".encode()


@pytest.mark.parametrize(
    ("data", "kwargs"),
    [
        (_text(), {}),
        (b"# belt\n" + _text().replace(b"1", b"1 "), {}),
        (_pbm(), {}),
        (_p1(), {}),
        (_png(IMG), {}),
        (IMG.astype(np.uint8).tobytes(), {"width": 11}),
    ],
    ids=["text", "text-spaced", "pbm-p4", "pbm-p1", "png", "raw"],
)
def test_formats_roundtrip(data, kwargs, tmp_path):
    assert np.array_equal(read_belt(io.BytesIO(data), **kwargs) > 0, IMG)
    path = tmp_path / "belt"
    path.write_bytes(data)
    chunks = list(read_rows(path, chunk_rows=4, **kwargs))
    if isinstance(chunks[0], bytes):
        got = np.frombuffer(b"".join(chunks), np.uint8).reshape(-1, 11).astype(bool)
    else:
        assert all(len(c) <= 4 for c in chunks)
        got = np.concatenate(chunks)
    assert np.array_equal(got > 0, IMG)


@pytest.mark.parametrize(
    ("data", "kwargs", "match"),
    [
        (b"0110\n0120\n", {}, r"line 2 \(row 1\), column 2: '2'"),
        (b"0110\n011\n", {}, r"line 2 \(row 1\) has 3 pixels, expected 4"),
        (_pbm()[:-5], {}, "truncated PBM"),
        (_p1()[:-30], {}, "truncated PBM"),
        (b"P4\nx 3\n", {}, "bad size"),
        (b"P4\n", {}, "incomplete header"),
        # a header's size was read in one go: out of memory for 1e8 x 1e8 (1.25 GB a row)
        (b"P4\n100000000 100000000\n", {}, "100000000 rows in the header, only 0 found"),
        (b"P4\n3000000000 2\n", {}, "3,000,000,000 pixels wide: rows of at most 2,147,483,647"),
        (_pbm(), {"width": 5}, "11 pixels wide"),
        (_png(IMG)[:40], {}, "PNG"),
        (b"\x00\x01\x02", {"width": 3}, "byte value 2"),
        (b"\x00\x01\x01\x00", {"width": 3}, "truncated stream"),
        (b"", {}, "empty stream"),
        (b"0101", {"fmt": "jpeg"}, "fmt must be one of"),
        (b"0101", {"fmt": "raw"}, "needs the row width"),
    ],
)
def test_bad_input(data, kwargs, match):
    with pytest.raises(InputError, match=match):
        read_belt(io.BytesIO(data), **kwargs)


def _image(arr, fmt, mode=None):
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(arr, mode=mode).save(buf, fmt)
    return buf.getvalue()


@pytest.mark.parametrize("fmt", ["PNG", "TIFF"])
@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
def test_grey_images_8_and_16_bit_keep_their_levels(fmt, dtype):
    img = (
        np.arange(12).reshape(3, 4) * 1000 % 256
        if dtype == np.uint8
        else np.arange(12).reshape(3, 4) * 5000
    ).astype(dtype)
    got = read_belt(io.BytesIO(_image(img, fmt)))
    assert got.dtype == dtype and np.array_equal(got, img)


def test_image_of_wrong_bit_depth_is_refused():
    data = _image(np.zeros((3, 4), dtype=np.float32), "TIFF")
    with pytest.raises(InputError, match="32-bit float pixels; expected a 1, 8 or 16-bit"):
        read_belt(io.BytesIO(data))
    data = _image(np.zeros((3, 4), dtype=np.int32), "TIFF")
    with pytest.raises(InputError, match="32-bit integer pixels"):
        read_belt(io.BytesIO(data))


def test_raw_grey_rows_of_any_dtype_and_truncated_stream():
    img = (np.arange(20).reshape(4, 5) * 3000).astype(np.uint16)
    chunks = list(read_rows(io.BytesIO(img.tobytes()), width=5, dtype="uint16", chunk_rows=3))
    assert [c.shape for c in chunks] == [(3, 5), (1, 5)]
    assert np.array_equal(np.concatenate(chunks), img)
    f = np.linspace(0, 1, 10, dtype=np.float32).reshape(2, 5)
    assert np.array_equal(read_belt(io.BytesIO(f.tobytes()), width=5, dtype="float32"), f)
    rows = read_rows(io.BytesIO(img.tobytes()[:-3]), width=5, dtype="uint16", chunk_rows=2)
    assert next(rows).shape == (2, 5)  # whole rows come out before the error
    with pytest.raises(InputError, match=r"truncated stream: row 3 has only 7 of 10 bytes"):
        list(rows)
    with pytest.raises(InputError, match="dtype must be one of"):
        read_belt(io.BytesIO(b"\x00"), width=1, dtype="int7")


def test_missing_file():
    with pytest.raises(InputError, match="cannot open"):
        read_belt("/nonexistent/belt.txt")


def test_text_with_a_byte_order_mark_is_read():
    # Notepad's "UTF-8 with BOM": was "line 1 (row 0), column 0: 'ï', expected 0 or 1"
    belt = read_belt(io.BytesIO(b"\xef\xbb\xbf0110\n0110\n"))
    np.testing.assert_array_equal(belt, [[0, 1, 1, 0], [0, 1, 1, 0]])
    with pytest.raises(InputError, match="line 2 \\(row 1\\), column 0: 'ï'"):
        read_belt(io.BytesIO(b"0110\n\xef\xbb\xbf0110\n"))  # only at the start
