"""The braking challenge on the page (issue 25, point 2), as a student plays it: the folder opened, Start, a key
held (the page names the keys) fires its thruster and lets go when released, the camera stays where it was
(viser moves it on the same keys outside a race), |K| falls in the race's words, End ends it. Everything the
test asserts about the race is read from the page; the server's engine is read only to confirm the thruster and
the camera."""

from __future__ import annotations

import re

import numpy as np
import pytest
from test_app_browser import (
    browser,  # noqa: F401 (a fixture)
    wait_until,
)
from test_app_browser_scene import (  # the scene module's server and page, one of each for this module
    app,  # noqa: F401 (a fixture)
    click,
    page,  # noqa: F401 (a fixture)
    session,
)

pytestmark = pytest.mark.browser
RACE_JS = """() => {
    for (const p of document.querySelectorAll('p'))
        if (p.innerText.startsWith('Braking challenge ·')) return p.innerText;
    return '';
}"""


def race(pg) -> str:
    return pg.evaluate(RACE_JS)


def share_of_start(pg) -> float:
    m = re.search(r"your \|K\| = \S+ \((\d+) % of its start\)", race(pg))
    assert m, race(pg)
    return float(m.group(1))


def test_a_student_holds_a_key_and_the_thruster_fires_until_it_is_let_go(page, app):  # noqa: F811
    page.get_by_text("Braking challenge", exact=True).click()
    assert "keys during a race: D +e1 · A -e1" in page.evaluate("() => document.body.innerText")
    click(page, "Start the challenge")
    wait_until(page, lambda: "A rigid body · start 0" in race(page) and "thruster: off" in race(page),
               "the race's words")
    eng = session(app).engine
    camera = session(app).client.camera
    before = np.array(camera.position)
    page.mouse.click(300, 450)  # the 3-D view has the focus, as when a student looks at the bodies
    page.keyboard.down("q")
    try:
        wait_until(page, lambda: "thruster: -e3" in race(page), "the thruster -e3 firing while Q is held")
        wait_until(page, lambda: share_of_start(page) < 97, "|K| falling under the thruster")
        assert eng.challenge.fired > 0.5  # simulated seconds with a thruster on
    finally:
        page.keyboard.up("q")
    wait_until(page, lambda: "thruster: off" in race(page), "the thruster off once Q is let go")
    np.testing.assert_allclose(np.array(camera.position), before, atol=1e-9)  # the key did not move the camera
    click(page, "End the challenge")
    wait_until(page, lambda: race(page) == "", "the race's words gone")
    assert eng.challenge is None
