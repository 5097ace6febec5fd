"""The server's collector of closed sessions (app.serve.closing.Collector): many closed together are freed by a few
full collections, not one each, and none is kept once its loop has ended."""

from __future__ import annotations

import gc
import threading
import weakref

from test_class_mode import wait_until

from app.serve.closing import Collector


class Cyclic:
    """Stands for a closed Session: cyclic garbage that only a full collection frees."""

    def __init__(self):
        self.me = self


def test_sessions_closed_together_are_freed_by_a_few_collections():
    ended = threading.Thread(target=lambda: None)
    ended.start()
    ended.join()
    running, release = threading.Event(), threading.Event()
    collector = Collector(delay=0.05, patience=5.0, loop_wait=5.0)
    gc.disable()  # only the collector's collections count (the interpreter's own would free them as well)
    try:
        objects = [Cyclic() for _ in range(40)]
        refs = [weakref.ref(o) for o in objects]
        # a session whose loop still runs: its frame holds the session until the loop ends
        alive = threading.Thread(target=lambda held=objects[-1]: (running.set(), release.wait()))
        alive.start()
        running.wait()
        for r in refs[:-1]:
            collector.add(ended, r)
        collector.add(alive, refs[-1])
        del objects
        wait_until(lambda: all(r() is None for r in refs[:-1]), timeout=10.0, what="the 39 freed")
        assert collector.collections <= 3 and refs[-1]() is not None
        release.set()
        alive.join()
        wait_until(lambda: refs[-1]() is None, timeout=10.0, what="the last freed once its loop ended")
        wait_until(lambda: collector._thread is None, timeout=10.0, what="the collector's thread ends when idle")
    finally:
        gc.enable()
        release.set()
