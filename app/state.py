"""The names scripts and tests import from the explorer's engine, in one place. The engine itself lives in
``app.engine`` (requests, actions, stepping), ``app.clock`` (warp and frame budget), ``app.frame`` (what a
frame shows) and ``app.workers`` (overlay and badge threads)."""

from .clock import DEFAULT_WARP, FRAME_HZ, MAX_FRAME_DT, PROBE, TICK_BUDGET_S
from .engine import HISTORY_ROWS, PLOT_POINTS, SAMPLES_PER_FRAME, TRAIL_POINTS, VIEWS, Engine
from .frame import Frame
from .workers import OVERLAY_SAMPLES, OVERLAY_WINDOWS

__all__ = ["DEFAULT_WARP", "FRAME_HZ", "HISTORY_ROWS", "MAX_FRAME_DT", "OVERLAY_SAMPLES", "OVERLAY_WINDOWS",
           "PLOT_POINTS", "PROBE", "SAMPLES_PER_FRAME", "TICK_BUDGET_S", "TRAIL_POINTS", "VIEWS", "Engine", "Frame"]
