"""Compare mode in a real browser (issue 16, point 1), read off the page in Debian's chromium at 1400x900:
turned on with a parameter difference (the default scene with and without the mass), both runs' readouts
show and differ, the charts' legends name both runs, an edit keeps the difference, and turning it off takes
the second readout and the overlaid charts away.
"""

from __future__ import annotations

import re

import pytest
from test_app_browser import (  # noqa: F401  (url and browser are fixtures)
    UI_TIMEOUT,
    browser,
    choose,
    open_page,
    set_slider,
    url,
    wait_until,
)

pytestmark = pytest.mark.browser

COMPARE_JS = """() => {
    for (const p of document.querySelectorAll('p')) if (p.innerText.includes('run 2: ')) return p.innerText;
    return '';
}"""
CHARTS_JS = """() => Array.from(document.querySelectorAll('.uplot')).filter(u => {
        const r = u.getBoundingClientRect(); return r.width > 0 && r.height > 0; })
    .map(u => ({title: (u.querySelector('.u-title') || {}).textContent || '',
                series: Array.from(u.querySelectorAll('.u-legend .u-series .u-label')).map(e => e.textContent)}))"""
NUMBER = r"([-+0-9.eE]+)"


@pytest.fixture(scope="module")
def page(browser, url):  # noqa: F811
    pg = open_page(browser, url)
    yield pg
    pg.close()


def runs(page) -> dict[str, dict[str, float]]:
    """{"run 1": {"theta": ..., "|K|": ..., "E": ...}, "run 2": {...}} from the compare readout's lines."""
    out = {}
    for line in page.evaluate(COMPARE_JS).splitlines():
        m = re.match(r"^(run [12]): theta = ", line)
        if m:
            out[m.group(1)] = {k: float(re.search(rf"{re.escape(k)} = {NUMBER}", line).group(1))
                               for k in ("theta", "|K|", "E")}
    return out


def shown_charts(page) -> list[dict]:
    return page.evaluate(CHARTS_JS)


def test_compare_mode_shows_both_runs_names_them_and_goes_away(page, tmp_path):
    page.get_by_text("Compare", exact=True).click()
    page.wait_for_timeout(300)  # the folder opens
    choose(page, "compare with", "another value of a parameter")  # first offered: m = 0, without the mass
    try:
        both = wait_until(page, lambda: runs(page) if len(runs(page)) == 2 else None, "both runs' readouts")
    except BaseException:  # what the page showed instead, to tmp_path (never into the repository)
        page.screenshot(path=str(tmp_path / "compare_not_shown.png"))
        print("page text:", page.evaluate("() => document.body.innerText")[:3000], "screenshot in", tmp_path)
        raise
    head = page.evaluate(COMPARE_JS).splitlines()[0]
    assert "run 1: m = 0.2 kg" in head and "run 2: m = 0 kg" in head, head
    one, two = both["run 1"], both["run 2"]
    # both runs start from the same K (the difference is carried onto run 1's start); the mass's own motion and
    # its inertia make their energies differ
    assert one["|K|"] == pytest.approx(two["|K|"], rel=1e-5) and one["E"] != two["E"], both

    def legends():
        names = [s for ch in shown_charts(page) for s in ch["series"]]
        ok = any("m = 0.2 kg" in s for s in names) and any("m = 0 kg" in s for s in names)
        return names if ok else None

    names = wait_until(page, legends, "the legends naming both runs")
    titles = [ch["title"] for ch in shown_charts(page)]
    assert sum("both runs" in t for t in titles) == 3, titles  # theta, |K| and E of both
    assert not any(t == "nutation angle theta" for t in titles), titles  # the single run's chart is hidden
    assert len([s for s in names if "m = 0 kg" in s]) == 3
    legend_line = "orange body: the same scene with m = 0 kg"  # the Legend window over the scene names it too
    wait_until(page, lambda: legend_line in page.evaluate("() => document.body.innerText"), "the legend's line")

    set_slider(page, "chi (1/s)", 8.0)  # an edit reaches both runs; the difference stays
    wait_until(page, lambda: "run 2: m = 0 kg" in page.evaluate(COMPARE_JS)
               and "chi (1/s)" in page.evaluate("() => document.body.innerText"), "the edit applied")
    after = wait_until(page, lambda: runs(page) if len(runs(page)) == 2 else None, "both readouts after the edit")
    assert after["run 2"]["|K|"] == pytest.approx(two["|K|"], rel=1e-5)  # the shown digits: K kept
    assert after["run 1"]["|K|"] == pytest.approx(one["|K|"], rel=1e-5)

    choose(page, "compare with", "off")
    wait_until(page, lambda: page.evaluate(COMPARE_JS) == "", "the second readout gone", timeout_ms=UI_TIMEOUT)

    def without_second_body():
        text = page.evaluate("() => document.body.innerText")
        return text if "orange body" not in text else None

    text = wait_until(page, without_second_body, "the legend's line gone")
    assert "run 2:" not in text
    titles = wait_until(page, lambda: [ch["title"] for ch in shown_charts(page)]
                        if "nutation angle theta" in [ch["title"] for ch in shown_charts(page)] else None,
                        "the single run's charts back")
    assert not any("both runs" in t for t in titles), titles
