"""Share codes and the browser's memory of the last scene, in a real browser (issue 16, point 5): a code shared
in one tab reproduces the scene in another, a link offers its scene, a reload restores the last scene, and a
garbage code is refused with its reason while the scene stays. Everything is read from the pages."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_app_browser import (  # noqa: E402  (its fixtures start the server and chromium once per module)
    browser,
    click,
    number_box,
    open_page,
    read,
    readouts,
    set_slider,
    url,
    wait_until,
)

pytestmark = pytest.mark.browser
__all__ = ["browser", "url"]  # fixtures, used by name

CHI = "chi (1/s)"
SIX = ("m (kg)", "rho (m)", "Omega (rad/s)", "chi (1/s)", "lambda (1/s)", "b (N m)")
STATUS_JS = """() => {
    for (const p of document.querySelectorAll('p')) if (p.innerText.includes('Quasirigid explorer')) return p.innerText;
    return '';
}"""

NOTE_JS = """() => {
    for (const p of document.querySelectorAll('p')) if (p.innerText.startsWith('Not loaded')) return p.innerText;
    return '';
}"""

TOP_JS = """() => {
    for (const p of document.querySelectorAll('p')) if (p.innerText.includes('Quasirigid explorer')) p.scrollIntoView();
}"""


def status(page) -> str:
    return page.evaluate(STATUS_JS)


def text_box(page, label: str):
    """The text input in the row of ``label`` (viser 1.1's text label names an id the input does not carry)."""
    lab = page.locator("label").filter(has_text=re.compile(rf"^{re.escape(label)}$")).first
    return lab.locator("xpath=ancestor::div[contains(@class, 'mantine-Flex-root')][1]"
                       "//*[self::input or self::textarea]").first


def open_share(page) -> None:
    if not page.get_by_role("button", name="Share this scene", exact=True).is_visible():
        page.get_by_text("Share", exact=True).click()
    page.get_by_role("button", name="Share this scene", exact=True).wait_for()


def share_code(page) -> str:
    open_share(page)
    click(page, "Share this scene")
    return wait_until(page, lambda: text_box(page, "share code").input_value().startswith("qr1:") and
                      text_box(page, "share code").input_value(), "the share code")


def paste_and_load(page, text: str) -> None:
    open_share(page)
    box = text_box(page, "paste a code")
    box.fill(text)
    page.wait_for_timeout(200)  # the browser sends one GUI message per 50 ms: the text before the click
    click(page, "Load shared code")


def sliders(page) -> dict[str, str]:
    return {label: number_box(page, label).input_value() for label in SIX}


def at_t0(page) -> str:
    """The readouts at t = 0, paused, without the scene's name."""
    page.evaluate(TOP_JS)  # the playback buttons, scrolled to from the Share folder at the panel's bottom
    page.wait_for_timeout(300)
    click(page, "Pause")
    click(page, "Reset")
    # the end state is worked out off the tab's loop (app.engine.output): its readout says so until it is done
    wait_until(page, lambda: read(page, "t") == "0 s" and "working it out" not in readouts(page),
               "t = 0 after Reset, with the end state worked out")
    return "\n".join(line for line in readouts(page).splitlines() if not line.startswith("preset:"))


@pytest.fixture(scope="module")
def first(browser, url):
    pg = open_page(browser, url)
    set_slider(pg, CHI, 9.5)
    wait_until(pg, lambda: "(edited)" in readouts(pg) or number_box(pg, CHI).input_value() == "9.5", "chi = 9.5")
    yield pg
    pg.close()


def test_a_code_shared_in_one_tab_reproduces_the_scene_in_another(first, browser, url, tmp_path):
    code = share_code(first)
    first.get_by_role("button", name="Load shared code", exact=True).scroll_into_view_if_needed()
    first.wait_for_timeout(300)
    shot = tmp_path / "share_1400x900.png"
    first.screenshot(path=str(shot))
    assert shot.stat().st_size > 10_000
    second = open_page(browser, url)  # another browser context: its own storage, the default scene
    try:
        assert number_box(second, CHI).input_value() != "9.5"
        paste_and_load(second, code)
        wait_until(second, lambda: "preset: shared scene" in readouts(second), "the shared scene loaded")
        wait_until(second, lambda: number_box(second, CHI).input_value() == "9.5", "chi shown as 9.5")
        assert sliders(second) == sliders(first)
        assert share_code(second) == code  # the same scenario, bit for bit, read back from the page
        assert at_t0(second) == at_t0(first)  # same readouts from t = 0
    finally:
        second.close()


def test_a_reload_restores_the_last_scene(first):
    first.wait_for_timeout(1500)  # the last scene is written at most once a second
    first.reload()
    first.wait_for_selector("canvas")
    wait_until(first, lambda: "restored your last scene" in status(first), "the status line's note")
    wait_until(first, lambda: number_box(first, CHI).input_value() == "9.5", "chi restored as 9.5")
    assert "preset: your last scene" in readouts(first)


def test_a_garbage_code_is_refused_and_the_scene_stays(first):
    before = sliders(first)
    name = [line for line in readouts(first).splitlines() if line.startswith("preset:")]
    paste_and_load(first, "qr1:this is not a code!")
    message = wait_until(first, lambda: first.evaluate(NOTE_JS), "the refusal")
    assert "share code" in message and "'!'" in message and "URL-safe base64" in message
    first.wait_for_timeout(500)
    assert sliders(first) == before
    assert [line for line in readouts(first).splitlines() if line.startswith("preset:")] == name


def test_a_link_offers_its_scene_and_loads_it_when_asked(first, browser, url, tmp_path):
    code = share_code(first)
    link = text_box(first, "link").input_value()
    assert link == f"{url.rstrip('/')}/?scene={code}"  # the page's own address, read from the browser
    third = open_page(browser, link, viewport={"width": 1024, "height": 768})
    try:
        third.get_by_text("Open the shared scene?").wait_for()
        assert number_box(third, CHI).input_value() != "9.5"  # offered, not loaded silently
        shot = tmp_path / "share_link_1024x768.png"
        third.screenshot(path=str(shot))
        assert shot.stat().st_size > 10_000
        click(third, "Load the shared scene")
        wait_until(third, lambda: number_box(third, CHI).input_value() == "9.5", "the link's scene loaded")
        share_code(third)
        third.get_by_role("button", name="Load shared code", exact=True).scroll_into_view_if_needed()
        third.wait_for_timeout(500)
        third.screenshot(path=str(tmp_path / "share_1024x768.png"))
    finally:
        third.close()


def test_a_stored_value_that_does_not_decode_is_ignored_with_a_notice(browser, url):
    garbage = "window.localStorage.setItem('viser-user:quasirigid.last', 'qr1:garbage');"
    pg = open_page(browser, url, init_script=garbage)
    try:
        wait_until(pg, lambda: "could not be read; ignored" in status(pg), "the status line's notice")
        pg.get_by_text("Your last scene was not restored").wait_for()
        assert "preset: Default" in readouts(pg)  # the page's usual scene
    finally:
        pg.close()
