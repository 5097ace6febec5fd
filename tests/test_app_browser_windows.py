"""The study windows in a real browser (issue 24, point 5): opened at 1400x900 and at 1024x768, the Sweep and the
Speed windows sit in the control panel's column, beside the 3-D view, and cover neither the view nor the legend
nor the momentum sphere's label ("K in body axes"), read as the page lays them out. Before, they opened over the
legend and the sphere (floating), then, docked at the left edge, left a 1024 px page a view about 250 px wide
with the body under the control panel. The unit side is tests/test_results_window.py."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from test_app_browser import SETTLE_MS, browser, click, open_page, url  # noqa: F401 (browser and url are fixtures)

pytestmark = pytest.mark.browser

# every text on the page as rectangles: [left, top, right, bottom] of each rendered line of the first text node
# holding the words, and the 3-D view's canvas (the largest: the charts draw on canvases too)
RECTS_JS = """(words) => {
    const box = b => [b.left, b.top, b.right, b.bottom];
    const canvas = Array.from(document.querySelectorAll('canvas'))
        .sort((a, b) => b.clientWidth * b.clientHeight - a.clientWidth * a.clientHeight)[0];
    const found = {};
    const walk = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
    for (let n = walk.nextNode(); n; n = walk.nextNode()) {
        for (const w of words) {
            if (!(w in found) && n.textContent.includes(w)) {
                const range = document.createRange(); range.selectNodeContents(n);
                const r = range.getBoundingClientRect();
                if (r.width > 0 && r.height > 0) found[w] = box(r);
            }
        }
    }
    return {canvas: box(canvas.getBoundingClientRect()), found};
}"""
SWEEP, SPEED = "Run a sweep (", "Run the sweep ("  # the windows' first words, till the button's name
LEGEND, SPHERE = "K: angular momentum, fixed", "K in body axes"


def overlap(a, b) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


@pytest.mark.parametrize("size", [(1400, 900), (1024, 768)], ids=["1400x900", "1024x768"])
def test_the_study_windows_open_beside_the_view_not_over_its_legend_or_sphere(browser, url, size):  # noqa: F811
    page = open_page(browser, url, {"width": size[0], "height": size[1]})
    try:
        page.get_by_text("Sweep", exact=True).click()
        click(page, "Open the sweep panel")
        page.get_by_text("Speed vs accuracy", exact=True).first.click()
        click(page, "Open the speed vs accuracy panel")
        page.get_by_text(SPEED).wait_for()
        page.wait_for_timeout(SETTLE_MS)  # the dock's layout settles
        # the folders the user opened stay open (moving the control panel into the dock closed them all)
        assert page.get_by_role("button", name="Run sweep", exact=True).is_visible()
        rects = page.evaluate(RECTS_JS, [SWEEP, SPEED, LEGEND, SPHERE])
        canvas, found = rects["canvas"], rects["found"]
        assert set(found) == {SWEEP, SPEED, LEGEND, SPHERE}, found
        for window in (SWEEP, SPEED):
            assert found[window][0] >= canvas[2] - 1, (window, found[window], canvas)  # right of the 3-D view
            for seen in (LEGEND, SPHERE):
                assert not overlap(found[window], found[seen]), (window, seen, found)
        for seen in (LEGEND, SPHERE):  # the legend and the sphere's label are on the view, in full
            r = found[seen]
            assert canvas[0] <= r[0] and r[2] <= canvas[2] and canvas[1] <= r[1] and r[3] <= canvas[3], (seen, r)
        assert canvas[2] - canvas[0] >= 0.55 * size[0]  # the view keeps most of the page
        folder = os.environ.get("QUASIRIGID_SHOTS")
        if folder:
            page.screenshot(path=str(Path(folder) / f"windows_{size[0]}x{size[1]}.png"))
    finally:
        page.close()
