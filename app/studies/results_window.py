"""Movable windows (viser 1.1's ``gui.add_panel``) that hold the study panels' results with room to read
them: the sweep's chart and points, the speed-versus-accuracy chart. Each study gets its own window.

The first window is docked to the left edge of the page, so the 3-D view shrinks beside it instead of being
covered: the legend (which floats at the view's left) and the momentum sphere (lower left in the view) stay
in sight. Its width is a share of the view's width as the browser reported it, between a chart's least
readable width and the width the charts were designed for. A second window stacks below the first in the
same column. The user can drag, float, resize or minimize them. (One window with a tab per study would hide
a new result behind the other tab: viser cannot switch tabs from Python.)

A gui without ``add_panel`` (an older viser, the tests' fake) gets None: the caller then places its
results inline, in its own folder.
"""

from __future__ import annotations

import weakref

WIDTH = 540  # px: a chart with its legend below and ticks that do not collide (the most a window takes)
MIN_WIDTH = 340  # px: the narrowest window whose chart ticks still read
SHARE = 0.36  # of the view's width, when the browser has reported it
HEIGHT = 600  # px: a window floated by the user starts this tall (the summary, chart and buttons of either study)

_first: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # gui -> its first results window


def width_for(canvas_width: int | None) -> int:
    """The docked column's width for a 3-D view ``canvas_width`` px wide (None or 0: not reported yet)."""
    if not canvas_width or canvas_width <= 0:
        return WIDTH
    return int(min(WIDTH, max(MIN_WIDTH, round(SHARE * canvas_width))))


def results_tab(gui, label: str, canvas_width: int | None = None):
    """A new window titled ``label`` (its single tab, a context to add widgets into), or None without panels."""
    add_panel = getattr(gui, "add_panel", None)
    if add_panel is None:
        return None
    window = add_panel()
    tab = window.add_tab(label)
    first = _first.get(gui)
    if first is not None:
        try:
            window.dock_below(first)
            window.set_height(HEIGHT)
            return tab
        except ValueError:  # the first window was closed: this one takes its place
            pass
    _first[gui] = window
    window.dock_left()
    window.set_width(width_for(canvas_width))
    window.set_height(HEIGHT)
    return tab
