"""``tentaclass grasp``: angles on stdout, the grasp state on stderr, figures, one-line errors."""

import json

import numpy as np
import pytest
from click.testing import CliRunner

pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")

from tentaclass import grasp_state
from tentaclass.cli.main import cli
from tentaclass.cli.options import parse_angle_list


def run(args):
    return CliRunner().invoke(cli, ["grasp", *args], catch_exceptions=False)


def test_square_prints_angles_that_classify_reads_and_the_state(tmp_path):
    from PIL import Image

    gif, png = tmp_path / "grasp.gif", tmp_path / "grasp.png"
    r = run(["--shape", "square", "--links", "16", "--gif", str(gif), "--plot", str(png)])
    assert r.exit_code == 0, r.output
    q = parse_angle_list(r.stdout)
    assert q.shape == (16,) and abs(q.sum() / (2 * np.pi) - 1) < 0.15  # about one lap
    state = grasp_state(q)
    assert r.stderr.startswith(f"grasp: {state.state.item()}, {float(state.laps):.2f} laps")
    with Image.open(png) as im:  # the final pose
        assert im.format == "PNG" and min(im.size) > 100
    with Image.open(gif) as im:  # the animation: the chain closing, frame after frame
        assert im.format == "GIF" and im.n_frames > 10
    c = CliRunner().invoke(cli, ["classify", r.stdout.strip()], catch_exceptions=False)
    assert c.exit_code == 0


def test_json_and_mask(tmp_path):
    from PIL import Image

    img = np.zeros((60, 60), np.uint8)
    img[15:45, 10:50] = 255
    path = tmp_path / "mask.png"
    Image.fromarray(img).save(path)
    r = run(["--mask", str(path), "--links", "20", "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.stdout)
    assert len(out["angles"]) == 20 and out["complete"] is True
    assert out["grasp"]["state"] in ("partial", "once", "multiple")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--shape", "polygon", "--vertices", "0,0 1,1 1,0 0,1"], "intersects itself"),
        (["--shape", "square", "--mask", "nope.png"], "nope.png"),
        (["--links", "0"], "links"),
        (
            ["--shape", "circle", "--size", "1", "--links", "8", "--link-length", "5"],
            "link_length 5 is longer than the object's diameter 2: ",
        ),
        (["--offset", "1e300"], "offset 1e+300 is longer than the chain (16 links of 1, 16)"),
        (["--thickness", "1e300"], "thickness 1e+300 is larger than the object (diameter 5.6"),
        (["--links", "1000000"], "MuJoCo builds chains of at most 496 links"),
        (["--links", "4", "--link-length", "1e-300"], "link_length 1e-300 is too short for an"),
        # the library flags the diverged simulation; the command said "q contains 16 NaN"
        (["--friction", "1e300"], "the grasp failed: the simulation diverged at joint 0"),
    ],
)
def test_errors_are_one_line(args, message):
    r = run(args)
    assert r.exit_code != 0
    assert message in r.output and "Traceback" not in r.output
    assert len(r.output.strip().splitlines()[-1]) > 0
