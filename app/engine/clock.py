"""One tab's simulated clock: the time warp asked for, the warp reached, and how much simulated time a
frame may integrate. No viser, no physics: the engine asks it how far to go and tells it what it cost.

A frame integrates for at most TICK_BUDGET_S of wall time, at the rate measured on the last frame, so a
warp beyond what the machine can integrate slows the simulated clock instead of the frames (a stiff preset
at 6000x took 0.27 s a frame without it); but never less than real time.
"""

from __future__ import annotations

import math
from collections import deque

from .presets import WARP_MAX, WARP_MIN

FRAME_HZ = 60.0
PLOT_HZ = 15.0  # plots resend their arrays; a quarter of the frame rate is smooth enough
MAX_FRAME_DT = 0.1  # s of wall time: after a stall, do not try to catch up more than this
TICK_BUDGET_S = 0.008  # wall seconds one frame may spend integrating
FLOOR_BUDGET_S = 0.05  # wall seconds a frame may spend to keep the clock at real time; beyond, it slows
PROBE = 16.0  # after a change, the first frame integrates this much less than the last estimate allows
DEFAULT_WARP = 1.0  # the default scene is made to be watched in real time
WARP_WINDOW_S = 1.0  # wall seconds over which the achieved warp is measured


class Clock:
    """Warp (simulated s per wall s asked for), ``achieved_warp`` (simulated over wall seconds while
    playing, over the last WARP_WINDOW_S of wall time) and ``sim_rate`` (simulated s per wall s of
    integration, measured on the last frame)."""

    def __init__(self, warp: float = DEFAULT_WARP):
        self.warp = float(warp)
        self.restart()

    def restart(self) -> None:
        """A new run: its cost is unknown."""
        self.sim_rate: float | None = None
        self.probe = True
        self._played: deque = deque()  # (simulated s, wall s) of the playing frames in the window

    def set_warp(self, warp: float) -> None:
        """Clamped to [WARP_MIN, WARP_MAX]; NaN is refused (ValueError), as min/max would pass it on."""
        warp = float(warp)
        if math.isnan(warp):
            raise ValueError(f"time warp {warp!r} is not a number; allowed: {WARP_MIN:g}x to {WARP_MAX:g}x")
        self.warp = float(min(WARP_MAX, max(WARP_MIN, warp)))
        self._played.clear()  # what the old warp reached says nothing of the new one

    def changed(self) -> None:
        """A change may make integrating far dearer (a stiffer chi, a warp): probe the cost again."""
        self.probe = True

    @staticmethod
    def frame_wall(wall_dt: float) -> float:
        return min(max(wall_dt, 0.0), MAX_FRAME_DT)

    def allowance(self, dt: float, floor: float) -> float:
        """Simulated seconds a playing frame may integrate out of the ``dt`` the warp asks for: what
        TICK_BUDGET_S affords at the last measured rate (PROBE times less after a change), at least
        ``floor`` (the frame's wall seconds: real time), unless even real time would cost more than
        FLOOR_BUDGET_S at that rate (200 plane pendulums: 5-13 s a frame): then the clock runs slower than
        real time and the frames go on."""
        cap = dt if self.sim_rate is None else self.sim_rate * TICK_BUDGET_S
        if self.sim_rate is not None:
            floor = min(floor, self.sim_rate * FLOOR_BUDGET_S)
        out = min(dt, max(cap / PROBE if self.probe else cap, floor))
        self.probe = False
        return out

    def measured(self, sim_dt: float, spent: float) -> None:
        """``sim_dt`` simulated seconds took ``spent`` wall seconds to integrate."""
        if sim_dt > 0 and spent > 0:
            self.sim_rate = sim_dt / spent

    def played(self, sim_dt: float, wall: float) -> None:
        """A playing frame advanced ``sim_dt`` in ``wall`` seconds: the whole wall time since the last
        frame, not the MAX_FRAME_DT it was clipped to (a smoothed rate over clipped frames said 773x where
        289x was measured, on a loaded machine whose frames took longer than 0.1 s)."""
        if wall <= 0:
            return
        self._played.append((sim_dt, wall))
        total = sum(w for _, w in self._played)
        while len(self._played) > 1 and total - self._played[0][1] >= WARP_WINDOW_S:
            total -= self._played.popleft()[1]

    def paused(self) -> None:
        """The clock stopped: a warp measured before the pause says nothing of after it."""
        self._played.clear()

    @property
    def achieved_warp(self) -> float:
        """Simulated seconds per wall second over the last WARP_WINDOW_S of playing (the warp asked for
        until a frame has played)."""
        wall = sum(w for _, w in self._played)
        return sum(s for s, _ in self._played) / wall if wall > 0 else self.warp
