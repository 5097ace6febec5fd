"""Explorer rates, measured server-side: frames published per second at 1x and 1000x warp on the
default scene, and the latency from a slider change to the first published frame reflecting it.

Starts the app in-process on a free port, connects Debian's chromium (Playwright) so a session
exists, and reads the session's counters. Usage:
``python bench/explorer_rates.py [seconds] [--out CSV] [--img PNG]`` (seconds per warp, default 10) prints a
small table and writes bench/results/explorer_rates.csv, bench/results/explorer_rates.meta.json (the command,
the date, the machine and versions, the load average before and after) and the chart
docs/img/explorer_rates.png. ``--chart-only`` redraws the chart from the CSV without measuring.
"""

from __future__ import annotations

import csv
import json
import os
import statistics
import sys
import time
from pathlib import Path

from playwright.sync_api import sync_playwright

from app.server import App, warm_up
from bench.explorer_startup import machine, save_chart

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "bench" / "results" / "explorer_rates.csv"
IMG = ROOT / "docs" / "img" / "explorer_rates.png"

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def main(seconds: float = 10.0, out: Path = OUT, img: Path = IMG) -> None:
    load_before = os.getloadavg()[0]
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
    box = machine()
    print(f"# {box['cpu']}, {box['cores']} cores, Python {box['python']}, numpy {box['numpy']}, numba {box['numba']}")
    for r in rows:
        print(f"{r['quantity']:<50} {r['value']}")
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["quantity", "value"])
        w.writeheader()
        w.writerows(rows)
    meta = dict(command=f"python bench/explorer_rates.py {seconds:g}", seconds_per_warp=seconds,
                date=time.strftime("%Y-%m-%dT%H:%M:%S+00:00", time.gmtime()), machine=box,
                load1_before=round(load_before, 2), load1_after=round(os.getloadavg()[0], 2))
    meta_path(out).write_text(json.dumps(meta, indent=2) + "\n")
    print(f"wrote {out} and {meta_path(out).name}")
    chart(out, img)


def meta_path(out: Path) -> Path:
    return out.with_name(out.stem + ".meta.json")


def chart(out: Path = OUT, img: Path = IMG) -> None:
    """The CSV as two bar charts: rates per second at each warp, and times in ms; the machine in the title."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with out.open(newline="") as f:
        rows = {r["quantity"]: float(r["value"]) for r in csv.DictReader(f)}
    rates = {k: v for k, v in rows.items() if " per s at " in k}
    times = {k: v for k, v in rows.items() if " ms" in k}
    fig, (a, b) = plt.subplots(1, 2, figsize=(9.5, 3.6), layout="constrained")
    a.barh(list(rates), list(rates.values()), color="C0")
    a.set_xlabel("per second")
    b.barh(list(times), list(times.values()), color="C1")
    b.set_xlabel("milliseconds")
    for ax, vals in ((a, rates), (b, times)):
        ax.invert_yaxis()
        ax.tick_params(axis="y", labelsize=7)
        for y, v in enumerate(vals.values()):
            ax.text(v, y, f" {v:g}", va="center", fontsize=7)
    where = out.relative_to(ROOT) if out.is_relative_to(ROOT) else out
    title = f"Explorer rates, default scene ({where})"
    m = json.loads(meta_path(out).read_text()) if meta_path(out).exists() else {}
    box = m.get("machine")
    if box:
        title += (f"\n{box['cpu']}, {box['cores']} cores, Python {box['python']}, "
                  f"load average {m['load1_before']:g}-{m['load1_after']:g}, {m['date'][:10]}")
    else:  # a CSV measured before the script recorded the machine: say so rather than guess it
        title += "\nmachine and load not recorded by that run"
    fig.suptitle(title, fontsize=9)
    save_chart(fig, img)


def parse(argv: list[str]):
    import argparse

    ap = argparse.ArgumentParser(prog="python bench/explorer_rates.py", description=__doc__.split("\n")[0])
    ap.add_argument("seconds", nargs="?", type=float, default=10.0, help="seconds measured at each warp (default 10)")
    ap.add_argument("--out", type=Path, default=OUT, help=f"the CSV (default {OUT.relative_to(ROOT)})")
    ap.add_argument("--img", type=Path, default=IMG, help=f"the chart (default {IMG.relative_to(ROOT)})")
    ap.add_argument("--chart-only", action="store_true", help="redraw the chart from the CSV; measure nothing")
    return ap.parse_args(argv)


if __name__ == "__main__":
    a = parse(sys.argv[1:])
    if a.chart_only:
        chart(a.out, a.img)
    else:
        main(a.seconds, a.out, a.img)
