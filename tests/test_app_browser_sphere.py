"""The momentum sphere (issue 16, point 2) in a real browser: the "momentum sphere" toggle is on the page and
its state is read from the page; the sphere shows in the canvas (hiding it changes the canvas, showing it
again brings the same picture back); the companion chart names the pure spins in its legend, and goes with
the toggle. The server runs in this process (as tests/test_app_browser_scene.py) to read what it sent.
"""

from __future__ import annotations

import pytest
from test_app_browser import UI_TIMEOUT, browser, paused_t, read, wait_until  # noqa: F401 (browser: a fixture)
from test_app_browser_scene import FIXED_DPR, PIXEL_TOL, app, canvas_png, click, legend, session  # noqa: F401 (app: a fixture)

from app.panel.energy_plot import END, SPINS, TITLE

pytestmark = pytest.mark.browser
np = pytest.importorskip("numpy")
TOGGLE = "momentum sphere"
MIN_CHANGED = 800  # px: a sphere 1.2 scene units across, with its curves, covers far more of a 1400x900 canvas
LEGEND_NAME = "K in body axes"  # the legend's line for the sphere (app.scene.legend)
SAME_TOL = 0.2  # showing the sphere again changes at most this fraction of what hiding it changed (dithering)
SPINS_SHOWN = [f"{symbol} (J): {what}" for symbol, what in SPINS]  # the legend's names at the plain scale
TOGGLE_JS = """(label) => {
    const l = Array.from(document.querySelectorAll('label')).find(x => x.textContent.trim() === label);
    if (!l || !l.htmlFor) return null;
    const input = document.getElementById(l.htmlFor);
    return input ? input.checked : null;
}"""
PANEL_LEFT_JS = """() => {
    for (const p of document.querySelectorAll('p')) if (p.innerText.includes('Quasirigid explorer'))
        return p.getBoundingClientRect().left;
    return null;
}"""
PANEL_MARGIN = 40  # px: the panel's padding and border left of its status line


@pytest.fixture(scope="module")
def page(browser, app):  # noqa: F811
    pg = browser.new_page(viewport={"width": 1400, "height": 900})
    pg.set_default_timeout(UI_TIMEOUT)
    pg.goto(f"http://127.0.0.1:{app.port}/{FIXED_DPR}")
    pg.wait_for_selector("canvas")
    wait_until(pg, lambda: read(pg, "fidelity").startswith("full"), "the session's first readouts")
    yield pg
    pg.close()


def toggle_state(page) -> bool | None:
    return page.evaluate(TOGGLE_JS, TOGGLE)


def body_text(page) -> str:
    return page.evaluate("() => document.body.innerText")


def set_toggle(page, on: bool) -> None:
    if toggle_state(page) != on:
        page.locator("label").filter(has_text=TOGGLE).first.click()
    wait_until(page, lambda: toggle_state(page) is on, f"the toggle {'on' if on else 'off'}")


def pause(page, s, tries: int = 3) -> None:
    """Click Pause until the run has paused (a click while the panel is being resent can be lost)."""
    for _ in range(tries):
        click(page, "Pause")
        for _ in range(8):
            if not s.engine.playing:
                return
            page.wait_for_timeout(250)
    pytest.fail("the run did not pause")


def test_the_toggle_is_on_the_page_and_on_by_default(page, app):  # noqa: F811
    assert toggle_state(page) is True
    assert session(app).engine.show_sphere is True


def test_the_legend_names_the_sphere_and_its_curves(page):
    wait_until(page, lambda: LEGEND_NAME in legend(page), "the sphere in the legend")
    assert "separatrix" in legend(page)


def test_the_chart_names_the_pure_spins(page):
    wait_until(page, lambda: TITLE in body_text(page), "the sphere's chart")
    text = body_text(page)
    for name in SPINS_SHOWN:
        assert name in text, f"the chart's legend lacks {name!r}"


def test_the_chart_has_the_end_state_line_and_the_readout_matches_it(page, app):  # noqa: F811
    """The default scene dissipates without braking: the chart names its E_end line, and the readouts' E_end
    is physics.end_state's (app.engine.output.end_readouts prints 6 digits)."""
    end_name = f"{END[0]} (J): {END[1]}"
    wait_until(page, lambda: end_name in body_text(page), "the E_end line in the chart's legend")
    wait_until(page, lambda: read(page, "E_end") != "", "the E_end readout")
    engine = session(app).engine
    assert float(read(page, "E_end").split()[0]) == pytest.approx(engine.end_state().E_end, rel=1e-5)
    assert read(page, "energy still to lose").endswith(" J")


def settled_png(page, tries: int = 6):
    """The canvas once two pictures 1 s apart agree: on a loaded machine (a cold numba cache compiling in the
    background) the page can still be drawing what it was last sent when a single picture is taken."""
    last = canvas_png(page)
    for _ in range(tries):
        page.wait_for_timeout(1000)
        now = canvas_png(page)
        if now.shape == last.shape and not np.count_nonzero(np.abs(now - last).max(axis=2) > PIXEL_TOL):
            return now
        last = now
    return last


def test_the_sphere_is_in_the_canvas_and_goes_with_the_toggle(page, app):  # noqa: F811
    s = session(app)
    wait_until(page, lambda: s.engine.sphere_path.size > 10, "K's path on the sphere")
    path = s.drawing.sphere.path.points  # what the page was sent: segments on the sphere's radius
    assert len(path) > 5
    pause(page, s)
    t_paused = paused_t(page)
    # the path is sent at the plots' rate: the first picture must show all of it, or showing the sphere again
    # (which sends the whole path) would differ from it by the last segments
    wait_until(page, lambda: s.drawing.sphere._version == s.engine.sphere_path.version, "the whole path sent")
    shown = settled_png(page)
    set_toggle(page, False)
    wait_until(page, lambda: s.engine.show_sphere is False, "the engine told")
    wait_until(page, lambda: TITLE not in body_text(page), "the chart hidden with the sphere")
    wait_until(page, lambda: LEGEND_NAME not in legend(page), "the legend without the sphere")
    hidden = settled_png(page)
    set_toggle(page, True)
    wait_until(page, lambda: TITLE in body_text(page), "the chart shown again")
    wait_until(page, lambda: LEGEND_NAME in legend(page), "the legend naming the sphere again")
    again = settled_png(page)
    assert read(page, "t") == t_paused and not s.engine.playing  # the same scene in all three pictures
    click(page, "Play")
    scene = slice(0, int(page.evaluate(PANEL_LEFT_JS)) - PANEL_MARGIN)  # the 3-D view left of the panel, whose
    # chart comes and goes with the toggle too
    shown, hidden, again = (a[:, scene] for a in (shown, hidden, again))
    changed = int(np.count_nonzero(np.abs(shown - hidden).max(axis=2) > PIXEL_TOL))
    back = int(np.count_nonzero(np.abs(shown - again).max(axis=2) > PIXEL_TOL))
    assert changed >= MIN_CHANGED, f"hiding the sphere changed only {changed} canvas pixels"
    assert back <= SAME_TOL * changed, f"showing it again left {back} pixels changed (hiding changed {changed})"
