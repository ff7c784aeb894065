import numpy as np
import pytest

from tentaclass.datasets import reference_tentacle, thesis_scanner, thesis_tentacle


@pytest.mark.parametrize("n", [16, 64])
def test_thesis_tentacle_arrays(n):
    d = thesis_tentacle(n)
    assert d.data.shape == (4, n)
    np.testing.assert_allclose(d.data.sum(axis=1), 2 * np.pi)
    square = d.data[0]
    assert np.count_nonzero(square) == 4 and np.allclose(square[square != 0], np.pi / 2)
    tri = d.data[2]
    assert np.allclose(tri[tri != 0], 2 * np.pi / 3) and np.count_nonzero(tri) == 3


def test_thesis_tentacle_rejects_other_lengths():
    with pytest.raises(ValueError, match="16 or 64"):
        thesis_tentacle(32)


def test_thesis_scanner_grids():
    d = thesis_scanner()
    assert d.grids.dtype == bool and d.grids.shape == (16, 5, 5)
    assert (d.target == np.repeat(d.target_names, 4)).all()
    assert d.grids[0].all()
    assert d.test_grids[0].sum() == 23 and not d.test_grids[0][1:3, 2].any()


@pytest.mark.parametrize("n", [5, 16, 33, 64])
def test_reference_tentacle_closed_laps(n):
    X, _ = reference_tentacle(n, n_starts=3, return_X_y=True)
    assert X.shape == (12, n)
    np.testing.assert_allclose(X.sum(axis=1), 2 * np.pi)


def test_ucr_shapes_official_split():
    pytest.importorskip("aeon", reason="ucr_shapes needs the bench extra (aeon)")
    from tentaclass.datasets import ucr_shapes

    d = ucr_shapes("ArrowHead")
    assert d.data.shape == (211, 251)
    assert (d.split == "train").sum() == 36 and set(d.target) == {"0", "1", "2"}


def test_ucr_shapes_unknown_name():
    from tentaclass.datasets import ucr_shapes

    with pytest.raises(ValueError, match="unknown UCR"):
        ucr_shapes("GunPoint")
