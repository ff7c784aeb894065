"""Figures of physical grasps: artists returned, animation frames."""

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")
pytest.importorskip("matplotlib")

from tentaclass import PlanarChain
from tentaclass.errors import InputError
from tentaclass.physics import grasp
from tentaclass.plot.physics import animate_grasp, plot_grasp
from tentaclass.shapes import square


@pytest.fixture(scope="module")
def recorded():
    return grasp(square(2.0), PlanarChain([0.5] * 12), frames=3)


def test_plot_grasp_draws_links_and_contacts(recorded):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    art = plot_grasp(recorded, square(2.0), ax=ax, color="tab:green")
    assert art["links"].axes is ax and art["links"].get_color() == "tab:green"
    np.testing.assert_allclose(np.c_[art["links"].get_data()], recorded.joints)
    assert len(art["contacts"].get_offsets()) == len(recorded.contact_points)
    plt.close(fig)


def test_animation_saves_one_image_per_frame(recorded, tmp_path):
    import matplotlib.pyplot as plt
    from PIL import Image

    # pillow merges identical images (the chain at rest): keep frames a few pixels apart
    fr = recorded.frames
    moved = np.r_[True, np.abs(np.diff(fr, axis=0)).max(axis=(1, 2)) > 0.1]
    g = type(recorded)(**{**recorded.__dict__, "frames": fr[moved]})
    assert 3 < len(g.frames) < len(fr)
    anim = animate_grasp(g, square(2.0))
    anim.save(tmp_path / "a.gif", writer="pillow", fps=10, dpi=40)
    with Image.open(tmp_path / "a.gif") as im:
        assert im.n_frames == len(g.frames)
    plt.close("all")


def test_animation_needs_frames():
    g = grasp(square(2.0), PlanarChain([0.5] * 12))
    with pytest.raises(InputError, match="frames"):
        animate_grasp(g, square(2.0))
