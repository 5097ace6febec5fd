"""Explorer rates, measured server-side: frames published per second at 1x and 1000x warp on the
default scene, and the latency from a slider change to the first published frame reflecting it.

Starts the app in-process on a free port, connects Debian's chromium (Playwright) so a session
exists, and reads the session's counters. Usage:
``python -m bench explorer-rates [seconds] [--out CSV] [--img PNG]`` (seconds per warp, default 10) prints a
small table and writes bench/results/explorer_rates.csv, bench/results/explorer_rates.meta.json (the command,
the date, the machine and versions, the load average before and after) and the chart
docs/img/explorer_rates.png. ``--chart-only`` redraws the chart from the CSV without measuring. ``--compare`` adds
the frame rates with compare mode's second body (app.engine.compare) and writes bench/results/explorer_rates_compare.csv
(+ .meta.json) and docs/img/explorer_rates_compare.png instead.
(``python bench/explorer_rates.py ...`` runs the same.)
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

ROOT = Path(__file__).resolve().parents[1]
if not __package__:  # run as a file (python bench/explorer_rates.py): its folder is on the path, not the project's
    sys.path.insert(0, str(ROOT))

from app.serve.server import App, warm_up  # noqa: E402
from bench.cli import bounded, study_parser  # noqa: E402
from bench.explorer_startup import save_chart  # noqa: E402
from bench.machine import machine  # noqa: E402

OUT = ROOT / "bench" / "results" / "explorer_rates.csv"
IMG = ROOT / "docs" / "img" / "explorer_rates.png"

COMPARE = ("mass.m", 0.0)  # --compare: the second body is the default scene without the mass
OUT_COMPARE = ROOT / "bench" / "results" / "explorer_rates_compare.csv"
IMG_COMPARE = ROOT / "docs" / "img" / "explorer_rates_compare.png"

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def measure(seconds: float = 10.0, out: Path = OUT, img: Path = IMG, command: str | None = None,
            compare: bool = False) -> None:
    """Measure, print, write the CSV and its metadata (``command`` recorded in it), draw the chart. With
    ``compare``, the same frame rates again with compare mode's second body (app.engine.compare: the default scene
    without the mass beside it), in the same run and on the same page."""
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
            if compare:
                rows += _compare_rows(session, eng, page, received, seconds)
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
    meta = dict(command=command or f"python -m bench explorer-rates {seconds:g}", seconds_per_warp=seconds,
                date=time.strftime("%Y-%m-%dT%H:%M:%S+00:00", time.gmtime()), machine=box,
                load1_before=round(load_before, 2), load1_after=round(os.getloadavg()[0], 2))
    meta_path(out).write_text(json.dumps(meta, indent=2) + "\n")
    print(f"wrote {out} and {meta_path(out).name}")
    chart(out, img)


def _compare_rows(session, eng, page, received: list, seconds: float) -> list[dict]:
    """Frames published and received per second, achieved warp and tick/publish ms with both bodies. Measured
    before the slider latency: the tick and publish percentile rows that follow read the session's last 600
    frames, in such a run mostly these two-body frames at 1000x."""
    rows = []
    eng.request("compare", COMPARE)
    page.wait_for_timeout(1000)
    if eng.compare is None:
        raise RuntimeError(f"compare mode did not turn on: {eng.error}")
    for warp in (1.0, 1000.0):
        eng.request("warp", warp)
        page.wait_for_timeout(1000)
        session.frame_ms.clear()
        f0, r0, t0, s0 = session.published, received[0], time.perf_counter(), eng.run.t
        page.wait_for_timeout(int(seconds * 1000))
        dt = time.perf_counter() - t0
        both = f"at {warp:g}x, two bodies"
        rows.append(dict(quantity=f"frames published per s {both}", value=round((session.published - f0) / dt, 1)))
        rows.append(dict(quantity=f"websocket messages received per s {both}",
                         value=round((received[0] - r0) / dt, 1)))
        rows.append(dict(quantity=f"achieved warp {both}", value=round((eng.run.t - s0) / dt, 1)))
        ms = sorted(m[0] + m[1] for m in session.frame_ms)
        rows.append(dict(quantity=f"frame (tick + publish) ms {both}, median", value=round(ms[len(ms) // 2], 2)))
    eng.request("compare", None)
    page.wait_for_timeout(500)
    return rows


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


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """``python -m bench explorer-rates [seconds] [--out CSV] [--img PNG] [--chart-only]``."""
    argv = sys.argv[1:] if argv is None else list(argv)
    ap = study_parser("explorer-rates", __doc__, prog)
    ap.add_argument("seconds", nargs="?", type=bounded(float, 0.5, 3600.0), default=10.0,
                    help="seconds measured at each warp (default 10)")
    ap.add_argument("--out", type=Path, default=OUT, help=f"the CSV (default {OUT.relative_to(ROOT)})")
    ap.add_argument("--img", type=Path, default=IMG, help=f"the chart (default {IMG.relative_to(ROOT)})")
    ap.add_argument("--chart-only", action="store_true", help="redraw the chart from the CSV; measure nothing")
    ap.add_argument("--compare", action="store_true",
                    help="also measure with compare mode's second body (the default scene without the mass); "
                         f"default outputs {OUT_COMPARE.relative_to(ROOT)} and {IMG_COMPARE.relative_to(ROOT)}")
    a = ap.parse_args(argv)
    if a.compare:  # its own files: the single-body figures quoted in docs/performance.md stay as they were measured
        a.out = OUT_COMPARE if a.out == OUT else a.out
        a.img = IMG_COMPARE if a.img == IMG else a.img
    if a.chart_only:
        chart(a.out, a.img)
    else:
        measure(a.seconds, a.out, a.img, command=" ".join([ap.prog, *argv]), compare=a.compare)
    return 0


if __name__ == "__main__":  # the older way to run it, kept working: python bench/explorer_rates.py ...
    raise SystemExit(main(sys.argv[1:], prog="python bench/explorer_rates.py"))
