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


def share_of_start(words: str) -> float:
    m = re.search(r"your \|K\| = \S+ \((\d+) % of its start\)", words)
    assert m, words
    return float(m.group(1))


def open_folder(pg) -> None:
    """The Braking challenge folder open (a test run alone finds it closed)."""
    if not pg.get_by_role("button", name="Start the challenge", exact=True).is_visible():
        pg.get_by_text("Braking challenge", exact=True).click()
        wait_until(pg, lambda: pg.get_by_role("button", name="Start the challenge", exact=True).is_visible(),
                   "the folder open")


def test_a_student_holds_a_key_and_the_thruster_fires_until_it_is_let_go(page, app):  # noqa: F811
    open_folder(page)
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
        wait_until(page, lambda: share_of_start(race(page)) < 97, "|K| falling under the thruster")
        assert eng.challenge.fired > 0.5  # simulated seconds with a thruster on
    finally:
        page.keyboard.up("q")
    wait_until(page, lambda: "thruster: off" in race(page), "the thruster off once Q is let go")
    np.testing.assert_allclose(np.array(camera.position), before, atol=1e-9)  # the key did not move the camera
    click(page, "End the challenge")
    wait_until(page, lambda: race(page) == "", "the race's words gone")
    assert eng.challenge is None


AIM = re.compile(r"K along your body's axes: e1 ([+-]\d\.\d\d) · e2 ([+-]\d\.\d\d) · e3 ([+-]\d\.\d\d)")
TORQUE = re.compile(r"thruster: \S+ \(torque (\S+) N m\)")
KEYS = {"+e1": "d", "-e1": "a", "+e2": "w", "-e2": "s", "+e3": "e", "-e3": "q"}


def test_a_student_who_reads_k_off_the_page_stops_the_body_and_is_scored(page, app):  # noqa: F811
    """A player with keys alone, as a student plays: K's body components read off the race's words, the key against
    the largest held down, and switched when another component becomes the largest, until the body stops; the
    page then shows the score T / T_you."""
    open_folder(page)
    click(page, "Start the challenge")
    wait_until(page, lambda: race(page) != "", "a race (the last test ended its own)")
    page.mouse.click(300, 450)
    held, b = None, None  # b: the thrusters' torque, read off the page once one fires
    try:
        for _ in range(2000):
            words = race(page)  # read once a look: under load each read waits for a page busy drawing
            if "score T / T_you" in words or "out of time:" in words:
                break
            m = AIM.search(words)
            if m:
                K = [float(x) for x in m.groups()]
                i = max(range(3), key=lambda j: abs(K[j]))
                key = KEYS[("-" if K[i] > 0 else "+") + f"e{i + 1}"]
                torque = TORQUE.search(words)
                if torque:
                    b = float(torque.group(1))
                if share_of_start(words) < 8 and b:  # near rest a held key overshoots: taps, each looked at
                    if held is not None:
                        page.keyboard.up(held)
                        held = None
                    # held as long as it takes to brake the largest component to a fifth, as a student learns to
                    K_abs = float(re.search(r"your \|K\| = (\S+) ", words).group(1))
                    page.keyboard.down(key)
                    page.wait_for_timeout(min(max(800 * abs(K[i]) * K_abs / b, 20), 1000))
                    page.keyboard.up(key)
                    page.wait_for_timeout(600)
                    continue
                if key != held:
                    if held is not None:
                        page.keyboard.up(held)  # let go first: its Thrusters off would stop the next one too
                    page.keyboard.down(key)
                    held = key
            page.wait_for_timeout(150)
    finally:
        if held is not None:
            page.keyboard.up(held)
    words = race(page)
    m = re.search(r"stopped in (\d+\.\d\d) s · score T / T_you = (\d\.\d\d)", words)
    assert m, words
    T = float(re.search(r"optimal T = (\d+\.\d) s", words).group(1))
    assert float(m.group(2)) == pytest.approx(T / float(m.group(1)), abs=0.01)  # both rounded as shown
    assert session(app).engine.challenge.score == pytest.approx(float(m.group(2)), abs=0.005)
