import re

import numpy as np
import pytest

from tentaclass.datasets import chain_wraps
from tentaclass.errors import InputError
from tentaclass.shapes import circle, rectangle, square, triangle
from tentaclass.wrapping import grasp_state

OUTLINES = [square(1.0), circle(1.0), triangle(side=1.0), rectangle(3.0, 1.0)]


def test_laps_offsets_and_reproducibility():
    kw = dict(n_wraps=12, laps=(1.2, 1.8), offset=(0.0, 1.0), random_state=3)
    d = chain_wraps(OUTLINES, 24, 0.5, **kw)
    assert d.n_failed == 0 and d.data.shape == (48, 24)
    assert np.array_equal(d.outline, np.repeat(np.arange(4), 12))
    # laps along the hull: each object is sized until the chain makes its laps
    assert np.all((d.laps >= 1.2 - 0.01) & (d.laps <= 1.8 + 0.01))
    assert ((d.offset >= 0) & (d.offset <= 1)).all()  # a distance: up to 2 links of 0.5
    # the angles alone say how many laps (the approach links do not count): on the
    # circle the last link's heading is half a link behind its tip; on a polygon it
    # turns corner by corner, at most one side (3/8 of a 3 x 1 rectangle) off
    g = grasp_state(d.data).laps
    per_lap = (24 - np.ceil(d.offset / 0.5 - 1e-9)) / d.laps
    on_circle = d.outline == 1
    np.testing.assert_allclose(g[on_circle], (d.laps - 0.5 / per_lap)[on_circle], atol=0.005)
    assert np.all(np.abs(g - d.laps) <= 3 / 8 + 0.01)
    again = chain_wraps(OUTLINES, 24, 0.5, **kw)
    np.testing.assert_array_equal(again.data, d.data)
    assert not np.array_equal(
        chain_wraps(OUTLINES, 24, 0.5, **{**kw, "random_state": 4}).data, d.data
    )


def test_diameters_set_the_size_and_noise_the_spread():
    kw = dict(n_wraps=20, laps=None, diameters=(6.0, 6.0), offset=(0.0, 0.0))
    clean = chain_wraps([circle(1.0)], 32, **kw)
    # a circle of diameter 6 unit links: 32 links cover 32 / (6 pi) laps
    np.testing.assert_allclose(clean.laps, 32 / (6 * np.pi), rtol=0.01)
    noisy = chain_wraps([circle(1.0)], 32, **kw, noise=0.05)
    assert noisy.noise.max() <= 0.05 and np.std(noisy.data - clean.data) > 0.01


def test_both_modes_and_progress():
    calls = []
    d = chain_wraps(
        OUTLINES[:2],
        16,
        n_wraps=40,
        mode="both",
        progress=lambda done, total: calls.append((done, total)),
    )
    assert set(d.mode) == {"taut", "hug"}
    assert calls[-1] == (80, 80) and [c[0] for c in calls] == sorted(c[0] for c in calls)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"outlines": []}, "outlines is empty"),
        ({"n_links": 2}, "n_links"),
        ({"link_length": 0.0}, "link_length"),
        ({"laps": None}, "either laps or diameters"),
        ({"diameters": (2.0, 3.0)}, "either laps or diameters"),
        ({"laps": None, "diameters": (0.5, 3.0)}, "at least 1 link length"),
        ({"laps": (2.0, 1.0)}, "low <= high"),
        ({"offset": (0.0, 15.0)}, "offset must stay below"),
        ({"noise": -0.1}, "noise"),
        ({"noise": 1e300}, "noise must be at most 2*pi radians"),
        ({"laps": (1.0, 1e300)}, "laps: 16 links cannot close 1e+300 laps (at most 8"),
        ({"laps": None, "diameters": (2.0, 1e300)}, "diameters must be at most 1e+12 link"),
        ({"mode": "loose"}, "mode"),
        ({"random_state": 1.5}, "random_state"),
        ({"random_state": -1}, "random_state must be at least 0"),
        ({"outlines": [[(0, 0), (1, 1)]]}, "outlines[0]"),
    ],
)
def test_bad_input(kwargs, message):
    args = {"outlines": OUTLINES, "n_links": 16, **kwargs}
    with pytest.raises(InputError, match=re.escape(message)):
        chain_wraps(args.pop("outlines"), args.pop("n_links"), **args)
