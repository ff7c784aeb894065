"""Train for a chain, then deploy: the bundled models, wrap | classify, rejection."""

import json

import numpy as np
import pytest
from click.testing import CliRunner

from tentaclass.cli.main import cli
from tentaclass.errors import InputError
from tentaclass.io import bundled_links, bundled_model, load_model, model_info


def run(*args, input=None):
    return CliRunner().invoke(cli, [str(a) for a in args], input=input, catch_exceptions=False)


def one_line_error(r, message):
    assert r.exit_code != 0, r.output
    assert message in r.output, r.output
    assert "Traceback" not in r.output
    assert len(r.output.strip().splitlines()) == 1, r.output


def wrap_then_classify(*wrap_args, classify_args=()):
    """`tentaclass wrap ... | tentaclass classify`: stdout of one is stdin of the other."""
    w = run("wrap", *wrap_args)
    assert w.exit_code == 0, w.output
    c = run("classify", *classify_args, input=w.stdout)
    assert c.exit_code == 0, c.output
    return c.stdout.splitlines()[1].split()[1]


@pytest.mark.parametrize(
    "args, label",
    [
        # the round trip that answered TRIANGLE with probability 1.000
        (["--shape", "rectangle", "--size", "6,2", "--links", "16", "--offset", "2"], "RECTANGLE"),
        # the default triangle wrap (1.85 laps) that answered CIRCLE
        (["--shape", "triangle"], "TRIANGLE"),
        # a triangle at 1.5 laps, that answered SQUARE
        (["--shape", "triangle", "--laps", "1.5"], "TRIANGLE"),
        # the README and docs/wrapping.md examples
        (["--shape", "square", "--size", "4", "--links", "16", "--link-length", "1"], "SQUARE"),
        (
            [
                "--shape",
                "rectangle",
                "--size",
                "6,2",
                "--links",
                "40",
                "--laps",
                "2",
                "--offset",
                "2",
                "--noise",
                "0.01",
                "--random-state",
                "1",
            ],
            "RECTANGLE",
        ),
        (["--shape", "circle", "--links", "16", "--laps", "2", "--offset", "1"], "CIRCLE"),
    ],
)
def test_wrap_piped_into_classify(args, label):
    assert wrap_then_classify(*args) == label


#: (noise, seed) of the wraps of each setting: clean, and as a real encoder reads them
NOISES = ((0.0, None), (0.02, 1))


def _wraps(shape, n_links, laps, offset_links):
    """Joint angles as `tentaclass wrap --shape S --links N --laps L --offset O` makes them,
    one wrap for each of NOISES (the link length does not depend on the noise)."""
    from tentaclass.cli.wrap import _outline
    from tentaclass.wrapping import link_length_for_laps as _length_for_laps
    from tentaclass.wrapping import wrap

    outline = _outline(shape, None, None, None)
    kw = {"start": 0.0, "direction": "ccw", "mode": "taut"}
    ell = _length_for_laps(outline, n_links, laps, offset=0.0, **kw)
    ell = _length_for_laps(outline, n_links, laps, offset=offset_links * ell, **kw)
    return [
        wrap(outline, n_links, ell, offset=offset_links * ell, noise=noise, random_state=seed, **kw)
        for noise, seed in NOISES
    ]


@pytest.mark.slow
@pytest.mark.parametrize("n_links", [16, 40])
def test_bundled_model_over_the_documented_range(n_links):
    """Four thesis shapes, 0.9-3 laps, offset 0-3 links, noise up to 0.02, as `wrap` makes them.

    `wrap --laps L --offset O` wraps slightly fewer or more laps than asked when
    the base stands off; wraps that end up outside 0.9-3 laps are not counted.
    """
    model, _ = bundled_model(n_links)
    X, y = [], []
    for shape in ("square", "circle", "triangle", "rectangle"):
        for laps in (0.9, 1.2, 1.5, 2.0, 2.5, 3.0):
            for offset in (0.0, 1.5, 3.0):
                try:
                    wraps = _wraps(shape, n_links, laps, offset)
                except InputError:  # `wrap` refuses it too: too few links per lap
                    continue
                for w in wraps:
                    if 0.9 <= w.laps <= 3.0:
                        X.append(w.angles)
                        y.append(shape)
    accuracy = np.mean(model.predict(np.array(X)) == np.array(y))
    # measured: 96 of 104 at 16 links (a chain of 16 links sees 4-6 links per lap
    # at 2.5-3 laps), 118 of 118 at 40 links; the documented examples all hold
    assert len(y) >= 100 and accuracy >= {16: 0.9, 40: 0.99}[n_links]


