"""A scene that explains itself (issue 13, point 6), in a real browser: the legend on the page names the
parts the scene draws (and only those) with the factor the mass is drawn with; aligned arrows share one
label; the satellite chosen in "body drawn as" still draws after a preset change, seen in the page's canvas.

The server runs in this process so a test can hide one scene node and see whether the canvas changes (the
satellite was hidden behind the inertia ellipsoid's near face: three.js drew it, but nothing showed).
"""

from __future__ import annotations

import io
import re
import warnings

import numpy as np
import pytest
from test_app_browser import (
    CHROMIUM,
    FLAGS,
    SETTLE_MS,
    UI_TIMEOUT,
    browser,  # noqa: F401 (a fixture)
    choose_until,
    control_id,
    number_box,
    read,
    readouts,
    sync_api,
    wait_until,
)

from app.engine.trail import SAMPLES_PER_TURN
from app.scene.legend import LEGEND_CLASS, LEGEND_LINE_PX

pytestmark = pytest.mark.browser
Image = pytest.importorskip("PIL.Image")
SIZES = ((1400, 900), (1024, 768))
LEGEND_JS = """() => {
    const el = document.querySelector('.LEGEND_CLASS'); return el ? el.innerText : '';
}"""
LEGEND_BOX_JS = """() => {
    const el = document.querySelector('.LEGEND_CLASS'); if (!el) return null;
    const r = el.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom];
}"""
# the legend's lines and the part of the page its window shows: the nearest box around it that clips what overflows
LEGEND_SHOWN_JS = """() => {
    const el = document.querySelector('.LEGEND_CLASS'); if (!el) return null;
    let box = el.parentElement;
    while (box && getComputedStyle(box).overflowY === 'visible') box = box.parentElement;
    const r = el.getBoundingClientRect(), b = box.getBoundingClientRect();
    return {lines: el.innerText.split('\\n').length, top: r.top, bottom: r.bottom, shown_top: b.top,
            shown_bottom: b.bottom};
}"""
LEGEND_JS, LEGEND_BOX_JS, LEGEND_SHOWN_JS = (js.replace("LEGEND_CLASS", LEGEND_CLASS)
                                             for js in (LEGEND_JS, LEGEND_BOX_JS, LEGEND_SHOWN_JS))
SATELLITE = "satellite.stl"
FLAT_SPIN = "Explorer 1's flat spin"
MIN_CHANGED = 800  # px: hiding a body drawn 1.5 scene units across changes at least this many canvas pixels
PIXEL_TOL = 24  # per channel: software WebGL's dithering differs by a few levels between frames
# viser's client lowers the canvas's resolution (to 0.75x) while frames are slow, which on a loaded machine
# redraws every edge between two pictures of one scene; pictures that are compared are taken at a fixed one
FIXED_DPR = "?fixedDpr=1"

assert CHROMIUM and FLAGS and sync_api  # imported for the fixtures above


@pytest.fixture(scope="module")
def app():
    from app.serve.server import App, warm_up

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = App(port=0)
        warm_up()
    yield a
    a.close()


@pytest.fixture(scope="module")
def page(browser, app):  # noqa: F811
    pg = browser.new_page(viewport={"width": 1400, "height": 900})
    pg.set_default_timeout(UI_TIMEOUT)
    pg.goto(f"http://127.0.0.1:{app.port}/{FIXED_DPR}")
    pg.wait_for_selector("canvas")
    wait_until(pg, lambda: read(pg, "fidelity").startswith("full"), "the session's first readouts")
    wait_until(pg, lambda: legend(pg), "the legend", timeout_ms=UI_TIMEOUT)
    yield pg
    pg.close()


def legend(page) -> str:
    return page.evaluate(LEGEND_JS)


def set_warp(page, log10: float) -> None:
    box = number_box(page, "time warp (log10 x)")
    box.fill(f"{log10:g}")
    box.press("Enter")


def click(page, name: str) -> None:
    page.get_by_role("button", name=name, exact=True).first.click()
    page.wait_for_timeout(200)


def session(app):
    (s,) = app.sessions.values()  # the module's one tab
    return s


def canvas_png(page) -> np.ndarray:
    box = page.locator("canvas").first.bounding_box()
    shot = page.screenshot(clip={"x": box["x"], "y": box["y"], "width": box["width"], "height": box["height"]})
    return np.asarray(Image.open(io.BytesIO(shot)).convert("RGB"), dtype=int)


