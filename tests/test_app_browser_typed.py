"""Numbers typed into the sliders' boxes as people write them, in a real browser (Debian's chromium via Playwright,
1400x900): ``1e-3``, ``1e308``, ``1,5``, ``abc``, an empty box and ``-2e+1``, reading what the page says under the
slider, what the box shows and what runs (the scenario the File folder downloads). viser's own number box dropped
what it did not expect (``1e-3`` arrived as -13, ``1,5`` as 15); the page's script sends the text as typed and the
server reads it (app/panel/typed_numbers.py, app/engine/typed.py).

The fixtures follow tests/test_app_browser.py: one server in a subprocess, one page, the tests in order.
"""

from __future__ import annotations

import re
import tomllib

import pytest
from test_app_browser import (  # noqa: F401 (browser and url are fixtures)
    ROOT,
    browser,
    click,
    number_box,
    open_page,
    url,
    wait_until,
)
from test_app_browser_reject import VIEWPORT, downloaded_scenario, type_into, visible_beside

pytestmark = pytest.mark.browser


@pytest.fixture(scope="module")
def page(browser, url):  # noqa: F811
    pg = open_page(browser, url, VIEWPORT)
    yield pg
    pg.close()


def running(page) -> dict:
    """The scenario that runs, as the File folder downloads it."""
    return tomllib.loads(downloaded_scenario(page))


def enter(page, label: str, text: str, key: str = "Enter"):
    """Type ``text`` over the box's value, key by key, and leave it with ``key`` (Enter, or Tab to the next)."""
    box = type_into(page, label, text) if text else _cleared(page, label)
    box.press(key)
    return box


def _cleared(page, label: str):
    box = number_box(page, label)
    box.evaluate("e => e.scrollIntoView({block: 'center'})")
    box.click()
    box.press("Control+a")
    box.press("Backspace")
    return box


GOOD: dict = {}  # the boxes' values before the refused texts: what must still run at the end


def test_1e_3_typed_in_lambda_is_0_001(page):
    box = enter(page, "lambda (1/s)", "1e-3")
    wait_until(page, lambda: box.input_value() == "0.001", "the lambda box to show 0.001")


def test_1e308_typed_in_m_is_refused_in_words_and_the_box_shows_the_mass_that_runs(page, tmp_path):
    m_box = number_box(page, "m (kg)")
    good = m_box.input_value()
    enter(page, "m (kg)", "1e308")
    visible_beside(page, re.compile(r"Rejected: m = 1e308 kg: must be less than .*m stays " + re.escape(good)), m_box)
    assert m_box.input_value() == good
    GOOD["m"] = float(good)
    page.screenshot(path=str(tmp_path / "typed_1e308.png"))


def test_an_omega_whose_arithmetic_overflows_is_refused_in_words_naming_it(page):
    """Omega = 1.7e100 passes validation, but the mass's quasi-static displacement overflows when the run is
    retuned: the page said "Rejected: OverflowError: (34, 'Numerical result out of range')" at the top and the
    same Python words beside the slider. Now it is refused as any bad value is, naming it and saying why."""
    box = number_box(page, "Omega (rad/s)")
    good = box.input_value()
    enter(page, "Omega (rad/s)", "1.7e100")
    visible_beside(page, re.compile(r"Rejected: Omega = 1\.7e\+100 rad/s: the run cannot start from it: a number "
                                    r"grew past the largest a float can hold .*Omega stays " + re.escape(good)), box)
    assert box.input_value() == good and "Error" not in page.inner_text("body")


def test_a_decimal_comma_is_read_as_a_decimal_point_and_said(page):
    box = enter(page, "chi (1/s)", "1,5", key="Tab")  # leaving the box sends it too
    visible_beside(page, re.compile(r"chi: '1,5' read as 1\.5 1/s"), box)
    wait_until(page, lambda: box.input_value() == "1.5", "the chi box to show 1.5")