@pytest.mark.parametrize("n_links", [16, 40])
def test_bundled_models_cover_the_example_chains(n_links):
    assert n_links in bundled_links()
    info = model_info(
        __import__("importlib.resources").resources.files("tentaclass.data")
        / f"default-{n_links}.tcm"
    )
    assert info["chain"]["n_links"] == n_links
    assert info["classes"] == ["circle", "rectangle", "square", "triangle"]
    assert 0 < info["reject_below"] < 1


def _star(n_links, link_lengths=(0.6, 0.8)):
    """Hug wraps of a five-pointed star: concave, unlike every thesis class."""
    from tentaclass.shapes import polygon
    from tentaclass.wrapping import wrap

    t = np.linspace(0, 2 * np.pi, 10, endpoint=False)
    r = np.where(np.arange(10) % 2 == 0, 2.0, 0.8)
    star = polygon(np.c_[r * np.cos(t), r * np.sin(t)])
    return [wrap(star, n_links, ell, mode="hug").angles for ell in link_lengths]


def test_reject_says_unknown_outside_the_classes():
    rows = "\n".join(" ".join(f"{a:.10g}" for a in q) for q in _star(16))
    r = run("classify", "--reject", input=rows)
    assert r.exit_code == 0, r.output
    assert [line.split()[1] for line in r.stdout.splitlines()[1:]] == ["unknown", "unknown"]
    # without --reject the closest class is named
    plain = run("classify", input=rows)
    assert "unknown" not in plain.stdout
    # an 'unknown' row shows no probability (it was '1.000', the known classes' best) and
    # names the closest class, the one classify names without --reject
    pairs = zip(r.stdout.splitlines()[1:], plain.stdout.splitlines()[1:], strict=True)
    for rejected, named in pairs:
        _, closest, _ = named.split()
        assert rejected.split()[2:] == ["-", "(closest:", f"{closest})"]
    # the thesis shapes are kept
    assert wrap_then_classify("--shape", "triangle", classify_args=["--reject"]) == "TRIANGLE"
    assert (
        wrap_then_classify(
            "--shape",
            "rectangle",
            "--size",
            "6,2",
            "--links",
            "16",
            "--offset",
            "2",
            classify_args=["--reject"],
        )
        == "RECTANGLE"
    )


def test_json_from_stdin_and_unknown_label():
    star = _star(16, (0.8,))[0]
    r = run("classify", "--json", "--reject", input=" ".join(map(str, star)))
    assert json.loads(r.stdout)[0]["label"] == "unknown"


# ------------------------------------------------------------------ bad input


@pytest.mark.parametrize(
    "args, stdin, message",
    [
        (["classify", "0 0 0"], None, "not a chain wrapped around an object"),
        (["classify", " ".join(["0"] * 16)], None, "turns 0 rad in total"),
        (["classify"], "", "standard input holds no angle arrays: give ANGLES or --file"),
        (["classify"], "0 0 x\n", "standard input, line 1"),
        (["classify"], "0 0 pi\n0 pi\n", "different numbers"),
    ],
)
def test_classify_bad_input(args, stdin, message):
    one_line_error(run(*args, input=stdin), message)


def test_model_of_another_chain_length(tmp_path):
    from tentaclass.classifiers import FourierClassifier
    from tentaclass.datasets import reference_tentacle
    from tentaclass.io import save_model

    X, y = reference_tentacle(16, return_X_y=True)
    path = save_model(
        FourierClassifier().fit(X, y), tmp_path / "robot.tcm", info={"chain": {"n_links": 16}}
    )
    r = run("classify", "--model", path, " ".join(["pi/10"] * 20))
    one_line_error(r, "robot.tcm was trained for a chain of 16 links; these arrays have 20")


def test_classify_without_a_bundled_length_falls_back_with_a_note():
    r = run("classify", " ".join(["2*pi/24"] * 24))
    assert r.exit_code == 0
    assert "CIRCLE" in r.stdout and "no bundled model for 24 links" in r.stderr


def test_library_check_names_both_lengths():
    from tentaclass.errors import InputError
    from tentaclass.io import check_chain_length

    with pytest.raises(InputError, match="chain of 16 links; these arrays have 20"):
        check_chain_length(np.zeros((2, 20)), {"chain": {"n_links": 16}}, 16)
    check_chain_length(np.zeros((2, 16)), {}, 16)


# ------------------------------------------------------------ train --outlines


