"""The sweep panel in a real browser (issue 13, point 3): the from/to boxes keep the decimals typed, the
sweep runs over exactly those values, the "best" line states its rule, and a later slider change marks the
result stale. Reads what the page shows; the server and browser fixtures are test_app_browser's."""

from __future__ import annotations

import re

import pytest
from test_app_browser import SIX, UI_TIMEOUT, browser, click, control_id, set_slider, url, wait_until  # noqa: F401

pytestmark = pytest.mark.browser
SWEEP_TIMEOUT = 240_000  # ms: five full runs of the default scene on a shared machine
TEXT_JS = """(pattern) => {
    const re = new RegExp(pattern);
    for (const p of document.querySelectorAll('p')) if (re.test(p.innerText)) return p.innerText;
    return '';
}"""


@pytest.fixture(scope="module")
def page(browser, url):  # noqa: F811 - the imported fixtures are this one's arguments
    pg = browser.new_page(viewport={"width": 1400, "height": 900})
    pg.set_default_timeout(UI_TIMEOUT)
    pg.goto(url)
    pg.wait_for_selector("canvas")
    pg.get_by_text(re.compile(r"Quasirigid explorer · ")).first.wait_for()  # the session's status line: connected
    yield pg
    pg.close()


def paragraph(page, pattern: str) -> str:
    """The text of the first paragraph on the page matching ``pattern`` ('' if none)."""
    return page.evaluate(TEXT_JS, pattern)


def box(page, label: str):
    return page.locator(f'[id="{control_id(page, label)}"]')


def type_into(page, label: str, text: str) -> None:
    b = box(page, label)
    b.click()
    b.fill(text)
    b.press("Tab")
    page.wait_for_timeout(300)


def test_typed_range_is_kept_run_and_the_best_line_states_its_rule(page, tmp_path):
    page.get_by_text("Sweep", exact=True).first.click()
    click(page, "Open the sweep panel")
    page.get_by_role("button", name="Run sweep", exact=True).wait_for()
    wait_until(page, lambda: box(page, "from").input_value() not in ("", "0"), "the default range")
    lo, hi = float(box(page, "from").input_value()), float(box(page, "to").input_value())
    assert 0 < lo < hi < 0.4, (lo, hi)  # m around the scene's 0.2, below the masses the body cannot hold
    type_into(page, "from", "0.05")
    type_into(page, "to", "0.25")
    type_into(page, "points", "5")
    assert box(page, "from").input_value() == "0.05" and box(page, "to").input_value() == "0.25"
    click(page, "Run sweep")
    done = wait_until(page, lambda: paragraph(page, r"points in [0-9.]+ s"), "the sweep to finish", SWEEP_TIMEOUT)
    assert "m from 0.05 to 0.25 (5 points)" in done, done
    best = wait_until(page, lambda: paragraph(page, r"^Best"), "the best line")
    assert "fastest decay" in best and "tau < 0 grows" in best, best
    m = re.search(r"decay_time = ([-0-9.e+]+) s at m = ([0-9.]+)", best)
    assert m, best
    assert float(m.group(1)) > 0 and float(m.group(2)) in (0.05, 0.1, 0.15, 0.2, 0.25)
    # the points list holds exactly the typed grid
    page.locator(f'[id="{control_id(page, "point")}"]').click()
    options = page.get_by_role("option").all_inner_texts()
    page.keyboard.press("Escape")
    ms = sorted(float(re.search(r"m = ([0-9.]+)", o).group(1)) for o in options)
    assert ms == [0.05, 0.1, 0.15, 0.2, 0.25], options
    page.screenshot(path=str(tmp_path / "sweep.png"))
    # another slider changes the scene: the result says it is stale
    set_slider(page, SIX["chi"], 7.5)
    wait_until(page, lambda: paragraph(page, r"Stale"), "the stale mark")