def test_the_legend_names_the_default_scenes_parts_and_the_mass_factor(page):
    text = legend(page)
    for part in ("K: angular momentum", "omega: angular velocity", "e3: symmetry axis", "body axes e1, e2, e3",
                 "uniform solid", "inertia ellipsoid", "moving mass", "spring", "rest point", "trail of e3"):
        assert part in text, f"the legend lacks {part!r}:\n{text}"
    for absent in ("pendulum bob", "cavity", "braking torque", "polhode"):
        assert absent not in text, f"the default scene has no {absent}, yet the legend names it:\n{text}"
    shown = page.evaluate(LEGEND_SHOWN_JS)  # the window as tall as its lines: all shown, little empty window
    assert shown["top"] >= shown["shown_top"] and shown["bottom"] <= shown["shown_bottom"], shown
    assert shown["shown_bottom"] - shown["bottom"] < 2 * LEGEND_LINE_PX, shown  # 59 px at a fixed height
    factor = float(number_box(page, "exaggerate u (x)").input_value())
    assert f"drawn x {factor:g}" in text  # the factor the page's slider shows
    assert factor < 10  # the old x10 drew the default scene's mass a body's size away


def test_the_legend_follows_a_pendulum_preset(page):
    choose_until(page, "Preset", "Spherical pendulum damper, resonant", lambda: "pendulum bob" in legend(page),
                 "the pendulum's legend")
    text = legend(page)
    assert "moving mass" not in text and "spring" not in text
    choose_until(page, "Preset", FLAT_SPIN, lambda: "moving mass" in legend(page) and "pendulum bob" not in
                 legend(page), "the moving mass's legend again")


def test_the_longest_legend_shows_every_line_at_both_sizes(page, app, tmp_path):
    """A mass, a cavity, a medium, the brake, the sphere and the polhode: 17 lines, the most a preset's legend has.
    In the panel's own type the last ones were scrolled out of the legend's window, where nobody looks for them."""
    name = "Braking with a fluid cavity and a resisting medium"
    choose_until(page, "Preset", name, lambda: "cavity filled" in legend(page), "the cavity's legend")
    page.locator(f'[id="{control_id(page, "polhode")}"]').check()
    wait_until(page, lambda: "polhode" in legend(page), "the polhode's line")
    want = session(app).drawing.legend.markdown.content.count("<br>") + 1  # the lines the page was sent
    assert want == 17
    for w, h in SIZES:
        page.set_viewport_size({"width": w, "height": h})
        page.wait_for_timeout(SETTLE_MS)
        shown = page.evaluate(LEGEND_SHOWN_JS)
        assert shown["lines"] == want, shown  # one line each: none wraps in the legend's width
        assert shown["shown_top"] <= shown["top"] and shown["bottom"] <= shown["shown_bottom"], (w, h, shown)
        assert shown["shown_bottom"] <= h, (w, h, shown)  # and the window itself is inside the page
        page.screenshot(path=str(tmp_path / f"legend_{w}x{h}.png"))
    page.locator(f'[id="{control_id(page, "polhode")}"]').uncheck()
    page.set_viewport_size({"width": 1400, "height": 900})


def test_aligned_arrows_share_one_label_once_settled(page, app, tmp_path):
    from app.engine.presets import DEFAULT

    choose_until(page, "Preset", DEFAULT, lambda: f"preset: {DEFAULT}" in readouts(page), "the default scene")
    set_warp(page, 2.0)  # 100x: the nutation closes within a few seconds
    wait_until(page, lambda: float(read(page, "theta").split()[0]) < 0.02, "the settled spin", timeout_ms=60_000)
    page.wait_for_timeout(1000)  # labels move at the plots' rate
    # viser draws scene labels on the canvas, not in the DOM: read the labels the page was sent
    labels = session(app).drawing.handles["labels"]
    assert [lab.text for lab in labels if lab.visible] == ["K, omega, e3"]
    for w, h in SIZES:  # pictures to look at, in tmp_path; the legend stays inside the window
        page.set_viewport_size({"width": w, "height": h})
        page.wait_for_timeout(SETTLE_MS)
        left, top, right, bottom = page.evaluate(LEGEND_BOX_JS)
        assert 0 <= left and right <= w and 0 <= top and bottom <= h, (w, h, left, top, right, bottom)
        page.screenshot(path=str(tmp_path / f"settled_{w}x{h}.png"))
    page.set_viewport_size({"width": 1400, "height": 900})