@pytest.fixture
def outline_files(tmp_path):
    from PIL import Image

    folder = tmp_path / "shapes"
    folder.mkdir()
    yy, xx = np.mgrid[:60, :60]
    disc = ((yy - 30) ** 2 + (xx - 30) ** 2 < 400).astype(np.uint8) * 255
    bar = np.zeros((60, 60), np.uint8)
    bar[22:38, 5:55] = 255
    Image.fromarray(disc).save(folder / "disc-1.png")
    Image.fromarray(bar).save(folder / "bar-1.png")
    np.savetxt(folder / "bar-2.csv", [(0, 0), (4, 0), (4, 1), (0, 1)], delimiter=",")
    np.save(folder / "tri-1.npy", np.array([(0, 0), (2, 0), (1, 1.7)]))
    return folder


def test_train_for_a_chain_then_classify(tmp_path, outline_files):
    out = tmp_path / "robot.tcm"
    r = run(
        "train",
        "--outlines",
        str(outline_files / "*"),
        "--links",
        20,
        "--link-length",
        0.5,
        "--wraps-per-outline",
        30,
        "--laps",
        "1,1.8",
        "--noise",
        "0.01",
        "--out",
        out,
    )
    assert r.exit_code == 0, r.output
    assert "3 classes (bar, disc, tri), 4 outlines" in r.stdout
    info = model_info(out)
    assert info["chain"]["n_links"] == 20 and info["chain"]["link_length"] == 0.5
    assert info["chain"]["laps"] == [1.0, 1.8] and info["chain"]["noise"] == [0.0, 0.01]
    assert info["training"]["held_out_accuracy"] >= 0.8
    assert load_model(out).n_features_in_ == 20
    # a wrap of a bar by that chain
    w = run("wrap", "--shape", "rectangle", "--size", "8,2", "--links", 20, "--laps", "1.4")
    c = run("classify", "--model", out, input=w.stdout)
    assert c.stdout.splitlines()[1].split()[1] == "BAR", c.output
    # another chain length is refused, naming both
    one_line_error(
        run("classify", "--model", out, " ".join(["pi/8"] * 16)),
        "trained for a chain of 20 links; these arrays have 16",
    )


def test_train_labels_from_a_csv(tmp_path, outline_files):
    labels = tmp_path / "labels.csv"
    labels.write_text("file,label\ndisc-1.png,round\nbar-1.png,long\nbar-2.csv,long\n")
    out = tmp_path / "m.tcm"
    r = run(
        "train",
        "--outlines",
        str(outline_files / "*.png"),
        "--outlines",
        str(outline_files / "*.csv"),
        "--labels",
        labels,
        "--links",
        16,
        "--wraps-per-outline",
        10,
        "--reject-rate",
        0.05,
        "--out",
        out,
    )
    assert r.exit_code == 0, r.output
    assert model_info(out)["classes"] == ["long", "round"]
    assert load_model(out).reject == 0.05  # the recogniser answers "unknown" by itself


def test_train_missing_labels_and_other_bad_input(tmp_path, outline_files):
    labels = tmp_path / "labels.csv"
    labels.write_text("disc-1.png,round\n")
    out = tmp_path / "m.tcm"
    base = ["train", "--outlines", str(outline_files / "*.png"), "--out", out]
    # input errors (what the files hold): exit code 1
    for r, message in [
        (run(*base, "--links", 16, "--labels", labels), "no label for 1 outline"),
        (
            run("train", "--outlines", str(outline_files / "disc-*"), "--links", 16, "--out", out),
            "only one class",
        ),
        (
            run(*base[:2], str(tmp_path / "none*.png"), "--links", 16, "--out", out),
            "matches no file",
        ),
    ]:
        one_line_error(r, message)
        assert r.exit_code == 1, r.output
    # usage errors (the options, found before any file is read): exit code 2
    for r, message in [
        (run(*base), "--outlines needs --links"),
        (run("train", "--out", out), "give either --data or --outlines"),
        (run(*base, "--links", 16, "--laps", "2,1"), "--laps: expected MIN,MAX with MIN <= MAX"),
        # both read "expected MIN,MAX with MIN <= MAX", which they were
        (run(*base, "--links", 16, "--laps", "nan,inf"), "--laps: MIN and MAX must be finite"),
        (run(*base, "--links", 16, "--noise", "-1"), "--noise: MAX must be >= 0"),
        (run(*base, "--links", 16, "--laps", "1,2", "--diameters", "3,4"), "not both"),
        # ranges the chain cannot wrap were found after every outline was read (exit code 1)
        (run(*base, "--links", 16, "--offset", "0,20"), "offset must stay below"),
        (run(*base, "--links", 16, "--laps", "1,9"), "16 links cannot close 9 laps"),
        # a chain too short for a default range: the message says it was the default
        (run(*base, "--links", 3), "(the default --laps 1,2: give other values)"),
        (run(*base, "--links", 4), "(the default --offset 0,2: give other values)"),
        (run(*base, "--links", 16, "--diameters", "0.5,2"), "diameters must be at least 1 link"),
        (run(*base, "--links", 16, "--noise", "7"), "noise must be at most 2*pi radians"),
        (run(*base, "--links", 16, "--offset", "-1,0"), "offset must be a finite number >= 0"),
    ]:
        one_line_error(r, message)
        assert r.exit_code == 2, r.output
    bad = outline_files / "bad-1.csv"
    bad.write_text("0,0\n1,x\n")
    one_line_error(
        run(
            "train",
            "--outlines",
            str(bad),
            "--outlines",
            str(outline_files / "*.png"),
            "--links",
            16,
            "--out",
            out,
        ),
        "bad-1.csv, line 2: expected 'x,y' (two numbers), got '1,x'",
    )
    assert not out.exists()


