import shutil

import numpy as np
import pytest

from tentaclass.datasets._wraps import mpeg7_tentacle, synthetic_tentacle
from tentaclass.wrapping import grasp_state


def test_synthetic_is_deterministic_and_varied():
    a = synthetic_tentacle(40, 16, noise=0.02, random_state=3)
    b = synthetic_tentacle(40, 16, noise=0.02, random_state=3)
    np.testing.assert_array_equal(a.data, b.data)
    assert not np.array_equal(a.data, synthetic_tentacle(40, 16, noise=0.02, random_state=4).data)
    assert a.data.shape == (40, 16) and np.all(np.isfinite(a.data))
    assert set(a.target) == {"square", "circle", "triangle", "rectangle"}
    assert np.all((a.laps > 1 - 0.01) & (a.laps < 2 + 0.01))  # along the hull: sized to the laps
    signs = np.sign(a.data.sum(axis=1))
    assert (signs > 0).any() and (signs < 0).any()  # both directions


def test_synthetic_partial_wraps():
    d = synthetic_tentacle(30, 16, laps=(0.5, 0.9), offset=(0, 0), noise=0.0, random_state=1)
    # laps along the hull: every object is sized until the chain makes them
    assert np.all((d.laps >= 0.5 - 0.01) & (d.laps <= 0.9 + 0.01))
    # on the circles (no approach) the heading turns with the arc: the first and the
    # last link both lag the tangent at their tips by half a link
    on_circle = d.target == "circle"
    np.testing.assert_allclose(grasp_state(d.data[on_circle]).laps, d.laps[on_circle], atol=0.005)


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
        ({"offset": (-3.0, 0.0)}, "offset"),
        ({"random_state": "x"}, "random_state"),  # was TypeError
        ({"random_state": -1}, "random_state"),
    ],
)
def test_synthetic_bad_ranges_and_seed(kwargs, match):
    with pytest.raises(ValueError, match=match):
        synthetic_tentacle(4, **kwargs)


def test_mpeg7_wraps_on_a_few_files(mpeg7_folder, tmp_path):
    for name in ("apple-1.png", "apple-2.png", "Bone-1.png", "device3-1.png"):
        shutil.copy(mpeg7_folder / name, tmp_path / name)
    d = mpeg7_tentacle(tmp_path, 32, copies=2, random_state=0, cache=False)
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
    again = mpeg7_tentacle(tmp_path, 32, copies=2, random_state=0, cache=False)
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


def test_fixed_chain_wraps_keep_every_row(mpeg7_folder, tmp_path):
    for name in ("apple-1.png", "Bone-1.png", "device3-1.png"):
        shutil.copy(mpeg7_folder / name, tmp_path / name)
    d = mpeg7_tentacle(tmp_path, 32, protocol="fixed-chain", laps=(1.2, 2.0), copies=2,
                       cache=False)  # fmt: skip
    assert d.data.shape == (6, 32) and d.complete.shape == (6,)  # failed wraps are kept
    assert np.all((d.offset >= 0) & (d.offset <= 2))
    done = d.complete
    assert np.all(np.isfinite(d.data[done]))
    # one chain of unit links: the object was scaled to the laps, read back from the angles
    from tentaclass.features import split_laps

    s = split_laps(d.data[done])
    assert np.mean(s.closed & (s.laps > 1.0) & (s.laps < 2.4)) >= 0.8


@pytest.mark.parametrize("mode", ["taut", "hug"])
def test_fixed_chain_wraps_make_the_laps_asked(mpeg7_folder, tmp_path, mode):
    # concave silhouettes: a hugging chain bridges their narrow concavities, so a
    # lap of chain is shorter than the outline and the size is searched for
    for name in ("bat-1.png", "device3-1.png", "octopus-1.png"):
        shutil.copy(mpeg7_folder / name, tmp_path / name)
    kw = {"protocol": "fixed-chain", "copies": 2, "cache": False}
    part = mpeg7_tentacle(tmp_path, 64, mode, laps=(0.5, 0.95), **kw)
    assert part.complete.all()
    assert np.all((part.laps >= 0.5 - 0.01) & (part.laps <= 0.95 + 0.01))
    full = mpeg7_tentacle(tmp_path, 64, mode, laps=(1.2, 2.0), **kw)
    assert full.complete.all()
    assert np.all((full.laps >= 1.2 - 0.01) & (full.laps <= 2.0 + 0.01))
    # independent: the lap length split_laps finds from the angles gives the same laps
    from tentaclass.features import split_laps

    s = split_laps(full.data)
    assert s.closed.all()
    np.testing.assert_allclose(s.laps, full.laps, atol=0.1)


