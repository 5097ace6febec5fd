"""Controls where a lecturer reaches them (issue 13, point 7), in a real browser: Play, Pause, Step and
Reset visible without scrolling at 1400x900 and at 1024x768 (a projector); Space, R and the right arrow
(as in MuJoCo's viewer), listed on the page; choosing the current preset again reloads it; a preset that
names an overlay turns it on; choosing a system keeps the body. Everything is read from the page.
"""

from __future__ import annotations

import re

import pytest
from test_app_browser import (
    CHROMIUM,
    FLAGS,
    UI_TIMEOUT,
    browser,  # noqa: F401 (a fixture)
    choose,
    choose_until,
    control_id,
    number_box,
    paused_t,
    read,
    readouts,
    set_slider,
    sync_api,
    url,  # noqa: F401 (a fixture)
    wait_until,
)

import physics

pytestmark = pytest.mark.browser
SIZES = ((1400, 900), (1024, 768))  # a desktop and a projector
BUTTONS = ("Play", "Pause", "Step", "Reset")
STATUS_JS = """() => {
    for (const p of document.querySelectorAll('p'))
        if (p.innerText.startsWith('Quasirigid explorer')) return p.innerText;
    return '';
}"""
DETUNED = "Large spinning body, pendulum damper detuned (half the nutation frequency)"
DETUNED_K = 30.94059405940594  # assets/scenarios/pendulum_detuned.toml
OBLATE = "Oblate body settling"  # fidelity auto; the closed form's estimate, about 0.06 rad, meets 0.1
FIGURE_WITH_OVERLAY = "Pendulum damper, averaged against full model at eps = 1/4 (overlay averaged; Grobov 1968)"

assert CHROMIUM and FLAGS and sync_api  # imported for the fixtures above


def status(page) -> str:
    return page.evaluate(STATUS_JS)


def body_text(page) -> str:
    return page.evaluate("() => document.body.innerText")


def t_of(page) -> float:
    return float(read(page, "t").split()[0])


def open_folder(page, title: str, label: str) -> None:
    """Open a collapsed folder (its sliders are not in the page until then), unless ``label`` shows."""
    shown = page.locator("label").filter(has_text=re.compile(rf"^{re.escape(label)}$"))
    if not (shown.count() and shown.first.is_visible()):
        page.get_by_text(title, exact=True).click()
        page.wait_for_timeout(300)


def focus_the_scene(page) -> None:
    """Keys go to the page, not to a control: click the 3-D view, away from the panel."""
    page.mouse.click(120, 500)
    page.wait_for_timeout(200)


@pytest.fixture(scope="module")
def page(browser, url):  # noqa: F811
    pg = browser.new_page(viewport={"width": 1400, "height": 900})
    pg.set_default_timeout(UI_TIMEOUT)
    pg.goto(url)
    pg.wait_for_selector("canvas")
    wait_until(pg, lambda: read(pg, "fidelity").startswith("full"), "the session's first readouts")
    yield pg
    pg.close()


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_the_four_buttons_and_the_keys_are_visible_without_scrolling(browser, url, size, tmp_path):  # noqa: F811
    width, height = size
    pg = browser.new_page(viewport={"width": width, "height": height})
    pg.set_default_timeout(UI_TIMEOUT)
    try:
        pg.goto(url)
        pg.wait_for_selector("canvas")
        wait_until(pg, lambda: read(pg, "fidelity").startswith("full"), "the first readouts")
        assert pg.evaluate("() => [window.scrollX, window.scrollY]") == [0, 0]
        for name in BUTTONS:
            box = pg.get_by_role("button", name=name, exact=True).bounding_box()
            assert box is not None, name
            assert 0 <= box["x"] and box["x"] + box["width"] <= width, (name, box)
            assert 0 <= box["y"] and box["y"] + box["height"] <= height, (name, box)
        keys = pg.get_by_text(re.compile(r"^keys: Space play/pause"))
        assert keys.count() == 1
        kb = keys.bounding_box()
        assert kb["y"] + kb["height"] <= height  # the keys are listed where the buttons are
        pg.screenshot(path=str(tmp_path / f"controls_{width}x{height}.png"))
    finally:
        pg.close()


