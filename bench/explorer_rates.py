"""Explorer rates, measured server-side: frames published per second at 1x and 1000x warp on the
default scene, and the latency from a slider change to the first published frame reflecting it.

Starts the app in-process on a free port, connects Debian's chromium (Playwright) so a session
exists, and reads the session's counters. Usage: python bench/explorer_rates.py [seconds]
Prints a small table and writes bench/explorer_rates.csv.
"""

from __future__ import annotations

import csv
import platform
import statistics
import sys
import time
from pathlib import Path

from playwright.sync_api import sync_playwright

from app.server import App, warm_up

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def main(seconds: float = 10.0) -> None:
    warm_up()
    app = App(port=0)
    rows = []
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=FLAGS)
            page = browser.new_page(viewport={"width": 1400, "height": 900})
            received = [0]
            page.on("websocket", lambda ws: ws.on("framereceived", lambda _f: received.__setitem__(0, received[0] + 1)))
            page.goto(f"http://127.0.0.1:{app.port}")
            page.wait_for_selector("canvas", timeout=60_000)
            while not app.sessions:
                page.wait_for_timeout(100)
            session = next(iter(app.sessions.values()))
            eng = session.engine
            for warp in (1.0, 1000.0):
                eng.request("warp", warp)
                page.wait_for_timeout(1000)
                f0, r0, t0, s0, w0 = session.published, received[0], time.perf_counter(), eng.run.t, eng.wall_total
                page.wait_for_timeout(int(seconds * 1000))
                dt = time.perf_counter() - t0
                fps = (session.published - f0) / dt
                rows.append(dict(quantity=f"frames published per s at {warp:g}x", value=round(fps, 1)))
                rows.append(dict(quantity=f"websocket messages received per s at {warp:g}x",
                                 value=round((received[0] - r0) / dt, 1)))
                rows.append(dict(quantity=f"achieved warp at {warp:g}x", value=round((eng.run.t - s0) / dt, 1)))
                rows.append(dict(quantity=f"integration wall fraction at {warp:g}x",
                                 value=round((eng.wall_total - w0) / dt, 3)))
            eng.request("warp", 1.0)
            lat = []
            for i in range(20):
                seq = eng.request_value("mass.chi", 8.0 + (i % 2))
                while seq not in session.first_frame_after:
                    page.wait_for_timeout(5)
                lat.append(session.first_frame_after[seq] * 1000)
                page.wait_for_timeout(100)
            ms = list(session.frame_ms)
            for i, what in enumerate(("tick (apply + integrate)", "publish")):
                vals = sorted(m[i] for m in ms)
                rows.append(dict(quantity=f"{what} ms, median", value=round(vals[len(vals) // 2], 2)))
                rows.append(dict(quantity=f"{what} ms, 99th percentile", value=round(vals[int(0.99 * len(vals))], 2)))
            rows.append(dict(quantity="slider change -> first frame, median ms",
                             value=round(statistics.median(lat), 1)))
            rows.append(dict(quantity="slider change -> first frame, max ms", value=round(max(lat), 1)))
            browser.close()
    finally:
        app.close()
    print(f"# {platform.node()} {platform.processor() or platform.machine()}, python {platform.python_version()}")
    for r in rows:
        print(f"{r['quantity']:<50} {r['value']}")
    out = Path(__file__).with_suffix(".csv")
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["quantity", "value"])
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 10.0)
