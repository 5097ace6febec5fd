"""In a real browser: an edit keeps the angular momentum K the page shows, and the page says what it did to E
(issue 13 point 1). Debian's chromium via Playwright, as tests/test_app_browser.py (whose helpers it uses).

The issue's sequence on the default scene, typed in m's number box: m 0.2 -> 0 -> 0.2 with the state kept
took |K| from 3.50 to 0.40 kg m^2/s before. Paused first, so the readouts before and after are comparable.
"""

from __future__ import annotations

import re

import pytest
from test_app_browser import browser, choose, open_page, paused_t, read, readouts, set_slider, url, wait_until

pytestmark = pytest.mark.browser
__all__ = ["browser", "url"]  # module fixtures of tests/test_app_browser.py, started here for this module
M_LABEL = "m (kg)"
LABEL = "E changed by the edit"


@pytest.fixture(scope="module")
def page(browser, url):
    pg = open_page(browser, url)
    yield pg
    pg.close()


def number(text: str) -> float:
    m = re.match(r"\s*([-+]?[0-9.]+(?:e[-+]?\d+)?)", text)
    assert m, text
    return float(m.group(1))


def paused(page) -> None:
    page.get_by_role("button", name="Pause", exact=True).click()
    paused_t(page)  # t holds on the page: its last update can land a frame after the click


def edit_line_after(page, key_value: tuple[str, float], previous: str | None) -> str:
    """Type a value in a slider's number box; return the new "E changed by the edit" readout."""
    set_slider(page, *key_value)

    def changed():
        line = re.search(rf"(?m)^{re.escape(LABEL)} = (.*)$", readouts(page))
        return line.group(1) if line and line.group(0) != previous else None

    return wait_until(page, changed, f"the page to report the edit {key_value}")


def test_mass_off_and_on_keeps_K_in_the_page(page, capsys):
    page.wait_for_timeout(1500)  # let the default scene play a little: the mass is displaced and moving
    paused(page)
    t0, K0, E0 = read(page, "t"), read(page, "|K|"), number(read(page, "E"))
    theta0 = read(page, "theta")  # K's angle to the body axis: K and the attitude kept, so it is kept too
    assert LABEL not in readouts(page)
    line_off = edit_line_after(page, (M_LABEL, 0.0), None)
    K1, E1 = read(page, "|K|"), number(read(page, "E"))
    assert read(page, "t") == t0  # the run went on from where it was: no restart
    assert K1 == K0  # kept to 1e-12: the 6 digits shown are the same
    assert number(line_off) == pytest.approx(E1 - E0, rel=1e-2, abs=2e-5 * max(abs(E0), abs(E1)))
    line_on = edit_line_after(page, (M_LABEL, 0.2), f"{LABEL} = {line_off}")
    K2, E2 = read(page, "|K|"), number(read(page, "E"))
    assert read(page, "t") == t0
    assert K2 == K0
    assert number(line_on) == pytest.approx(E2 - E1, rel=1e-2, abs=2e-5 * max(abs(E1), abs(E2)))
    line_half = edit_line_after(page, (M_LABEL, 0.1), f"{LABEL} = {line_on}")  # m 0.2 -> 0.1: 3.58 -> 3.30 before
    K3 = read(page, "|K|")
    assert read(page, "t") == t0 and K3 == K0 and read(page, "theta") == theta0
    with capsys.disabled():
        print(f"\n[page] t = {t0}: |K| {K0} -> m = 0: {K1} -> m = 0.2: {K2} -> m = 0.1: {K3}; "
              f"E {E0} -> {E1} -> {E2}; lines: '{line_off}', '{line_on}', '{line_half}'")


def test_a_fidelity_change_and_an_inertia_change_keep_K_in_the_page(page, capsys):
    t0, K0 = read(page, "t"), read(page, "|K|")
    choose(page, "Fidelity", "averaged")
    wait_until(page, lambda: read(page, "fidelity").startswith("averaged"), "the averaged model")
    assert read(page, "t") == t0
    K1 = read(page, "|K|")
    assert K1 == K0
    fidelity_line = read(page, LABEL)  # the averaged model has no mass energy of its own: E changes
    page.get_by_text("Body inertia", exact=True).click()  # the folder opens; its sliders start hidden
    page.wait_for_timeout(300)
    inertia_line = edit_line_after(page, ("A (kg m^2)", 1.2), f"{LABEL} = {fidelity_line}")
    K2 = read(page, "|K|")
    assert K2 == K0 and read(page, "t") == t0
    with capsys.disabled():
        print(f"\n[page] t = {t0}: full -> averaged: |K| {K0} -> {K1} ('{fidelity_line}'); "
              f"A 1 -> 1.2: |K| -> {K2} ('{inertia_line}')")