def test_a_browser_asking_for_reduced_motion_starts_paused_and_says_so(browser, url, tmp_path):  # noqa: F811
    """Issue 25 point 4 (WCAG 2.2.2): the operating system's reduced-motion setting, as chromium reports it."""
    pg = browser.new_page(viewport={"width": 1024, "height": 768}, reduced_motion="reduce")
    pg.set_default_timeout(UI_TIMEOUT)
    try:
        pg.goto(url)
        pg.wait_for_selector("canvas")
        wait_until(pg, lambda: "asks for reduced motion" in status(pg), "the reduced-motion note")
        assert "paused" in status(pg) and read(pg, "t") == "0 s"
        pg.wait_for_timeout(1000)
        assert read(pg, "t") == "0 s"  # it stays still
        pause = pg.get_by_role("button", name="Play", exact=True).bounding_box()
        assert pause["y"] + pause["height"] <= 768  # Play is in sight, beside the note
        pg.screenshot(path=str(tmp_path / "reduced_motion_1024x768.png"))
        pg.get_by_role("button", name="Play", exact=True).click()
        wait_until(pg, lambda: "playing" in status(pg) and "reduced motion" not in status(pg), "Play to start it")
        wait_until(pg, lambda: read(pg, "t") != "0 s", "t to move")
    finally:
        pg.close()


FOCUSED_JS = "() => { const e = document.activeElement; return e ? (e.innerText || e.value || '').trim() : ''; }"
TITLES_JS = """() => Array.from(document.querySelectorAll('[data-qr-key]')).map(
    t => [t.innerText.trim(), t.tabIndex, t.getAttribute('role'), t.getAttribute('aria-expanded')])"""


def tab_to(page, text: str, limit: int = 120) -> int:
    """Press Tab until the focused element's text is ``text``; the presses it took."""
    for n in range(1, limit + 1):
        page.keyboard.press("Tab")
        if page.evaluate(FOCUSED_JS) == text:
            return n
    pytest.fail(f"{text!r} not reached in {limit} presses of Tab")


def test_a_closed_folder_opens_from_the_keyboard_and_its_controls_work(browser, url, tmp_path):  # noqa: F811
    """Issue 25 point 4: folder titles are in the Tab order; Enter opens one, Space closes it without pausing
    the run, and a button inside is pressed with Enter: the File folder's scenario download, keyboard only."""
    pg = browser.new_page(viewport={"width": 1400, "height": 900})
    pg.set_default_timeout(UI_TIMEOUT)
    try:
        pg.goto(url)
        pg.wait_for_selector("canvas")
        wait_until(pg, lambda: read(pg, "fidelity").startswith("full"), "the first readouts")
        wait_until(pg, lambda: len(pg.evaluate(TITLES_JS)) >= 6, "the folder titles made keyboard buttons")
        titles = {t[0]: t[1:] for t in pg.evaluate(TITLES_JS)}
        for name in ("Details", "Plots", "Playback", "Model", "Share", "File"):
            assert titles[name][:2] == [0, "button"], (name, titles)
        assert titles["File"][2] == "false" and titles["Plots"][2] == "true"  # closed and open, as shown
        pg.locator("[data-qr-key]").filter(has_text=re.compile(r"^Braking challenge$")).focus()  # the one above File
        assert tab_to(pg, "File", limit=5) == 1  # the next stop of Tab
        pg.keyboard.press("Enter")
        download = pg.get_by_role("button", name="Download scenario (TOML)", exact=True)
        wait_until(pg, lambda: download.count() and download.is_visible(), "the File folder open")
        tab_to(pg, "Download scenario (TOML)", limit=10)
        with pg.expect_download() as got:
            pg.keyboard.press("Enter")
        assert "[run]" in open(got.value.path()).read()
        pg.screenshot(path=str(tmp_path / "keyboard_file_open.png"))
        title = pg.locator("[data-qr-key]").filter(has_text=re.compile(r"^File$"))
        title.focus()
        pg.keyboard.press(" ")
        wait_until(pg, lambda: not download.count(), "Space to close the folder")
        assert "playing" in status(pg)  # Space on a folder's title opens or closes it, and does not pause
    finally:
        pg.close()


def test_space_pauses_and_plays(page):
    focus_the_scene(page)
    page.keyboard.press("Space")
    wait_until(page, lambda: "paused" in status(page), "Space to pause")
    frozen = paused_t(page)  # the status line can show "paused" a frame before t's last value
    page.wait_for_timeout(1000)
    assert read(page, "t") == frozen  # t stands still on the page
    page.keyboard.press("Space")
    wait_until(page, lambda: "playing" in status(page), "Space to play")
    wait_until(page, lambda: read(page, "t") != frozen, "t to move again")