def test_the_satellite_still_draws_after_a_preset_change(page, app):
    choose_until(page, "body drawn as", SATELLITE, lambda: f"drawn as {SATELLITE}" in legend(page),
                 "the satellite in the legend")
    choose_until(page, "Preset", FLAT_SPIN, lambda: f"preset: {FLAT_SPIN}" in readouts(page),
                 "the preset chosen")
    wait_until(page, lambda: f"drawn as {SATELLITE}" in legend(page), "the preset, still drawn as the satellite")
    assert control_value(page, "body drawn as") == SATELLITE
    click(page, "Pause")
    page.wait_for_timeout(SETTLE_MS)
    shape = session(app).drawing.handles["shape"]
    assert len(shape.vertices) > 200  # the satellite's mesh (a cylinder has 194 vertices): server side
    shown = canvas_png(page)
    shape.visible = False  # the server-side hook: hide the body, and the page's canvas must change
    try:
        page.wait_for_timeout(SETTLE_MS)
        hidden = canvas_png(page)
    finally:
        shape.visible = True
    changed = int(np.count_nonzero(np.abs(shown - hidden).max(axis=2) > PIXEL_TOL))
    assert changed >= MIN_CHANGED, f"hiding the satellite changed only {changed} canvas pixels: it was not seen"
    click(page, "Play")


def control_value(page, label: str) -> str:
    return page.locator(f'[id="{control_id(page, label)}"]').input_value()


def test_at_10000x_the_trail_stays_a_ring(page, app, tmp_path):
    set_warp(page, 4.0)
    click(page, "Reset")
    page.wait_for_timeout(2500)
    s = session(app)
    trail = s.drawing.handles["trail"].points.astype(float)  # what was sent to the page: segments (n, 2, 3)
    chords = np.linalg.norm(trail[:, 1] - trail[:, 0], axis=1)
    reach = np.linalg.norm(trail.reshape(-1, 3), axis=1).max()  # the e3 arrow's length: the trail's sphere
    assert len(trail) >= SAMPLES_PER_TURN
    # each chord spans at most 1/24 of a turn of the cone (a chord across a disc would be up to 2 reach)
    assert chords.max() <= 2 * reach * np.sin(np.pi / SAMPLES_PER_TURN) * 1.01
    for w, h in SIZES:
        page.set_viewport_size({"width": w, "height": h})
        page.wait_for_timeout(SETTLE_MS)
        page.screenshot(path=str(tmp_path / f"warp10000_{w}x{h}.png"))
    page.set_viewport_size({"width": 1400, "height": 900})
    assert re.search(r"drawn as satellite\.stl", legend(page))


ROW_JS = """() => {
    const pause = [...document.querySelectorAll('button')].find(b => b.innerText.trim() === 'Pause');
    const status = [...document.querySelectorAll('p')].find(p => p.innerText.includes('Quasirigid explorer'));
    const r = pause.getBoundingClientRect(), s = status.getBoundingClientRect();
    return {pause_top: r.top, pause_bottom: r.bottom, status_top: s.top, status_height: s.height,
            status: status.innerText};
}"""


def row_when(page, words: str) -> dict | None:
    """Where the Run row and the status line are, once the status line says ``words``."""
    r = page.evaluate(ROW_JS)
    return r if words in r["status"] else None


def test_the_run_row_stays_put_while_the_status_line_changes_length(page):
    """The status line gains and loses "(reaching N x: ...)" as the machine's pace moves, one line or three: a row
    under it would move under the pointer (a click on Pause landed on the status line's text)."""
    set_warp(page, 4.0)  # whatever the status line says at 10000x on this machine
    click(page, "Play")
    playing = wait_until(page, lambda: row_when(page, "· playing"), "the status line while playing")
    assert playing["pause_bottom"] <= playing["status_top"], playing  # the row above the status line
    click(page, "Pause")
    paused = wait_until(page, lambda: row_when(page, "· paused"), "the status line while paused")
    assert paused["pause_top"] == playing["pause_top"], (playing, paused)
    click(page, "Play")
