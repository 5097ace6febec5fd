"""Time from ``python -m app`` to the explorer's scene drawn in a browser, with warm caches (numba's
cache compiled, the OS's file cache filled by a first launch that is not counted).

Each repetition launches ``python -m app --port 0`` and opens the URL in Debian's chromium
(Playwright) as soon as the server prints it: the server starts before the physics loads, so the
page loads meanwhile. The clock stops when the tab shows its first readouts (the panel is filled by
the session's first published frames, after the scene's meshes are sent). Usage:
``python -m bench explorer-startup [repetitions] [--compare-env-map]``; prints a table and writes
bench/results/explorer_startup.csv. (``python bench/explorer_startup.py ...`` runs the same.)

``python -m bench explorer-startup --cold [repetitions] [--out CSV] [--img PNG] [--fast-timeout S]``
measures the first start on a machine: launches with an empty numba cache (each its own new
NUMBA_CACHE_DIR, so the developer's cache is left alone) interleaved with launches on a warm one, each
until the scene moves (the readouts' t passes 0) and until the status line stops saying it prepares the
fast integrator; prints the medians and the cold/warm ratio, writes bench/results/explorer_startup_cold.csv
(with the machine and the load average at each launch) and docs/img/explorer_startup_cold.png.

``--compare-env-map`` alternates each launch with one that keeps viser's
default environment map (which the explorer turns off: software WebGL stalls 4-6 s on it in about half
the page loads) and prints both columns, measured in the same run.
"""

from __future__ import annotations

import csv
import math
import os
import re
import signal
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

from playwright.sync_api import TimeoutError as PlaywrightTimeout
from playwright.sync_api import sync_playwright

ROOT = Path(__file__).resolve().parents[1]
if not __package__:  # run as a file (python bench/explorer_startup.py): its folder is on the path, not the project's
    sys.path.insert(0, str(ROOT))

from bench.cli import bounded, study_parser  # noqa: E402
from bench.machine import machine  # noqa: E402

# the machine's columns in each row of the --cold CSV: the ones its earlier files have (bench.machine has more)
ROW_MACHINE = ("cpu", "cores", "python", "numpy", "numba")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run"]
# python -m app with viser's default environment map kept: the explorer's call that turns it off does nothing
WITH_ENV_MAP = ("import sys, viser._scene_api as s; f = s.SceneApi.configure_environment_map; "
                "s.SceneApi.configure_environment_map = "
                "lambda self, hdri='warehouse', **k: f(self, hdri or 'warehouse', **k); "
                "from app.__main__ import main; sys.exit(main(sys.argv[1:]))")
READOUTS = "() => Array.from(document.querySelectorAll('p')).some(p => p.innerText.includes('fidelity = '))"
# the scene moves: the readouts show a simulated time past the first published one (t > 0)
MOVING = ("() => Array.from(document.querySelectorAll('p')).some(p => {"
          " const m = p.innerText.match(/^t = ([-0-9.e+]+) s/m); return m && parseFloat(m[1]) > 0; })")
# the status line has said it is preparing the fast integrator, and no longer does
PREPARING = "() => document.body.innerText.includes('preparing the fast integrator')"


def launch_once(browser, after_ready: bool = False, env_map: bool = False, env: dict | None = None,
                moving: bool = False, fast_timeout: float = 0.0, page_timeout: float = 60.0) -> dict:
    """One launch; ``env`` for the server (the cold mode's NUMBA_CACHE_DIR). With ``moving``, also wait for
    the scene to move, then (``fast_timeout`` seconds at most) for the status line to stop saying it prepares
    the fast integrator. A cold launch that shows no moving scene within ``page_timeout`` s is recorded as nan."""
    t0 = time.perf_counter()
    cmd = [sys.executable, "-u", *(["-c", WITH_ENV_MAP] if env_map else ["-m", "app"]), "--port", "0"]
    # a session of its own: stopping it stops the background build of the compiled kernels too
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=env, start_new_session=True)
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
        try:
            page.wait_for_function(READOUTS, polling=20, timeout=page_timeout * 1000)
            times["scene_drawn_s"] = time.perf_counter() - t0
            if moving:
                page.wait_for_function(MOVING, polling=20, timeout=page_timeout * 1000)
                times["moving_s"] = time.perf_counter() - t0
        except PlaywrightTimeout:
            if not moving:
                raise
            print(f"  no moving scene within {page_timeout:g} s (recorded as nan)", flush=True)
            page.close()
            return {k: times.get(k, float("nan")) for k in ("serving_s", "ready_s", "canvas_s", "scene_drawn_s",
                                                            "moving_s", "preparing_shown", "fast_integrator_s")}
        if moving:
            # "preparing" shows only while the build runs: read once, then wait for it to go
            times["preparing_shown"] = bool(page.evaluate(PREPARING))
            try:
                page.wait_for_function(f"() => !({PREPARING})()", polling=100, timeout=fast_timeout * 1000)
                times["fast_integrator_s"] = time.perf_counter() - t0
            except PlaywrightTimeout:
                pass
        page.close()
        keys = ["serving_s", "ready_s", "canvas_s", "scene_drawn_s"]
        if moving:
            keys += ["moving_s", "preparing_shown", "fast_integrator_s"]
        return {k: times.get(k, float("nan")) for k in keys}
    finally:
        try:
            os.killpg(proc.pid, signal.SIGTERM)  # the server and its build, if one still runs
        except ProcessLookupError:
            pass
        proc.wait(timeout=10)


