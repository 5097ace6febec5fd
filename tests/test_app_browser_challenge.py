"""The braking challenge on the page (issue 25, point 2), as a student plays it: the folder opened, Start, a key
held (the page names the keys) fires its thruster and lets go when released, the camera stays where it was
(viser moves it on the same keys outside a race), |K| falls in the race's words, End ends it. Everything the
test asserts about the race is read from the page; the server's engine is read only to confirm the thruster and
the camera."""

from __future__ import annotations

import re
import time

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


def over(words: str) -> bool:
    """The race's words say it has ended: stopped and scored, or out of time."""
    return "score T / T_you" in words or "out of time:" in words


def elapsed(words: str) -> float:
    m = re.search(r"elapsed (\d+\.\d) s", words)
    assert m, words
    return float(m.group(1))


def wait_fresh(pg, let_go: float) -> None:
    """Until the words show the clock past ``let_go`` (race seconds) with the thruster off, or the race over: a page
    busy drawing shows them late, and a tap decided on stale words brakes what is already braked."""
    def fresh() -> bool:
        words = race(pg)
        return over(words) or ("thruster: off" in words and elapsed(words) >= let_go + 0.2)
    wait_until(pg, fresh, "the race's words after the key was let go", 10_000)


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


def brake_key(K, i: int) -> str:
    """The key whose thruster brakes K's component i."""
    return KEYS[("-" if K[i] > 0 else "+") + f"e{i + 1}"]


def test_a_student_who_reads_k_off_the_page_stops_the_body_and_is_scored(page, app):  # noqa: F811
    """A player with keys alone, as a student who knows the body is axisymmetric plays: K's body components read off
    the race's words; the spin component braked first (it does not turn in the body's axes, and once it is gone
    the others stop turning), then the larger of the other two; a key held while the component is more than a
    look's worth of braking, tapped once it is less, each tap looked at, until the body stops; the page then shows
    the score T / T_you."""
    # a small window: software WebGL draws it three times faster, and a page busy drawing hands the keys on late
    # (beside four busy processes an earlier version of this player stopped in 51 s of the 60 s allowed at 1400x900,
    # 47 s at 800x520; this one, beside three, in 41 s and 42 s at 800x520)
    page.set_viewport_size({"width": 800, "height": 520})
    open_folder(page)
    click(page, "Start the challenge")
    wait_until(page, lambda: race(page) != "", "a race (the last test ended its own)")
    page.mouse.click(300, 450)
    held, b = None, None  # b: the thrusters' torque, read off the page once one fires
    look_s, looked = 0.5, None  # how long a look takes, learned as the race goes: under load a page is slow to read
    try:
        for _ in range(2000):
            words = race(page)  # read once a look: under load each read waits for a page busy drawing
            now = time.monotonic()
            if looked is not None:
                look_s = max(0.8 * look_s, now - looked)
            looked = now
            if over(words):
                break
            m = AIM.search(words)
            if m:
                K_abs = float(re.search(r"your \|K\| = (\S+) ", words).group(1))
                K = [float(x) * K_abs for x in m.groups()]
                torque = TORQUE.search(words)
                if torque:
                    b = float(torque.group(1))
                margin = 0.0 if b is None else 1.5 * b * look_s  # what a held key brakes before the next look
                # the held key kept until its component is braked: two nearly equal ones would be swapped every look
                i = next((j for j in range(3) if held == brake_key(K, j)), None)
                if i is None or abs(K[i]) <= margin:
                    i = 2 if abs(K[2]) > margin else max(range(2), key=lambda j: abs(K[j]))
                key = brake_key(K, i)
                if b is not None and abs(K[i]) <= margin:  # held, it would overshoot before the next look: a tap
                    if held is not None:  # let go, and the tap decided on words from after the let-go
                        page.keyboard.up(held)
                        held = None
                        wait_fresh(page, elapsed(words) + time.monotonic() - now)
                        looked = None
                        continue
                    i = max(range(3), key=lambda j: abs(K[j]))
                    key = brake_key(K, i)
                    page.keyboard.down(key)
                    page.wait_for_timeout(min(max(600 * abs(K[i]) / b, 20), 1000))  # to 0.4 of it: let go late, it
                    page.keyboard.up(key)                                             # overshoots less
                    wait_fresh(page, elapsed(words) + time.monotonic() - now)
                    looked = None
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
        page.set_viewport_size({"width": 1400, "height": 900})
    words = race(page)
    m = re.search(r"stopped in (\d+\.\d\d) s · score T / T_you = (\d\.\d\d)", words)
    assert m, words
    T = float(re.search(r"optimal T = (\d+\.\d) s", words).group(1))
    assert float(m.group(2)) == pytest.approx(T / float(m.group(1)), abs=0.01)  # both rounded as shown
    assert session(app).engine.challenge.score == pytest.approx(float(m.group(2)), abs=0.005)
