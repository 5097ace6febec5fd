"""The runs a study starts, watched: ``watch(monkeypatch, module)`` replaces the study module's ``simulate`` with
one that records each run's ``run.t_end`` as it starts and how it ended: "ended", or "stopped" when the study's
halt ended it. It sees the runs of this process's threads, so an in-process dask cluster's workers too."""

from __future__ import annotations

import time
from collections.abc import Callable

from physics.studies.pool import Stopped


class Watched:
    def __init__(self):
        self.started: list[float] = []
        self.outcomes: list[tuple[float, str]] = []  # (t_end, how its run ended)

    def settle(self, timeout: float = 120.0) -> None:
        """Waits until every run started has ended: a cancelled dask task leaves the scheduler at once, but its
        thread runs on until the run ends."""
        deadline = time.monotonic() + timeout
        while len(self.outcomes) < len(self.started) and time.monotonic() < deadline:
            time.sleep(0.1)


def watch(monkeypatch, module, on_start: Callable | None = None) -> Watched:
    """``module.simulate`` watched (``on_start(scenario)`` called as each run starts)."""
    w, real = Watched(), module.simulate

    def watched(sc, **kw):
        w.started.append(sc.run.t_end)
        if on_start is not None:
            on_start(sc)
        try:
            tr = real(sc, **kw)
        except Stopped:
            w.outcomes.append((sc.run.t_end, "stopped"))
            raise
        w.outcomes.append((sc.run.t_end, "ended"))
        return tr

    monkeypatch.setattr(module, "simulate", watched)
    return w