def warm_main(repetitions: int = 5, compare_env_map: bool = False) -> None:
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


def cold_main(repetitions: int = 3, out: Path | None = None, img: Path | None = None,
              fast_timeout: float = 300.0, inline: bool = False) -> dict:
    """Cold and warm launches, interleaved, measured in one run. A cold launch gets an empty numba cache of
    its own (NUMBA_CACHE_DIR pointing at a new temporary directory: the developer's cache is left alone), a
    warm one a cache filled before the first launch. Returns the medians and the cold/warm ratio of the time
    to a moving scene; writes the rows (with the machine and the load average at each launch) as CSV and a
    chart. ``inline`` adds launches with an empty cache and no background build (QUASIRIGID_BUILD=inline: the
    first call compiles in the server, as before the build moved to a child process), for comparison."""
    import tempfile

    out = out or ROOT / "bench" / "results" / "explorer_startup_cold.csv"
    img = img or ROOT / "docs" / "img" / "explorer_startup_cold.png"
    rows, box = [], machine()
    with tempfile.TemporaryDirectory(prefix="quasirigid-numba-") as tmp, sync_playwright() as p:
        warm_env = dict(os.environ, NUMBA_CACHE_DIR=str(Path(tmp) / "warm"))
        # fill the warm cache as the explorer's own build does (and write its "built" stamp), at full priority
        subprocess.run([sys.executable, "-c", "from physics.stepping.warm import build_here; build_here()"],
                       cwd=ROOT, env=warm_env, check=True)
        browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=FLAGS)
        launch_once(browser, env=warm_env, moving=True)  # uncounted: the OS file cache, chromium
        for i in range(repetitions):
            for kind in ("cold", "warm", "cold-inline")[:3 if inline else 2]:  # interleaved: the same load
                env = warm_env if kind == "warm" else dict(os.environ, NUMBA_CACHE_DIR=str(Path(tmp) / f"{kind}{i}"))
                if kind == "cold-inline":
                    env["QUASIRIGID_BUILD"] = "inline"
                load = os.getloadavg()[0]
                times = launch_once(browser, env=env, moving=True, fast_timeout=fast_timeout, page_timeout=240.0)
                rows.append(dict(run=i + 1, cache=kind, **{k: round(float(v), 3) for k, v in times.items()},
                                 load1=round(load, 2), **{k: box[k] for k in ROW_MACHINE}))
                print({k: rows[-1][k] for k in ("run", "cache", "scene_drawn_s", "moving_s", "fast_integrator_s",
                                                 "load1")}, flush=True)
        browser.close()
    kinds = list(dict.fromkeys(r["cache"] for r in rows))
    summary = {kind: _median(r["moving_s"] for r in rows if r["cache"] == kind) for kind in kinds}
    summary["ratio"] = summary["cold"] / summary["warm"]
    fast = [r["fast_integrator_s"] for r in rows if r["cache"] == "cold"]
    print(f"machine: {box['cpu']}, {box['cores']} cores, Python {box['python']}, numpy {box['numpy']}, "
          f"numba {box['numba']}; load average {min(r['load1'] for r in rows):.2f}-{max(r['load1'] for r in rows):.2f}")
    for kind in kinds:
        sel = [r for r in rows if r["cache"] == kind]
        print(f"  {kind}: to a moving scene median {summary[kind]:.2f} s (max {max(r['moving_s'] for r in sel):.2f});"
              f" readouts {_median(r['scene_drawn_s'] for r in sel):.2f} s; 'ready' printed "
              f"{_median(r['ready_s'] for r in sel):.2f} s")
    if inline:
        print(f"  cold-inline/warm ratio {summary['cold-inline'] / summary['warm']:.2f} (compiling in the server)")
    print(f"  cold/warm ratio {summary['ratio']:.2f} (goal: at most 2.5); compiled integrator in use after "
          f"{_median(fast):.1f} s (cold, median; inf: not within {fast_timeout:g} s)")
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {out}")
    chart(rows, summary, img)
    return summary


