"""The Design panel in a real browser, as an engineer uses it: open it, keep its first slider and range, run a short
design, read the optimum in the Design window, take it into the scene; then start a long one and stop it. Reads what
the page shows; the server and browser fixtures are test_app_browser's."""

from __future__ import annotations

import re

import pytest
from test_app_browser import UI_TIMEOUT, browser, choose, click, number_box, url, wait_until  # noqa: F401
from test_app_browser_sweep import box, paragraph

pytestmark = pytest.mark.browser
DESIGN_TIMEOUT = 300_000  # ms: twenty runs of the default scene and the full model's check, on a shared machine
VIEWPORT = {"width": 1400, "height": 900}


@pytest.fixture(scope="module")
def page(browser, url):  # noqa: F811 - the imported fixtures are this one's arguments
    pg = browser.new_page(viewport=VIEWPORT)
    pg.set_default_timeout(UI_TIMEOUT)
    pg.goto(url)
    pg.wait_for_selector("canvas")
    pg.get_by_text(re.compile(r"Quasirigid explorer · ")).first.wait_for()  # the session's status line: connected
    yield pg
    pg.close()


def set_runs(page, n: int) -> None:
    b = box(page, "runs at most")
    b.click()
    b.fill(str(n))
    b.press("Tab")
    wait_until(page, lambda: b.input_value() == str(n), f"runs at most = {n}")


def test_a_design_shows_its_optimum_in_its_window_and_the_scene_takes_it(page, tmp_path):
    page.get_by_text("Design", exact=True).first.click()
    click(page, "Open the design panel")
    page.get_by_role("button", name="Run design", exact=True).wait_for()
    wait_until(page, lambda: box(page, "from").input_value() not in ("", "0"), "the default range")
    lo, hi = float(box(page, "from").input_value()), float(box(page, "to").input_value())
    assert 0 < lo < hi, (lo, hi)
    set_runs(page, 20)
    click(page, "Run design")
    done = wait_until(page, lambda: paragraph(page, r"^Done: \d+ runs"), "the design to finish", DESIGN_TIMEOUT)
    assert "(stopped)" not in done and "Take the optimum" in done, done
    optimum = wait_until(page, lambda: paragraph(page, r"^Optimum"), "the optimum in the Design window")
    found = re.search(r"\): (\S+) = ([-0-9.e+]+)", optimum)
    assert found, optimum
    label, value = found.group(1), float(found.group(2))
    assert lo * (1 - 1e-3) <= value <= hi * (1 + 1e-3), (value, lo, hi)  # printed to 4 digits
    assert re.search(r"decay_time = [-0-9.e+]+ s from the full model", optimum), optimum  # checked, not stopped
    result = page.get_by_text(re.compile(r"^Optimum")).first
    bb = result.bounding_box()
    assert result.is_visible() and 0 <= bb["y"] and bb["y"] + bb["height"] <= VIEWPORT["height"], bb
    page.screenshot(path=str(tmp_path / "design.png"))
    click(page, "Take the optimum")
    took = wait_until(page, lambda: paragraph(page, r"^Took the optimum"), "the optimum taken")
    assert f"{label} = " in took, took
    wait_until(page, lambda: abs(float(number_box(page, _slider_label(page, label)).input_value()) - value)
               <= 1e-3 * abs(value), f"the {label} box at the optimum {value}")


def _slider_label(page, label: str) -> str:
    """The slider's full label ("m (kg)") for the short name the summary uses ("m")."""
    texts = page.locator("label").all_inner_texts()
    return next(t for t in texts if t == label or t.startswith(label + " ("))


def test_stop_design_ends_a_long_design_with_what_it_found(page):
    """Three sliders: a coarse start of 27 runs and refinements, a minute or more (one slider's design converges
    in a few dozen runs, and ended before Stop could be pressed)."""
    choose(page, "second parameter", "chi (1/s)")  # the sliders' own names, as the panel reads
    choose(page, "third parameter", "Omega (rad/s)")
    wait_until(page, lambda: box(page, "from (3rd)").is_visible(), "the third slider's range")
    set_runs(page, 400)
    click(page, "Run design")
    wait_until(page, lambda: paragraph(page, r"^Run \d+ of at most 400"), "the design's first runs", DESIGN_TIMEOUT)
    click(page, "Stop design")
    done = wait_until(page, lambda: paragraph(page, r"^Done: \d+ runs"), "the stopped design's end", DESIGN_TIMEOUT)
    runs = int(re.search(r"Done: (\d+) runs", done).group(1))
    assert "(stopped)" in done and 1 <= runs < 400, done
    assert page.get_by_role("button", name="Run design", exact=True).is_enabled()
