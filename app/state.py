"""The names scripts and tests import from the explorer's engine, in one place. The engine itself lives in
the package ``app.engine``: ``engine`` (requests, actions, stepping), ``clock`` (warp and frame budget), ``frame``
(what a frame shows) and ``workers`` (overlay and badge threads)."""

from .engine.clock import DEFAULT_WARP, FRAME_HZ, MAX_FRAME_DT, PROBE, TICK_BUDGET_S
from .engine.engine import HISTORY_ROWS, PLOT_POINTS, SAMPLES_PER_FRAME, TRAIL_POINTS, VIEWS, Engine
from .engine.frame import Frame
from .engine.workers import OVERLAY_SAMPLES, OVERLAY_WINDOWS

__all__ = ["DEFAULT_WARP", "FRAME_HZ", "HISTORY_ROWS", "MAX_FRAME_DT", "OVERLAY_SAMPLES", "OVERLAY_WINDOWS",
           "PLOT_POINTS", "PROBE", "SAMPLES_PER_FRAME", "TICK_BUDGET_S", "TRAIL_POINTS", "VIEWS", "Engine", "Frame"]
