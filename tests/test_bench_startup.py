"""``bench/explorer_startup.py --cold`` runs end to end on one launch of each kind (issue 13 point 9), so the
first-start benchmark cannot rot: its CSV holds cold and warm rows with the times and the machine."""

from __future__ import annotations

import csv
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("playwright.sync_api")
pytest.importorskip("matplotlib")
if not os.path.exists("/usr/bin/chromium"):
    pytest.skip("Debian's chromium is not installed (apt-get install -y chromium)", allow_module_level=True)

pytestmark = [pytest.mark.slow, pytest.mark.browser]
ROOT = Path(__file__).resolve().parent.parent


def test_cold_mode_writes_cold_and_warm_rows(tmp_path):
    out, img = tmp_path / "startup_cold.csv", tmp_path / "startup_cold.png"
    # --fast-timeout 1: do not wait for the cold launch's background build (its column may then be nan)
    done = subprocess.run([sys.executable, "bench/explorer_startup.py", "--cold", "1", "--out", str(out),
                           "--img", str(img), "--fast-timeout", "1"], cwd=ROOT, capture_output=True, text=True,
                          timeout=900)
    assert done.returncode == 0, done.stdout + done.stderr
    with out.open() as fh:
        rows = list(csv.DictReader(fh))
    assert [r["cache"] for r in rows] == ["cold", "warm"]
    for r in rows:
        drawn, moving = float(r["scene_drawn_s"]), float(r["moving_s"])
        assert 0 < float(r["serving_s"]) < drawn <= moving and math.isfinite(moving)
        assert r["cpu"] and int(r["cores"]) >= 1 and r["numba"] and r["numpy"] and r["python"]
        # the machine's 1-minute load average as the launch ran, as the bench writes it (os.getloadavg, 2 decimals):
        # a missing reading written as nan or inf, or an unrounded one, fails here
        load1 = float(r["load1"])
        assert math.isfinite(load1) and load1 >= 0 and load1 == round(load1, 2), r["load1"]
    # the cold launch's page said it was preparing the fast integrator (its kernels were not built); the warm did not
    assert [r["preparing_shown"] for r in rows] == ["1.0", "0.0"]
    assert "cold/warm ratio" in done.stdout
    assert img.stat().st_size > 10_000
