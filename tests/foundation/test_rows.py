"""geometry.rows.unique_rows against numpy's np.unique(axis=0) (the reference)."""

import numpy as np
import pytest

from millpath.geometry.rows import unique_rows


@pytest.mark.parametrize("dtype", [np.float64, np.int64])
def test_same_as_numpy_unique(dtype):
    rng = np.random.default_rng(7)
    a = rng.integers(0, 6, (4000, 3)).astype(dtype)       # many repeated rows
    a[::5, 1] = -a[::5, 1]
    u, inv, cnt = unique_rows(a)
    ru, rinv, rcnt = np.unique(a, axis=0, return_inverse=True, return_counts=True)
    assert np.array_equal(u, ru)
    assert np.array_equal(inv, rinv.ravel())
    assert np.array_equal(cnt, rcnt)
    assert np.array_equal(u[inv], a)


def test_empty_and_single():
    u, inv, cnt = unique_rows(np.zeros((0, 2)))
    assert u.shape == (0, 2) and len(inv) == 0 and len(cnt) == 0
    u, inv, cnt = unique_rows(np.array([[1.5, 2.0]]))
    assert u.tolist() == [[1.5, 2.0]] and inv.tolist() == [0] and cnt.tolist() == [1]
    with pytest.raises(ValueError):
        unique_rows(np.zeros(3))
