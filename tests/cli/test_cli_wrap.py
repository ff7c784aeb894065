import json

import numpy as np
import pytest
from click.testing import CliRunner

from tentaclass.cli.wrap import wrap


def run(args):
    return CliRunner().invoke(wrap, args, catch_exceptions=False)


def test_square_prints_thesis_array_and_state():
    r = run(["--shape", "square", "--size", "4", "--links", "16", "--link-length", "1"])
    assert r.exit_code == 0, r.output
    q = np.array(r.stdout.split(), float)
    assert np.allclose(q, np.tile([np.pi / 2, 0, 0, 0], 4))
    assert "grasp: once" in r.stderr


def test_output_is_accepted_by_classify_parser():
    from tentaclass.cli.options import parse_angle_list

    r = run(["--shape", "circle", "--size", "1", "--links", "16", "--laps", "1"])
    assert r.exit_code == 0
    q = parse_angle_list(r.stdout)
    assert q.shape == (16,) and np.allclose(q.sum(), 2 * np.pi, atol=1e-6)


def test_json_laps_offset_and_noise():
    r = run(["--shape", "rectangle", "--size", "6,2", "--links", "40", "--laps", "2",
             "--offset", "2", "--noise", "0.01", "--random-state", "1", "--json"])  # fmt: skip
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert len(d["angles"]) == 40 and d["offset_links"] >= 1
    assert d["grasp"]["state"] == "multiple" and abs(d["laps"] - 2) < 0.1


def test_mask_and_plot(tmp_path):
    from PIL import Image

    img = np.zeros((40, 50), np.uint8)
    img[10:30, 5:45] = 255
    Image.fromarray(img).save(tmp_path / "obj.png")
    out = tmp_path / "wrap.png"
    r = run(["--mask", str(tmp_path / "obj.png"), "--links", "24", "--laps", "1",
             "--plot", str(out)])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert out.stat().st_size > 1000


@pytest.mark.parametrize(
    "args, message",
    [
        (["--shape", "square", "--link-length", "100"], "diameter"),
        (["--shape", "polygon"], "--vertices"),
        (["--shape", "polygon", "--vertices", "0,0 1,1 2,2"], "zero area"),
        (["--shape", "square", "--size", "a"], "not a list of numbers"),
        (["--links", "0"], "links"),
        (["--link-length", "1", "--laps", "2"], "not both"),
        (["--shape", "rectangle", "--size", "-1,2"], "width"),
        (["--shape", "rectangle", "--size", "4,5,6"], "'W' or 'W,H'"),  # 6 must not be ignored
        (["--size", ""], "empty"),  # fell back to the default size
        (["--size", "1e300"], "too large"),
        (["--link-length", "-1"], "must be >= 0"),
        (["--laps", "inf"], "finite"),  # silently wrapped 7.9 laps
        (["--laps", "nan"], "finite"),
        (["--laps", "9"], "cannot close 9 laps"),  # 16 links: silently 7.9 laps
        (["--noise", "0.1", "--random-state", "-1"], "--random-state"),
        (["--shape", "polygon", "--vertices", "0,0 1,1 1,0 0,1"], "intersects itself"),
    ],
)
def test_bad_input_is_one_line(args, message):
    r = CliRunner().invoke(wrap, args)
    assert r.exit_code != 0
    assert message in r.output
    assert "Traceback" not in r.output
    assert r.exception is None or isinstance(r.exception, SystemExit)


def test_laps_needing_too_many_links_is_one_line_error():
    from tentaclass.cli.main import cli

    r = CliRunner().invoke(cli, ["wrap", "--laps", "1e-9"])  # 1.6e10 links per lap
    assert r.exit_code == 2  # a usage error, as --laps 9 is (was exit code 1)
    assert "laps 1e-09 is too small for 16 links: one lap would take 1.6e+10 links" in r.output
    assert "Traceback" not in r.output and len(r.output.strip().splitlines()) == 1
