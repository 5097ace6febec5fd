"""The plots and the trajectory export, read off the page in Debian's chromium at 1400x900 (issue 13,
points 4 and 5): uPlot's tick labels are drawn whole and are distinct, they bracket the value the
readouts show, the plots hold the run from t = 0 (or the last seconds, as chosen), the prediction starts
at t = 0, and the CSV downloaded after running at a high warp starts at t = 0.

uPlot draws its axes on a canvas, so the page holds no tick text in the DOM: an init script wraps the
canvas's fillText and keeps, per canvas, each text drawn since the canvas was last cleared, with its box
from measureText. A label cut by the canvas edge ("09.34" for 309.34) has a box reaching past it.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from test_app_browser import (  # noqa: F401  (url and browser are fixtures)
    LABELS_JS,
    UI_TIMEOUT,
    browser,
    choose,
    choose_until,
    click,
    open_page,
    paused_t,
    read,
    readouts,
    url,
    wait_until,
)

from app.panel.plots import SPANS

pytestmark = pytest.mark.browser

TICKS_HOOK = """(() => {
  const drawn = new WeakMap();  // canvas -> texts drawn since its last full clear
  const P = CanvasRenderingContext2D.prototype, clear = P.clearRect, fill = P.fillText;
  P.clearRect = function (x, y, w, h) {
    if (x <= 0 && y <= 0 && w >= this.canvas.width && h >= this.canvas.height) drawn.set(this.canvas, []);
    return clear.apply(this, arguments);
  };
  P.fillText = function (text, x, y) {
    const m = this.measureText(text), t = this.getTransform();
    const left = x - m.actualBoundingBoxLeft, right = x + m.actualBoundingBoxRight;
    const top = y - m.actualBoundingBoxAscent, bottom = y + m.actualBoundingBoxDescent;
    const list = drawn.get(this.canvas) || [];
    list.push({text: String(text), align: this.textAlign, left: t.a * left + t.e, right: t.a * right + t.e,
               top: t.d * top + t.f, bottom: t.d * bottom + t.f});
    drawn.set(this.canvas, list);
    return fill.apply(this, arguments);
  };
  window.__charts = () => Array.from(document.querySelectorAll('.uplot')).map(u => {
    const c = u.querySelector('canvas'), r = c.getBoundingClientRect();
    const box = (u.closest('.uplot-container') || u).getBoundingClientRect();
    return {title: (u.querySelector('.u-title') || {}).textContent || '',
            series: Array.from(u.querySelectorAll('.u-legend .u-series .u-label')).map(e => e.textContent),
            width: c.width, height: c.height, shown: r.width > 0 && r.height > 0,
            canvas: [r.left, r.top, r.width / c.width, r.height / c.height],
            box: [box.left, box.top, box.right, box.bottom], texts: drawn.get(c) || []};
  });
})();"""
READOUT_OF = {"nutation angle theta": "theta", "angular momentum |K|": "|K|", "energy E": "E"}


@pytest.fixture(scope="module")
def page(browser, url):  # noqa: F811
    pg = open_page(browser, url, init_script=TICKS_HOOK)
    yield pg
    pg.close()


def charts(page) -> list[dict]:
    """The charts shown, each with its y ticks (drawn right-aligned left of the plot) and x ticks."""
    out = []
    for ch in page.evaluate("() => window.__charts()"):
        if ch["shown"] and ch["texts"]:
            ch["y"] = [t for t in ch["texts"] if t["align"] == "right"]
            ch["x"] = [t for t in ch["texts"] if t["align"] == "center"]
            out.append(ch)
    return out


def number(text: str) -> float:
    return float(text.replace(",", "").replace("−", "-"))


def physical(label: str, tick: float) -> float:
    """A tick's value in the quantity's units, from the series' label: "|K| − 3.58 (×1e-9 kg m²/s)"."""
    off = re.search(r" − ([-+0-9.e]+) \(", label)
    exp = re.search(r"×1e(-?\d+)", label)
    return tick * 10.0 ** (int(exp.group(1)) if exp else 0) + (float(off.group(1)) if off else 0.0)


def check_ticks(page) -> list[dict]:
    """Every shown chart: y tick labels whole (inside the canvas), distinct, at least two, bracketing the
    value the readout shows; x tick labels whole and distinct; the canvas inside its chart's box."""
    shown = wait_until(page, lambda: [c for c in charts(page) if len(c["y"]) >= 2] or None, "charts with ticks")
    assert {c["title"] for c in shown} >= {"angular momentum |K|", "energy E"}, [c["title"] for c in shown]
    for ch in shown:
        what = f"{ch['title']} ({ch['series']}): {[t['text'] for t in ch['texts']]}"
        x0, y0, sx, sy = ch["canvas"]
        left, top, right, bottom = ch["box"]
        for t in ch["texts"]:
            assert t["left"] >= 0 and t["right"] <= ch["width"], f"{t['text']!r} cut at the side: {what}"
            assert t["top"] >= 0 and t["bottom"] <= ch["height"], f"{t['text']!r} cut at the top or bottom: {what}"
            # and inside the chart's box on the page
            assert left <= x0 + sx * t["left"] and x0 + sx * t["right"] <= right, f"{t['text']!r} outside: {what}"
            assert top <= y0 + sy * t["top"] and y0 + sy * t["bottom"] <= bottom, f"{t['text']!r} outside: {what}"
        for axis in ("y", "x"):
            texts = [t["text"] for t in ch[axis]]
            assert len(set(texts)) == len(texts), f"repeated {axis} ticks: {what}"
        assert len(ch["y"]) >= 2, what
        key = READOUT_OF.get(ch["title"]) or ("theta" if ch["title"].startswith("theta") else None)
        if key is None:
            continue
        ticks = sorted(physical(ch["series"][1], number(t["text"])) for t in ch["y"])
        step = ticks[1] - ticks[0]
        value = float(read(page, key).split()[0])
        assert ticks[0] - step <= value <= ticks[-1] + step, f"{key} = {value} off the axis {ticks}: {what}"
    return shown


