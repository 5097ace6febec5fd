"""The first start on a machine (issue 13 point 9), in Debian's chromium: with the compiled kernels not yet
built (QUASIRIGID_BUILD_GATE holds the background build back), the page shows a moving scene and says it is
preparing the fast integrator; once the build is let through, the notice goes and the scene keeps moving."""

from __future__ import annotations

import os
import re
import signal

import pytest
from explorer_process import Explorer
from test_app_browser import launch, read, sync_api

pytestmark = pytest.mark.browser
PREPARING = "preparing the fast integrator"
STATUS_JS = """() => { for (const p of document.querySelectorAll('p'))
    if (p.innerText.startsWith('Quasirigid explorer')) return p.innerText; return ''; }"""
BUILD_TIMEOUT = 600.0  # s: on a machine whose numba cache is cold the released build really compiles


def _sim_time(page) -> float:
    return float(read(page, "t").split()[0])


def test_the_scene_runs_while_the_integrator_is_built_and_after(tmp_path):
    gate = tmp_path / "gate"
    explorer = Explorer(env=dict(os.environ, QUASIRIGID_BUILD_GATE=str(gate)), own_group=True)
    url = explorer.url
    try:
        with sync_api.sync_playwright() as p:
            browser = launch(p)
            page = browser.new_page(viewport={"width": 1400, "height": 900})
            page.set_default_timeout(60_000)
            page.goto(url)
            page.wait_for_function(f"() => ({STATUS_JS})().includes('{PREPARING}')", polling=100)
            page.wait_for_function("() => document.body.innerText.includes('fidelity = ')", polling=100)
            t0 = _sim_time(page)
            page.wait_for_function(f"() => {{ const m = document.body.innerText.match(/^t = ([-0-9.e+]+) s/m);"
                                   f" return m && parseFloat(m[1]) > {t0}; }}", polling=100)
            status = page.evaluate(STATUS_JS)
            assert PREPARING in status and "playing" in status, status
            assert re.search(rf"{PREPARING}: \d+ s", status), status  # it counts the seconds
            page.screenshot(path=str(tmp_path / "preparing.png"))

            gate.write_text("built")  # the background build may now finish
            page.wait_for_function(f"() => !({STATUS_JS})().includes('{PREPARING}')", polling=200,
                                   timeout=BUILD_TIMEOUT * 1000)
            t1 = _sim_time(page)
            page.wait_for_function(f"() => {{ const m = document.body.innerText.match(/^t = ([-0-9.e+]+) s/m);"
                                   f" return m && parseFloat(m[1]) > {t1}; }}", polling=100)
            status = page.evaluate(STATUS_JS)
            assert "playing" in status and "fault" not in status, status
            browser.close()
    finally:
        code = explorer.stop(signal.SIGTERM)
    # the explorer ran until it was told to stop: ended by the signal, not by an exit of its own (a crash exits 1)
    assert code == -signal.SIGTERM