def test_abc_and_an_empty_box_are_refused_and_the_boxes_show_the_values_that_run(page):
    omega = number_box(page, "Omega (rad/s)")
    good = omega.input_value()
    enter(page, "Omega (rad/s)", "abc")
    visible_beside(page, re.compile(r"Rejected: Omega = 'abc': not a number .*Omega stays " + re.escape(good)), omega)
    assert omega.input_value() == good
    rho = number_box(page, "rho (m)")
    rho_good = rho.input_value()
    enter(page, "rho (m)", "")
    visible_beside(page, re.compile(r"rho: the box was left empty; nothing changed\. rho stays " + re.escape(rho_good)),
                   rho)
    assert rho.input_value() == rho_good
    GOOD["Omega"], GOOD["rho"] = float(good), float(rho_good)
    click(page, "Reset")
    page.wait_for_timeout(500)
    assert omega.input_value() == good and rho.input_value() == rho_good  # never an empty box


def test_a_signed_exponent_is_read_and_a_negative_b_refused(page):
    box = enter(page, "b (N m)", "-2e+1")
    visible_beside(page, re.compile(r"Rejected: b = -2e\+1 N m: must be >= 0"), box)
    assert box.input_value() == "0"


def test_the_time_warp_box_takes_a_decimal_comma_too(page):
    enter(page, "time warp (log10 x)", "2,5")
    wait_until(page, lambda: "warp 316x" in page.get_by_text(re.compile(r"Quasirigid explorer ·")).first.inner_text(),
               "the warp of 10^2.5")


def test_what_runs_is_what_the_page_says(page):
    """One download of the scenario that runs (each is slow on a loaded machine): the values read are applied, the
    refused ones left the old values running, and nothing was clamped."""
    sc = running(page)
    assert sc["medium"]["lambda"] == 0.001 and sc["mass"]["chi"] == 1.5
    assert {k: sc["mass"][k] for k in GOOD} == GOOD
    assert "control" not in sc  # b = -2e+1 refused: no braking


def test_a_refused_upload_is_said_under_the_load_button_instead_of_uploaded_successfully(page, tmp_path):
    """viser says "File uploaded successfully." once a file has arrived, before the server reads it; a file the
    explorer refuses was said at the top of the panel, a screen away. Now the answer is under the button."""
    load = page.get_by_role("button", name="Load scenario (TOML)", exact=True)
    if not load.is_visible():
        page.get_by_text("File", exact=True).click()  # the folder starts collapsed
    page.evaluate("""() => { window.__notices = [];  // every notice text the page shows, as it shows it
        new MutationObserver(() => { for (const d of document.getElementsByClassName(
            'mantine-Notification-description')) window.__notices.push(d.textContent); })
        .observe(document.body, {childList: true, subtree: true, characterData: true}); }""")
    bad = (ROOT / "physics" / "data" / "default.toml").read_bytes().replace(b"\nm = 0.2\n", b"\nm = -1.0\n")
    assert b"m = -1.0" in bad
    page.locator("input[type=file]").first.set_input_files(
        {"name": "bad.toml", "mimeType": "application/toml", "buffer": bad})
    note = page.get_by_text(re.compile(r"Not loaded: mass\.m = -1.*The scene is unchanged\."))
    wait_until(page, lambda: note.count() and note.is_visible(), "the refusal under the Load button")
    nb, lb = note.bounding_box(), load.bounding_box()
    assert 0 <= nb["y"] - (lb["y"] + lb["height"]) <= 40, (nb, lb)  # right under the button
    notices = wait_until(page, lambda: [n for n in page.evaluate("window.__notices") if n.startswith("File ")],
                         "viser's notice, reworded")  # it closes by itself a few seconds later
    assert all(n.startswith("File received; whether it loaded") for n in notices), notices
    page.screenshot(path=str(tmp_path / "upload_refused.png"))
