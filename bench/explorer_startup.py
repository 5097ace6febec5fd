"""Time from ``python -m app`` to the explorer's scene drawn in a browser, with warm caches (numba's
cache compiled, the OS's file cache filled by a first launch that is not counted).

Each repetition launches ``python -m app --port 0`` and opens the URL in Debian's chromium
(Playwright) as soon as the server prints it: the server starts before the physics loads, so the
page loads meanwhile. The clock stops when the tab shows its first readouts (the panel is filled by
the session's first published frames, after the scene's meshes are sent). Usage:
``python bench/explorer_startup.py [repetitions] [--compare-env-map]``; prints a table and writes
bench/results/explorer_startup.csv. ``--compare-env-map`` alternates each launch with one that keeps viser's
default environment map (which the explorer turns off: software WebGL stalls 4-6 s on it in about half
the page loads) and prints both columns, measured in the same run.
"""

from __future__ import annotations

import csv
import re
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

from playwright.sync_api import sync_playwright

ROOT = Path(__file__).resolve().parents[1]
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run"]
# python -m app with viser's default environment map kept: the explorer's call that turns it off does nothing
WITH_ENV_MAP = ("import sys, viser._scene_api as s; f = s.SceneApi.configure_environment_map; "
                "s.SceneApi.configure_environment_map = "
                "lambda self, hdri='warehouse', **k: f(self, hdri or 'warehouse', **k); "
                "from app.__main__ import main; sys.exit(main(sys.argv[1:]))")
READOUTS = "() => Array.from(document.querySelectorAll('p')).some(p => p.innerText.includes('fidelity = '))"


def launch_once(browser, after_ready: bool = False, env_map: bool = False) -> dict:
    t0 = time.perf_counter()
    cmd = [sys.executable, "-u", *(["-c", WITH_ENV_MAP] if env_map else ["-m", "app"]), "--port", "0"]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    times: dict = {}

    def watch():  # the "ready" line arrives while the browser is already loading the page
        for line in proc.stdout:
            if "ready in" in line:
                times["ready_s"] = time.perf_counter() - t0

    try:
        url = None
        for line in proc.stdout:
            m = re.search(r"serving (http://\S+);", line)
            if m:
                url, times["serving_s"] = m.group(1), time.perf_counter() - t0
                break
        if url is None:
            raise RuntimeError("the explorer did not start")
        threading.Thread(target=watch, daemon=True).start()
        while after_ready and "ready_s" not in times and proc.poll() is None:
            time.sleep(0.01)
        page = browser.new_page(viewport={"width": 1400, "height": 900})
        page.goto(url)  # as a user would: open the URL as soon as it is printed
        page.wait_for_selector("canvas", timeout=60_000)
        times["canvas_s"] = time.perf_counter() - t0
        page.wait_for_function(READOUTS, polling=20, timeout=60_000)
        times["scene_drawn_s"] = time.perf_counter() - t0
        page.close()
        return {k: times.get(k, float("nan")) for k in ("serving_s", "ready_s", "canvas_s", "scene_drawn_s")}
    finally:
        proc.terminate()
        proc.wait(timeout=10)


def main(repetitions: int = 5, compare_env_map: bool = False) -> None:
    rows = []
    variants = [False, True] if compare_env_map else [False]
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=FLAGS)
        launch_once(browser)  # warm-up: numba's cache, the OS file cache, chromium's own start
        for i in range(repetitions):
            for env_map in variants:  # interleaved, so both see the same load
                times = launch_once(browser, env_map=env_map)
                rows.append(dict(run=i + 1, env_map=env_map, **{k: round(v, 3) for k, v in times.items()}))
                print(rows[-1], flush=True)
        browser.close()
    for env_map in variants:
        if compare_env_map:
            print("with viser's default environment map" if env_map else "as shipped (no environment map)")
        for key in ("serving_s", "ready_s", "canvas_s", "scene_drawn_s"):
            values = [r[key] for r in rows if r["env_map"] == env_map]
            over = sum(v > 5.0 for v in values) if key == "scene_drawn_s" else None
            print(f"  {key:<15} median {statistics.median(values):.2f} s, max {max(values):.2f} s"
                  + (f", {over} of {len(values)} over 5 s" if over is not None else ""))
    out = ROOT / "bench" / "results" / "explorer_startup.csv"
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {out}")


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    main(int(args[0]) if args else 5, compare_env_map="--compare-env-map" in sys.argv)