def _median(values) -> float:
    """Median, a launch that never got there (nan) counting as later than any other."""
    return statistics.median([v if v == v else math.inf for v in values])


def chart(rows: list[dict], summary: dict, img: Path) -> None:
    """Each launch's times to the readouts, to a moving scene and to the compiled integrator, cold vs warm."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 3.6), layout="constrained")
    marks = {"scene_drawn_s": ("readouts shown", "o"), "moving_s": ("scene moving", "s"),
             "fast_integrator_s": ("compiled integrator in use", "^")}
    kinds = [k for k in ("warm", "cold", "cold-inline") if k in summary]
    names = {"warm": "warm cache", "cold": "empty cache", "cold-inline": "empty cache,\nno background build"}
    for y, kind in enumerate(kinds):
        sel = [r for r in rows if r["cache"] == kind]
        for j, (key, (label, marker)) in enumerate(marks.items()):
            xs = [r[key] for r in sel if r[key] == r[key]]
            ax.scatter(xs, [y + 0.12 * (j - 1)] * len(xs), marker=marker, color=f"C{j}",
                       label=label if y == 1 else None)
        if math.isfinite(summary[kind]):
            ax.plot([summary[kind]] * 2, [y - 0.3, y + 0.3], color="k", lw=1)
    ax.axvline(2.5 * summary["warm"], color="C3", ls="--", lw=1, label="goal: 2.5 x warm (moving)")
    ax.set_yticks(range(len(kinds)), [names[k] for k in kinds])
    ax.set_ylim(-0.5, len(kinds) - 0.5)
    ax.set_xlabel("seconds from `python -m app` (black bars: medians to a moving scene)")
    loads = [r["load1"] for r in rows]
    ax.set_title(f"First start: cold/warm = {summary['ratio']:.2f} ({rows[0]['cpu']}, {rows[0]['cores']} cores, "
                 f"load average {min(loads):.0f}-{max(loads):.0f})", fontsize=10)
    ax.legend(loc="lower right", fontsize=8)
    save_chart(fig, img)


def save_chart(fig, img: Path) -> None:
    """Write an explorer benchmark's chart (both explorer benchmarks draw theirs the same way) and close it."""
    import matplotlib.pyplot as plt

    img.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(img, dpi=110)
    plt.close(fig)
    print(f"wrote {img}")


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """``python -m bench explorer-startup [repetitions] [--compare-env-map]`` or ``... --cold [options]``."""
    ap = study_parser("explorer-startup", __doc__, prog)
    ap.add_argument("repetitions", nargs="?", type=bounded(int, 1, 100),
                    help="launches of each kind (default 5; --cold: 3)")
    ap.add_argument("--compare-env-map", action="store_true", help="alternate with viser's default environment map")
    ap.add_argument("--cold", action="store_true", help="launches with an empty numba cache against warm ones")
    ap.add_argument("--inline", action="store_true",
                    help="--cold: also launch with an empty cache and no background build (compiling in the server)")
    ap.add_argument("--out", type=Path, help="--cold: the CSV (default bench/results/explorer_startup_cold.csv)")
    ap.add_argument("--img", type=Path, help="--cold: the chart (default docs/img/explorer_startup_cold.png)")
    ap.add_argument("--fast-timeout", type=bounded(float, 1.0, 3600.0), default=300.0,
                    help="--cold: seconds to wait for the compiled integrator after the scene moves (default 300)")
    a = ap.parse_args(argv)
    if a.cold:
        cold_main(a.repetitions or 3, a.out, a.img, a.fast_timeout, a.inline)
    else:
        warm_main(a.repetitions or 5, compare_env_map=a.compare_env_map)
    return 0


if __name__ == "__main__":  # the older way to run it, kept working: python bench/explorer_startup.py ...
    raise SystemExit(main(sys.argv[1:], prog="python bench/explorer_startup.py"))