def test_tick_labels_are_whole_distinct_and_right_on_the_default_scene(page):
    page.wait_for_timeout(2500)
    click(page, "Pause")
    page.wait_for_timeout(800)  # the last plot update after the pause
    check_ticks(page)
    click(page, "Play")


def _preset_with_the_largest_K() -> str:
    """The preset whose |K| is largest (Taylor's damper, |K| = 455, showed "0" for its ticks)."""
    import physics
    from app.engine import presets

    return max(presets.preset_names(), key=lambda n: physics.LiveRun(presets.load_preset(n)).last.K[0])


def test_tick_labels_of_a_large_nearly_constant_K(page):
    name = _preset_with_the_largest_K()
    choose_until(page, "Preset", name, lambda: f"preset: {name}" in readouts(page), "the preset in the readouts")
    page.wait_for_timeout(2500)
    click(page, "Pause")
    page.wait_for_timeout(800)
    shown = check_ticks(page)
    K = next(c for c in shown if c["title"] == "angular momentum |K|")
    assert float(read(page, "|K|").split()[0]) > 100  # the case the issue saw cut
    assert len(K["y"]) >= 2
    click(page, "Play")


def _x_ticks(page, title_start: str) -> list[float]:
    ch = next(c for c in charts(page) if c["title"].startswith(title_start))
    return [number(t["text"]) for t in ch["x"]]


def test_plots_show_the_whole_run_or_the_last_seconds(page):
    click(page, "Reset")
    page.wait_for_timeout(9000)  # past the recent window (6 s played)
    click(page, "Pause")
    t_now = float(paused_t(page).split()[0])
    assert min(_x_ticks(page, "energy E")) == 0.0  # the whole run, from t = 0
    # a dropdown whose options the server is resending can swallow a click: choose_until chooses again
    choose_until(page, "plots show", next(label for label, span in SPANS.items() if span == "recent"),
                 lambda: min(_x_ticks(page, "energy E")) > 0.0, "the plots to show the last seconds")
    assert max(_x_ticks(page, "energy E")) <= t_now
    choose_until(page, "plots show", "whole run", lambda: min(_x_ticks(page, "energy E")) == 0.0,
                 "the whole run again")
    click(page, "Play")


def _control(page, text: str) -> str:
    return next(i for label, i, _ in page.evaluate(LABELS_JS) if label == text)


def test_the_prediction_starts_at_t0(page):
    from app.engine import presets

    choose_until(page, "Preset", presets.DEFAULT,  # the moving mass: its averaged model predicts theta
                 lambda: f"preset: {presets.DEFAULT}" in readouts(page), "the default scene")
    choose(page, "Overlay prediction", "averaged")
    shown = wait_until(page, lambda: [c for c in charts(page) if "from t = 0" in c["title"]] or None,
                       "the prediction's chart")
    assert min(number(t["text"]) for t in shown[0]["x"]) == 0.0
    assert len(shown[0]["series"]) == 3 and shown[0]["series"][2].startswith("prediction")
    choose(page, "Overlay prediction", "none")


def test_csv_after_a_high_warp_starts_at_t0(page, tmp_path):
    warp = next(label for label, _i, slider in page.evaluate(LABELS_JS) if "warp" in label and slider)
    box = page.locator(f'[id="{_control(page, warp)}"]').locator("xpath=..").locator("input.mantine-NumberInput-input")
    box.fill("3")  # 10^3 x
    box.press("Enter")
    click(page, "Reset")
    click(page, "Play")
    page.wait_for_timeout(4000)
    click(page, "Pause")
    t_page = float(paused_t(page).split()[0])
    assert t_page > 20.0  # it ran faster than real time (1000x asked; a loaded machine reaches less)
    page.get_by_text("File", exact=True).click()
    with page.expect_download() as info:
        click(page, "Download trajectory (CSV)")
    path = tmp_path / "trajectory.csv"
    info.value.save_as(path)
    text = Path(path).read_text()
    lines = text.splitlines()
    comments = [ln for ln in lines if ln.startswith("#")]
    assert comments and lines[len(comments)].startswith("t,theta,K,E")
    table = np.loadtxt(path, delimiter=",", skiprows=len(comments) + 1, ndmin=2)
    assert table[0, 0] == 0.0  # from the start of the run
    assert table[-1, 0] == pytest.approx(t_page, rel=1e-3)  # to the time the page shows
    assert np.all(np.diff(table[:, 0]) > 0)
