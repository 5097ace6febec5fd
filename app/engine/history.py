"""A whole run's rows in bounded memory: every row is kept until the store is full, then every second one.

The plots (whole run) and the CSV export read a run from t = 0 however long it has played. A ring buffer
would drop the start; keeping everything would grow without bound. This store keeps the rows whose index
(0, 1, 2, ... in the order appended) is a multiple of ``stride``; when it fills up, the stride doubles
and every second kept row goes. So its memory is fixed, the first row (t = 0) stays, each kept row is a
row that was appended, unchanged, and the last row appended is always returned too (a live plot ends at
"now", not at the last multiple of the stride). The session's loop appends while a download callback
reads, on another thread: a lock keeps a read from seeing a half-done halving.
"""

from __future__ import annotations

import threading

import numpy as np


class DecimatingStore:
    """Rows of a fixed width; at most ``capacity`` kept at any time, plus the latest one."""

    def __init__(self, capacity: int, width: int):
        if not isinstance(capacity, int) or capacity < 2 or capacity % 2:
            raise ValueError(f"capacity must be an even integer >= 2, got {capacity!r}")
        if not isinstance(width, int) or width < 1:
            raise ValueError(f"width must be a positive integer, got {width!r}")
        self._data = np.full((capacity, width), 0.0)  # written now (np.zeros is not): its pages count from the start
        self._last = np.zeros(width)
        self._lock = threading.Lock()
        self.clear()

    @property
    def capacity(self) -> int:
        return self._data.shape[0]

    @property
    def width(self) -> int:
        return self._data.shape[1]

    def clear(self) -> None:
        with self._lock:
            self._clear()

    def _clear(self) -> None:
        self._kept = 0  # rows in _data
        self.stride = 1  # kept rows are those whose index is a multiple of this
        self.appended = 0  # rows ever appended (the next row's index)

    def extend(self, rows: np.ndarray) -> None:
        """Append rows (n, width) or one row (width,)."""
        rows = np.atleast_2d(np.asarray(rows, dtype=float))
        if rows.shape[1] != self.width:
            raise ValueError(f"rows must have {self.width} columns, got {rows.shape[1]}")
        n = len(rows)
        if n == 0:
            return
        with self._lock:
            self._append(rows, n)

    def _append(self, rows: np.ndarray, n: int) -> None:
        first = self.appended  # index of rows[0]
        self.appended += n
        self._last[:] = rows[-1]
        i = (-first) % self.stride  # first position in rows whose index is a multiple of the stride
        while i < n:
            take = rows[i::self.stride][: self.capacity - self._kept]
            self._data[self._kept:self._kept + len(take)] = take
            self._kept += len(take)
            i += len(take) * self.stride
            if self._kept == self.capacity:
                self._halve()
                i += (-(first + i)) % self.stride  # realign to the doubled stride

    def _halve(self) -> None:
        """Keep rows 0, 2, 4, ... (indices multiple of 2 * stride): row j holds index j * stride."""
        half = self._data[0::2]
        self._kept = len(half)
        self._data[: self._kept] = half.copy()
        self.stride *= 2

    def values(self) -> np.ndarray:
        """Kept rows oldest first, then the latest row if it is not one of them: a copy (size, width)."""
        return self.snapshot()[0]

    def snapshot(self) -> tuple[np.ndarray, int]:
        """(values(), the stride they were kept at), read together."""
        with self._lock:
            out = self._data[: self._kept]
            if self.appended and (self.appended - 1) % self.stride:
                return np.vstack([out, self._last]), self.stride
            return out.copy(), self.stride

    def __len__(self) -> int:
        return self._kept + (1 if self.appended and (self.appended - 1) % self.stride else 0)
