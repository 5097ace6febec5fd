"""What happens to a tab after it closes, for the explorer's server and the class alike: the ids of the tabs that
closed (``ClosedTabs``), so that one closing while its view or session is being built gets none, and one thread
that frees the closed sessions (``COLLECTOR``).
"""

from __future__ import annotations

import gc
import threading
import time
import weakref

KEPT = 10_000  # closed tabs' ids remembered: far more than connect callbacks ever wait in viser's queue


class ClosedTabs:
    """The ids of the last ``kept`` tabs that closed, an ordered set trimmed from the oldest: a server up for days
    keeps no record per tab. Not locked: its owner holds its own lock around it."""

    def __init__(self, kept: int = KEPT):
        self.kept = kept
        self._ids: dict[int, None] = {}

    def add(self, cid: int) -> None:
        self._ids[cid] = None
        if len(self._ids) > self.kept:
            del self._ids[next(iter(self._ids))]

    def __contains__(self, cid: int) -> bool:
        return cid in self._ids


class Collector:
    """One thread that frees closed sessions and hands their memory back to the system.

    A closed session is cyclic garbage (the client's GUI handles hold its callbacks, which close over the
    session), which only a full collection frees; CPython runs one only after the long-lived objects grow by a
    quarter (~35k here), so each reconnection kept its ~3 MB for dozens of reconnections. A session is freed once
    its loop has ended and viser's disconnect handling has let go of its client handle. A thread per closed tab,
    each collecting once a second after its loop ended, left 28 of 64 sessions in memory when 100 tabs left at once
    (bench load; viser still held some handles then), each of the 64 threads running its own full collection of a
    300,000-object heap. This one collects once every ``delay`` while a closed session whose loop has ended is
    still in memory, watching each for at most ``loop_wait + patience`` seconds after it closed, however many
    closed together."""

    def __init__(self, delay: float = 1.0, patience: float = 10.0, loop_wait: float = 5.0):
        self.delay, self.patience, self.loop_wait = delay, patience, loop_wait
        self._lock = threading.Lock()
        self._watched: list[tuple[threading.Thread, weakref.ref, float]] = []  # (loop, session, give up at)
        self._thread: threading.Thread | None = None
        self.collections = 0

    def add(self, loop: threading.Thread, session: weakref.ref) -> None:
        with self._lock:
            self._watched.append((loop, session, time.monotonic() + self.loop_wait + self.patience))
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="collect-sessions", daemon=True)
                self._thread.start()

    def _run(self) -> None:
        while True:
            time.sleep(self.delay)  # viser's disconnect handling drops its last references meanwhile
            with self._lock:
                now = time.monotonic()
                self._watched = [w for w in self._watched if w[1]() is not None and now < w[2]]
                ready = any(not loop.is_alive() for loop, _, _ in self._watched)
                if not self._watched:
                    self._thread = None
                    return
            if ready:
                gc.collect()  # a full collection: the sessions' objects have long reached the oldest generation
                self.collections += 1
                _trim_heap()


COLLECTOR = Collector()


def _trim_heap() -> None:
    """Hand freed memory back to the system after a tab's session is freed: glibc keeps its buffers
    otherwise (docs/reliability.md). Elsewhere than glibc this does nothing."""
    try:
        import ctypes

        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        pass