def test_r_resets_to_zero_and_the_right_arrow_steps(page):
    focus_the_scene(page)
    page.keyboard.press("Space")
    wait_until(page, lambda: "paused" in status(page), "Space to pause")
    page.keyboard.press("r")
    wait_until(page, lambda: read(page, "t") == "0 s", "R to reset to t = 0")
    page.keyboard.press("ArrowRight")
    wait_until(page, lambda: t_of(page) > 0, "the right arrow to step")
    one = t_of(page)
    page.keyboard.press("ArrowRight")
    wait_until(page, lambda: t_of(page) > one, "a second step")
    assert t_of(page) == pytest.approx(2 * one, rel=1e-3)  # the same step each time: warp / 60 s
    assert "paused" in status(page)  # stepping leaves the clock paused
    two = read(page, "t")
    thumb = page.locator(f'[id="{control_id(page, "chi (1/s)")}"] [role="slider"]')
    thumb.focus()
    page.keyboard.press("ArrowRight")  # a focused slider takes the arrow: one step of chi, no step of t
    page.wait_for_timeout(1000)
    assert read(page, "t") == two


def test_choosing_the_current_preset_again_reloads_it(page):
    choose_until(page, "Preset", DETUNED, lambda: DETUNED in readouts(page), "the detuned preset")
    open_folder(page, "Pendulum damper", "spring k (N m/rad)")
    k_box = number_box(page, "spring k (N m/rad)")
    wait_until(page, lambda: float(k_box.input_value()) == pytest.approx(DETUNED_K, rel=1e-3), "the preset's k")
    page.get_by_role("button", name="Tune to resonance", exact=True).click()
    wait_until(page, lambda: float(k_box.input_value()) != pytest.approx(DETUNED_K, rel=1e-3), "k tuned")
    preset_box = page.locator(f'[id="{control_id(page, "Preset")}"]')
    wait_until(page, lambda: preset_box.input_value() == DETUNED + " (edited)", "the preset marked edited")
    choose_until(page, "Preset", DETUNED,  # the same preset again
                 lambda: float(k_box.input_value()) == pytest.approx(DETUNED_K, rel=1e-3), "k reloaded")
    wait_until(page, lambda: preset_box.input_value() == DETUNED, "the plain preset name again")


def test_a_preset_that_names_an_overlay_turns_it_on(page):
    page.get_by_role("button", name="Play", exact=True).click()  # a paused new run has one row: no chart yet
    overlay_box = page.locator(f'[id="{control_id(page, "Overlay prediction")}"]')
    choose_until(page, "Preset", FIGURE_WITH_OVERLAY, lambda: overlay_box.input_value() == "averaged",
                 "the overlay the preset names")
    chart = page.get_by_text(re.compile(r"^theta and the averaged model's prediction"))
    wait_until(page, lambda: chart.count() > 0 and chart.first.is_visible(), "the prediction's chart")


def test_choosing_a_system_keeps_the_body(page):
    wait_until(page, lambda: read(page, "fidelity"), "the session's first readouts")  # the panel is the session's
    choose_until(page, "Preset", "Explorer 1's flat spin", lambda: "Explorer 1's flat spin" in readouts(page),
                 "the preset")
    open_folder(page, "Body inertia", "A (kg m^2)")
    set_slider(page, "A (kg m^2)", 1.2)  # a body no preset has (A <= B + C = 1.5)
    a_box, c_box = number_box(page, "A (kg m^2)"), number_box(page, "C (kg m^2)")
    wait_until(page, lambda: float(a_box.input_value()) == pytest.approx(1.2), "A edited")
    c_before = float(c_box.input_value())
    choose_until(page, "System", "spherical pendulum", lambda: "body kept" in readouts(page),
                 "the spherical pendulum with the body kept")
    assert float(a_box.input_value()) == pytest.approx(1.2)
    assert float(c_box.input_value()) == pytest.approx(c_before)
    assert read(page, "fidelity")  # the run goes on with the new system


def test_auto_s_accuracy_is_chosen_on_the_page_and_the_badge_and_readout_follow(page):
    """issue 15: auto with a looser accuracy runs the closed form where its estimate meets it (the badge
    states the estimate); the control shows only while auto is the fidelity."""
    choose_until(page, "Preset", OBLATE, lambda: OBLATE in readouts(page), "the oblate preset (fidelity auto)")
    wait_until(page, lambda: "auto → full" in body_text(page), "auto's badge at the default accuracy")
    assert f"accuracy asked: {physics.DEFAULT_ACCURACY:g} rad (the default)" in body_text(page)
    choose_until(page, "auto's accuracy", "0.1 rad", lambda: read(page, "fidelity").startswith("closed"),
                 "auto running the closed form")
    text = body_text(page)
    assert "auto → closed" in text and "accuracy asked: 0.1 rad" in text
    assert re.search(r"closed: within 0\.0\d+ rad of the full model over the run", text), text
    choose(page, "Fidelity", "full")
    wait_until(page, lambda: "auto's accuracy" not in body_text(page), "the control hidden without auto")
