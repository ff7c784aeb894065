import shutil

import numpy as np
import pytest

from tentaclass.datasets._wraps import mpeg7_tentacle, synthetic_tentacle


def test_synthetic_is_deterministic_and_varied():
    a = synthetic_tentacle(40, 16, noise=0.02, seed=3)
    b = synthetic_tentacle(40, 16, noise=0.02, seed=3)
    np.testing.assert_array_equal(a.data, b.data)
    assert not np.array_equal(a.data, synthetic_tentacle(40, 16, noise=0.02, seed=4).data)
    assert a.data.shape == (40, 16) and np.all(np.isfinite(a.data))
    assert set(a.target) == {"square", "circle", "triangle", "rectangle"}
    assert np.all(a.laps > 0.6) and 1.2 < np.median(a.laps) < 1.8  # heading-based, steps at corners
    signs = np.sign(a.data.sum(axis=1))
    assert (signs > 0).any() and (signs < 0).any()  # both directions


def test_synthetic_partial_wraps():
    d = synthetic_tentacle(30, 16, laps=(0.5, 0.9), offset_links=(0, 0), noise=0.0, seed=1)
    # laps are read from headings, which jump at corners: judge the bulk
    assert np.median(d.laps) < 0.9 and np.all(d.laps < 1.3)


def test_synthetic_bad_noise():
    with pytest.raises(ValueError, match="noise"):
        synthetic_tentacle(4, noise=(0.05, 0.01))


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"laps": (np.nan, 1.0)}, "laps"),  # was OverflowError from numpy
        ({"laps": (2.0, 1.0)}, "low <= high"),
        ({"laps": (0.0, 0.0)}, "laps"),
        ({"laps": (-1.0, 1.0)}, "laps"),  # was silently accepted
        ({"laps": 1.0}, "pair"),  # was TypeError
        ({"laps": (1.0, 2.0, 3.0)}, "pair"),
        ({"offset_links": (-3.0, 0.0)}, "offset_links"),
        ({"seed": "x"}, "seed"),  # was TypeError
        ({"seed": -1}, "seed"),
    ],
)
def test_synthetic_bad_ranges_and_seed(kwargs, match):
    with pytest.raises(ValueError, match=match):
        synthetic_tentacle(4, **kwargs)


def test_mpeg7_wraps_on_a_few_files(mpeg7_folder, tmp_path):
    for name in ("apple-1.png", "apple-2.png", "Bone-1.png", "device3-1.png"):
        shutil.copy(mpeg7_folder / name, tmp_path / name)
    d = mpeg7_tentacle(tmp_path, 32, copies=2, seed=0, cache=False)
    assert d.data.shape == (8, 32)
    assert d.target.tolist()[:4] == ["apple", "apple", "Bone", "device3"]
    assert d.wrap_index.tolist() == [0] * 4 + [1] * 4
    assert d.complete.all()  # taut chains never jam
    np.testing.assert_allclose(np.abs(d.data.sum(axis=1)), 2 * np.pi, atol=0.5)
    # the gap is where the rebuilt chain ends, in links: independent check by a loop
    for q, gap in zip(d.data, d.closure_gap, strict=True):
        heading = np.cumsum(q)
        end = np.array([np.cos(heading).sum(), np.sin(heading).sum()])
        assert gap == pytest.approx(np.hypot(*end), abs=1e-9)
    assert np.all(d.closure_gap < 2.0)  # taut laps close to within a couple of links
    again = mpeg7_tentacle(tmp_path, 32, copies=2, seed=0, cache=False)
    np.testing.assert_array_equal(d.data, again.data)


def test_mpeg7_wraps_without_cache_write_nothing(mpeg7_folder, tmp_path, monkeypatch):
    data = tmp_path / "data"
    data.mkdir()
    shutil.copy(mpeg7_folder / "apple-1.png", data / "apple-1.png")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    mpeg7_tentacle(data, 16, cache=False)
    assert not (tmp_path / "cache").exists()
    mpeg7_tentacle(data, 16)
    assert len(list((tmp_path / "cache").glob("tentaclass/*.npz"))) == 2  # outlines, wraps