def test_wrap_cache_is_keyed_on_the_files(mpeg7_folder, tmp_path, monkeypatch):
    from tentaclass.datasets import clear_cache

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    shutil.copy(mpeg7_folder / "apple-1.png", a / "apple-1.png")
    shutil.copy(mpeg7_folder / "Bone-1.png", b / "Bone-1.png")
    kw = {"protocol": "fixed-chain", "laps": (1.2, 1.5)}
    da, db = mpeg7_tentacle(a, 16, **kw), mpeg7_tentacle(b, 16, **kw)  # same number of files
    assert da.target.tolist() == ["apple"] and db.target.tolist() == ["Bone"]
    assert not np.array_equal(da.data, db.data, equal_nan=True)
    store = tmp_path / "cache" / "tentaclass"
    assert len(list(store.glob("mpeg7-wraps-*.npz"))) == 2
    # a cached read equals a fresh one; other parameters are another entry
    np.testing.assert_array_equal(mpeg7_tentacle(a, 16, **kw).data, da.data)
    np.testing.assert_array_equal(mpeg7_tentacle(a, 16, cache=False, **kw).data, da.data)
    mpeg7_tentacle(a, 16, protocol="fixed-chain", laps=(1.5, 1.8))
    assert len(list(store.glob("mpeg7-wraps-*.npz"))) == 3
    assert clear_cache() == 3
    assert not list(store.glob("mpeg7-wraps-*.npz"))


def test_synthetic_return_x_y_and_modes():
    X, y = synthetic_tentacle(12, 16, mode="hug", random_state=2, return_X_y=True)
    d = synthetic_tentacle(12, 16, mode="hug", random_state=2)
    np.testing.assert_array_equal(X, d.data)
    assert y.tolist() == d.target.tolist() and d.complete.shape == (12,)
    with pytest.raises(ValueError, match="mode"):
        synthetic_tentacle(4, mode="loose")


def test_mpeg7_bad_protocol(mpeg7_folder):
    with pytest.raises(ValueError, match="protocol"):
        mpeg7_tentacle(mpeg7_folder, 16, protocol="tuned")


def test_wrap_cache_misses_after_an_upgrade(mpeg7_folder, tmp_path, monkeypatch):
    import tentaclass
    from tentaclass.datasets import _wraps

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    folder = tmp_path / "a"
    folder.mkdir()
    shutil.copy(mpeg7_folder / "apple-1.png", folder / "apple-1.png")
    kw = {"protocol": "fixed-chain", "laps": (1.2, 1.5)}
    store = tmp_path / "cache" / "tentaclass"
    first = mpeg7_tentacle(folder, 16, **kw)
    assert len(list(store.glob("mpeg7-wraps-*.npz"))) == 1
    mpeg7_tentacle(folder, 16, **kw)
    assert len(list(store.glob("mpeg7-wraps-*.npz"))) == 1  # read back: no new entry

    # wraps cached by another protocol version are not read: a poisoned entry proves it
    (cached,) = store.glob("mpeg7-wraps-*.npz")
    with np.load(cached) as f:
        entry = dict(f)
    np.savez(cached, **{**entry, "angles": np.zeros_like(entry["angles"])})
    assert np.all(mpeg7_tentacle(folder, 16, **kw).data == 0)  # the same version reads it
    monkeypatch.setattr(_wraps, "_WRAPS_VERSION", _wraps._WRAPS_VERSION + 1)
    np.testing.assert_array_equal(mpeg7_tentacle(folder, 16, **kw).data, first.data)
    assert len(list(store.glob("mpeg7-wraps-*.npz"))) == 2
    monkeypatch.setattr(tentaclass, "__version__", tentaclass.__version__ + ".post1")
    np.testing.assert_array_equal(mpeg7_tentacle(folder, 16, **kw).data, first.data)
    assert len(list(store.glob("mpeg7-wraps-*.npz"))) == 3
    # nor outlines decoded by another version
    from tentaclass.shapes._images import _cache_file

    files = [folder / "apple-1.png"]
    named = _cache_file(store, files, 1000)
    monkeypatch.setattr(tentaclass, "__version__", tentaclass.__version__ + ".post2")
    assert _cache_file(store, files, 1000) != named
