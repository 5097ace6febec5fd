"""The decimating store behind the whole-run plots and the CSV export (app/engine/history.py)."""

from __future__ import annotations

import numpy as np
import pytest

from app.engine.history import DecimatingStore


def rows(start: int, n: int) -> np.ndarray:
    """Row i is (i, 2 i + 0.5, -i): each row can be told from every other."""
    i = np.arange(start, start + n, dtype=float)
    return np.column_stack([i, 2 * i + 0.5, -i])


def test_below_capacity_every_row_is_kept_in_order():
    s = DecimatingStore(100, 3)
    s.extend(rows(0, 37))
    np.testing.assert_array_equal(s.values(), rows(0, 37))
    assert s.stride == 1 and len(s) == 37


@pytest.mark.parametrize("chunk", [4, 64, 1000, 250_001])  # 4: rows per published frame
def test_a_million_rows_stay_bounded_and_are_actual_rows(chunk):
    cap = 256
    s = DecimatingStore(cap, 3)
    buffer = s._data
    n = 1_000_000
    for start in range(0, n, chunk):
        s.extend(rows(start, min(chunk, n - start)))
        assert len(s) <= cap + 1
    assert s._data is buffer and buffer.shape == (cap, 3)  # no growth, no reallocation
    v = s.values()
    idx = v[:, 0].astype(int)
    np.testing.assert_array_equal(v, rows(0, n)[idx])  # every kept row is a row appended, unchanged
    assert idx[0] == 0  # t = 0 stays
    assert idx[-1] == n - 1  # the latest row is present
    assert np.all(np.diff(idx) > 0)
    # the kept rows (all but a latest row off the stride) are exactly the multiples of the stride
    body = idx[:-1] if (n - 1) % s.stride else idx
    np.testing.assert_array_equal(body, np.arange(0, n, s.stride))
    assert len(v) >= cap // 2  # halving leaves at least half the capacity: the resolution does not collapse


@pytest.mark.parametrize("chunk", [1, 3, 13])
def test_chunking_does_not_change_what_is_kept(chunk):
    a, b = DecimatingStore(64, 3), DecimatingStore(64, 3)
    a.extend(rows(0, 5000))
    for start in range(0, 5000, chunk):
        b.extend(rows(start, min(chunk, 5000 - start)))
    np.testing.assert_array_equal(a.values(), b.values())
    assert a.stride == b.stride > 1


def test_the_latest_row_is_returned_once():
    s = DecimatingStore(4, 3)
    s.extend(rows(0, 4))  # fills, halves to indices 0, 2 with stride 2; latest (3) is off the stride
    idx = s.values()[:, 0].astype(int).tolist()
    assert idx == [0, 2, 3]
    s.extend(rows(4, 1))  # index 4 is on the stride: not repeated as "latest"
    assert s.values()[:, 0].astype(int).tolist() == [0, 2, 4]


def test_clear_starts_again_at_stride_one():
    s = DecimatingStore(8, 3)
    s.extend(rows(0, 100))
    assert s.stride > 1
    s.clear()
    assert len(s) == 0 and s.stride == 1 and s.values().shape == (0, 3)
    s.extend(rows(0, 3))
    np.testing.assert_array_equal(s.values(), rows(0, 3))


@pytest.mark.parametrize("capacity, width, what", [(7, 3, "capacity"), (0, 3, "capacity"), (8, 0, "width")])
def test_bad_sizes_are_refused_by_name(capacity, width, what):
    with pytest.raises(ValueError, match=what):
        DecimatingStore(capacity, width)


def test_rows_of_the_wrong_width_are_refused():
    with pytest.raises(ValueError, match="columns"):
        DecimatingStore(8, 3).extend(np.zeros((2, 4)))
