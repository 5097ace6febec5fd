"""How often a tab's loop publishes a frame: as often as the server's Python affords for every tab at once.

Every tab's loop (tick and publish) and viser's event loop (which encodes and sends what was published) take
turns on one interpreter. When the loops together ask for more than a core's worth, viser's sender falls behind
and merges queued updates: a tab is published frames it never receives, and an edit waits behind them. So a
loop measures what its own frames cost in CPU time (its thread's, which a wait for the lock does not inflate)
and, when the tabs together would pass SHARE of one core, each publishes fewer frames, never fewer than MIN_HZ.
On a fast machine nothing changes (ten tabs of the default scene ask about a quarter of a core at 40 frames/s);
on one half as fast the frames thin out instead of piling up.
"""

from __future__ import annotations

from ..engine.clock import FRAME_HZ

CROWD = 4  # tabs on one server beyond which each gets CROWD_HZ frames per second instead of FRAME_HZ
CROWD_HZ = 40.0  # still smooth, and ten tabs fit one core's worth of Python (docs/reliability.md)
SHARE = 0.7  # of one core, for the tabs' loops together: the rest is viser's event loop sending their frames
MIN_HZ = 10.0  # the fewest frames per second a tab is given, however crowded the server
SMOOTHING = 0.1  # weight of the newest frame in the running mean of a frame's cost
SPIKE = 4.0  # a frame counts at most this many times the mean: one slow frame (a preset loading) is not a trend


class Pace:
    """A tab loop's frame rate from the running mean of its frames' CPU cost and the number of tabs."""

    def __init__(self):
        self.cost_s: float | None = None  # CPU seconds of one frame (tick + publish), a running mean
        self.frames = 0

    def spent(self, cpu_s: float) -> None:
        """One frame took ``cpu_s`` CPU seconds of the loop's thread."""
        cpu_s = max(float(cpu_s), 0.0)
        self.frames += 1
        if self.frames == 1:
            return  # a tab's first frame draws the whole scene: no guide to the next ones
        if not self.cost_s:
            self.cost_s = cpu_s
            return
        cpu_s = min(cpu_s, SPIKE * self.cost_s)  # a real change of cost still wins in a few tens of frames
        self.cost_s += SMOOTHING * (cpu_s - self.cost_s)

    def hz(self, tabs: int) -> float:
        """Frames per second for this tab while ``tabs`` tabs share the server."""
        tabs = max(int(tabs), 1)
        wanted = FRAME_HZ if tabs <= CROWD else CROWD_HZ
        if not self.cost_s:
            return wanted
        return max(MIN_HZ, min(wanted, SHARE / (tabs * self.cost_s)))

    def crowded(self, tabs: int) -> bool:
        return tabs > CROWD
