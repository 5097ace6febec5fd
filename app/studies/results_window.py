"""Movable windows (viser 1.1's ``gui.add_panel``) that hold the study panels' results with room to read
them: the sweep's chart and points, the speed-versus-accuracy chart. Each study gets its own window,
floating at the left of the 3-D view, clear of the control panel on the right; a second one opens a little
lower and to the right, so both title bars show. The user can drag, dock or minimize them. (One window
with a tab per study would hide a new result behind the other tab: viser cannot switch tabs from Python.)

A gui without ``add_panel`` (an older viser, the tests' fake) gets None: the caller then places its
results inline, in its own folder.
"""

from __future__ import annotations

import weakref

WIDTH = 540  # px: a chart with its legend below and ticks that do not collide
HEIGHT = 600  # px: the summary, chart and buttons of either study without scrolling, within a 768 px tall screen
GAP = 12  # px from the canvas's left and top edges
CASCADE = (40, 48)  # px right and down for each further window

_count: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def results_tab(gui, label: str):
    """A new window titled ``label`` (its single tab, a context to add widgets into), or None without panels."""
    add_panel = getattr(gui, "add_panel", None)
    if add_panel is None:
        return None
    k = _count.get(gui, 0)
    _count[gui] = k + 1
    window = add_panel()
    tab = window.add_tab(label)
    window.float(x=GAP + k * CASCADE[0], y=GAP + k * CASCADE[1], width=WIDTH, height=HEIGHT)
    return tab
