"""The viscous wheel damper on the page (issue 22): chosen in the System dropdown, its wheel is drawn where the
canvas shows it and the legend names it with its role's words from physics.

The server runs in this process so the test can hide the wheel's scene node and see whether the canvas changes
(a part drawn inside the opaque body would be sent, yet nothing would show).
"""

from __future__ import annotations

import numpy as np
import pytest
from test_app_browser import (
    SETTLE_MS,
    browser,  # noqa: F401 (a fixture)
    read,
    wait_until,
)
from test_app_browser_scene import (  # the scene module's server and page, one of each for this module
    PIXEL_TOL,
    app,  # noqa: F401 (a fixture)
    canvas_png,
    choose_until,
    click,
    legend,
    page,  # noqa: F401 (a fixture)
)

import physics
from app.scene.legend import FIGURE_COLORS

pytestmark = pytest.mark.browser
WHEEL = "viscous wheel"  # the wheel system's label, offered in the System dropdown (lower case, as the others)
# px: the wheel is a translucent disk 0.25 of the body's extent in radius inside the translucent body, so it
# changes far fewer pixels than a hidden body (test_app_browser_scene's 800): hiding it at t = 0 changed 255
# pixels at 1400x900 when it was a bare ring (2026-11-26), and one drawn edge-on still changes its axle's line
MIN_CHANGED = 150



def session(app):  # noqa: F811
    (s,) = app.sessions.values()  # the module's one tab
    return s


def wheel_label(scenario) -> str:
    """The wheel role's words as physics gives them: the legend must say these, not the app's own."""
    view = physics.figure.View(extent=1.0)
    disks = [p for p in physics.get_system(scenario.system).figure(scenario, {}, view) if p.role == "wheel"]
    assert disks, "the wheel system's figure has no wheel role"
    return disks[0].label


def test_the_wheel_damper_draws_its_wheel_and_names_it_in_the_legend(page, app):  # noqa: F811
    choose_until(page, "System", WHEEL, lambda: session(app).engine.scenario.system == "wheel",
                 "the wheel system chosen")
    label = wheel_label(session(app).engine.scenario)
    wait_until(page, lambda: label in legend(page), f"the legend line {label!r}")
    assert "moving mass" not in legend(page)  # the default system's part is gone with it
    click(page, "Pause")
    click(page, "Reset")  # t = 0: the body's start attitude, where the camera sees the wheel's face, not its edge
    wait_until(page, lambda: read(page, "t") == "0 s", "the scene reset and paused")
    page.wait_for_timeout(SETTLE_MS)
    wheel = session(app).drawing.parts.nodes["wheel"]  # the disk's scene node (app.scene.figure_view)
    # the paused picture settles first: the momentum sphere's "end" label can come a few seconds after the system
    # change (115 pixels), and a first picture taken before it read as the scene drifting
    shown = canvas_png(page)
    for _ in range(10):
        page.wait_for_timeout(SETTLE_MS)
        later = canvas_png(page)
        if int(np.count_nonzero(np.abs(shown - later).max(axis=2) > PIXEL_TOL)) == 0:
            break
        shown = later
    wheel.visible = False  # the server-side hook: hide the wheel, and the page's canvas must change
    try:
        page.wait_for_timeout(SETTLE_MS)
        hidden = canvas_png(page)
    finally:
        wheel.visible = True
    page.wait_for_timeout(SETTLE_MS)
    again = canvas_png(page)
    changed = np.abs(shown - hidden).max(axis=2) > PIXEL_TOL
    assert int(np.count_nonzero(changed)) >= MIN_CHANGED, (
        f"hiding the wheel changed only {int(np.count_nonzero(changed))} canvas pixels: it was not seen")
    # where the canvas changed it showed the wheel: those pixels were nearer the wheel's shade shown than hidden
    shade = np.array(FIGURE_COLORS["wheel"])
    near = np.abs(shown[changed] - shade).sum(axis=1) < np.abs(hidden[changed] - shade).sum(axis=1)
    assert near.mean() > 0.5, f"only {near.mean():.0%} of the changed pixels turned toward the wheel's colour"
    # the change is the wheel's, not the scene drifting: shown again, the canvas is the first picture
    drift = int(np.count_nonzero(np.abs(shown - again).max(axis=2) > PIXEL_TOL))
    assert drift < MIN_CHANGED // 5, f"the paused scene itself changed {drift} pixels"
    click(page, "Play")
