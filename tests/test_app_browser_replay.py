"""A replay anyone can open (issue 16, point 3), in a real browser: ``python -m app record`` writes one HTML file
that chromium opens from a file:// URL with no server running and that fetches nothing, whose scene moves and
whose page names the scenario; and the page's "Download replay (HTML)" button hands the browser such a file.
"""

from __future__ import annotations

import io
import subprocess
import sys

import numpy as np
import pytest
from test_app_browser import ROOT, UI_TIMEOUT, browser, click, open_page, url, wait_until  # noqa: F401 (fixtures)

from app.replay.page import external_refs

pytestmark = pytest.mark.browser
Image = pytest.importorskip("PIL.Image")
SCENARIO = ROOT / "physics" / "data" / "default.toml"  # read only
LOCAL = ("file:", "data:", "blob:", "about:")
MOVED = 0.002  # fraction of the view's central pixels that must change in a second while the replay plays


def _centre(png: bytes) -> np.ndarray:
    """The central half of a screenshot (the body and its arrows), as an RGB array: the replay's box and the
    player's scrub bar lie outside it, so a difference here is the scene moving."""
    a = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)
    h, w, _ = a.shape
    return a[h // 4: 3 * h // 4, w // 4: 3 * w // 4]


def test_a_recorded_replay_plays_from_a_file_with_no_server_and_no_network(browser, tmp_path):  # noqa: F811
    out = tmp_path / "demo.html"
    done = subprocess.run([sys.executable, "-m", "app", "record", str(SCENARIO), "--seconds", "6", "--out", str(out)],
                          cwd=ROOT, capture_output=True, text=True, timeout=180)  # writes only --out
    assert done.returncode == 0, done.stderr
    assert f"wrote {out}" in done.stdout and "180 frames" in done.stdout, done.stdout  # 6 s at 30 frames/s
    html = out.read_text(encoding="utf-8")
    assert external_refs(html) == []  # the viser client is inline: nothing names a server
    pg = browser.new_page(viewport={"width": 1400, "height": 900})
    pg.set_default_timeout(UI_TIMEOUT)
    requests: list[str] = []
    pg.on("request", lambda r: requests.append(r.url))
    try:
        pg.goto(out.as_uri())
        pg.wait_for_selector("canvas")
        text = pg.evaluate("document.body.innerText")
        assert "Quasirigid replay: default.toml: Quasirigid's default scene" in text, text[:500]
        assert "6 s played at" in text, text[:500]
        pg.get_by_text("Scenario (TOML)").click()  # the scenario that made it, as text on the page
        wait_until(pg, lambda: "theta0 = 0.8" in pg.locator("pre.scenario").inner_text(), "the scenario's TOML")
        img = pg.locator("img[alt^='theta']")
        assert img.evaluate("i => i.complete && i.naturalWidth") > 100  # the plots' picture decoded
        pg.wait_for_timeout(1500)  # software WebGL: the first frames and the recording's start
        first = _centre(pg.screenshot())
        pg.wait_for_timeout(1000)
        second = _centre(pg.screenshot())
        changed = np.mean(np.any(np.abs(first - second) > 8, axis=2))
        assert changed > MOVED, f"only {changed:.4%} of the view's pixels changed in a second"
        fetched = [u for u in requests if not u.startswith(LOCAL)]
        assert fetched == [], fetched
        pg.screenshot(path=str(tmp_path / "replay.png"))
    finally:
        pg.close()


def test_the_export_button_downloads_a_replay_of_the_scene_and_says_where_it_went(browser, url, tmp_path):  # noqa: F811
    pg = open_page(browser, url)
    try:
        pg.get_by_text("File", exact=True).first.click()  # the folder opens
        with pg.expect_download(timeout=120_000) as dl:
            click(pg, "Download replay (HTML)")
        download = dl.value
        name = download.suggested_filename
        assert name.startswith("quasirigid-replay-default") and name.endswith(".html"), name
        saved = tmp_path / name
        download.save_as(saved)
        html = saved.read_text(encoding="utf-8")
        assert "Quasirigid replay: Default: oblate body settling" in html
        assert external_refs(html) == []
        said = wait_until(pg, lambda: next((line for line in pg.evaluate("document.body.innerText").splitlines()
                                            if line.startswith("Replay downloaded as")), None),
                          "the button's note on the page")
        assert name in said and "downloads folder" in said, said
    finally:
        pg.close()