def test_outline_csv_header_row_and_bad_lines(tmp_path):
    from tentaclass.cli.train import read_outline

    path = tmp_path / "plate-1.csv"
    path.write_text("x,y\n0,0\n4,0  # a comment\n4,4\n0,4\n")  # was refused for its header
    assert read_outline(path).tolist() == [[0, 0], [4, 0], [4, 4], [0, 4]]
    path.write_text("0 0\n4 0\n4 4\n")
    with pytest.raises(ValueError, match=r"plate-1.csv, line 1: expected 'x,y' \(two numbers\)"):
        read_outline(path)
    path.write_text("x,y\n")
    with pytest.raises(ValueError, match=r"plate-1\.csv: no 'x,y' rows found"):
        read_outline(path)


def test_outline_images_two_objects_colour_and_blank(tmp_path, capsys):
    from PIL import Image

    from tentaclass.cli.options import image_outline

    img = np.full((60, 120), 255, np.uint8)  # black objects on white
    img[10:50, 5:45] = 0
    img[20:50, 70:100] = 0
    Image.fromarray(img).save(tmp_path / "two.png")
    outline = image_outline(tmp_path / "two.png")
    assert np.ptp(outline[:, 0]) == np.ptp(outline[:, 1]) == 40  # the larger one
    err = capsys.readouterr().err
    assert err == (
        f"warning: {tmp_path / 'two.png'}: 2 objects; the largest (1,600 px) is used, "
        "1 other(s) of up to 900 px left out: one object per image\n"
    )
    img[20:50, 70:100] = 255
    img[55:57, 100:102] = 0  # a speck is not another object
    Image.fromarray(img).save(tmp_path / "one.png")
    rgb = np.stack([np.where(img == 0, 200, 255), np.where(img == 0, 30, 255), img], axis=-1)
    Image.fromarray(rgb.astype(np.uint8)).save(tmp_path / "colour.png")
    assert np.array_equal(
        image_outline(tmp_path / "colour.png"), image_outline(tmp_path / "one.png")
    )
    assert capsys.readouterr().err == ""
    Image.fromarray(np.full((20, 20), 255, np.uint8)).save(tmp_path / "blank.png")
    with pytest.raises(ValueError, match=r"blank\.png: no object found"):
        image_outline(tmp_path / "blank.png")


@pytest.mark.parametrize(
    "text, message",
    [
        ("0,0\n1,0\n2,0\n3,0\n", "has zero area: its points are collinear"),
        ("0,0\n0,0\n0,0\n", "has fewer than 3 distinct points: all its points coincide"),
        ("0,0\n4,0\n0,4\n4,4\n", "intersects itself"),  # a bow tie
        ("0,0\n4,0\n4,4\n2,0\n0,4\n", "intersects itself"),  # touches itself at (2, 0)
        ("0,0\n4,0\n", "must hold at least 3 points, got 2"),
        ("0,0\n1e300,0\n0,1e300\n", "spans 1e+300: too large or too small to compute with"),
        (np.array([[0, 0], [1, 0], [0, 1]], bool), "must hold numbers, got booleans"),
    ],
)
def test_degenerate_outline_files_are_named_once(tmp_path, text, message):
    from tentaclass.cli.train import read_outline

    path = tmp_path / ("plate-1.npy" if isinstance(text, np.ndarray) else "plate-1.csv")
    np.save(path, text) if isinstance(text, np.ndarray) else path.write_text(text)
    with pytest.raises(ValueError) as caught:
        read_outline(path)
    # the file was named twice: "plate-1.csv: plate-1.csv intersects itself"
    assert str(caught.value).startswith(f"{path} ") or str(caught.value).startswith(f"{path}: ")
    assert str(caught.value).count(str(path)) == 1 and message in str(caught.value)
