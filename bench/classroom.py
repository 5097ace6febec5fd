"""A class on one server: N student tabs following the lecturer's run (issue 25, point 1).

``python -m bench class --tabs 30 --minutes 10 --out bench/results/class.json`` serves the explorer in class mode
in this process (``app.serve.server.App(class_mode=True)`` on a free loopback port) and starts, in a child process,
one lecturer tab (a raw client that answers the server's read of its storage with the key, as the lecturer's link
would) and ``--tabs`` student tabs (bench/class_client.py: raw clients that count the windows turning their body,
as bench/load.py's do). So the resident memory sampled here is the server's alone.

Every ``--edit-every`` seconds the lecturer edits the body (A, between two values, through the class engine's
``request_value``, the path the lecturer's slider callback takes); the edit redraws the body in every tab, and each
tab records when its redrawn shape arrived (``time.time()``, one clock for both processes of this machine). The
latency of an edit to a tab is that arrival less the time of the request.

Writes JSON (``--out``): ``clients`` (per student tab: ``median_updates_per_s``, ``min_updates_per_s``,
``share_of_seconds_ge_30``, its edit latencies' median and max), the server's RSS after the warm-up and at the end,
the edit latency over all tabs (median, max), the class loop's frames and ticks, the load average and the machine;
and a chart beside it (same name, .png): each tab's updates per second over time, the server's RSS, and the
latencies. The first ``--warmup`` seconds (tabs joining) are not measured.
"""

from __future__ import annotations

import asyncio
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench.cli import bounded, study_parser

from .load import rss_bytes
from .machine import machine

ROOT = Path(__file__).resolve().parent.parent
TARGET_UPDATES_PER_S = 30.0  # issue 25: each following tab at least this many in 95 % of seconds
TARGET_SHARE = 0.95
TARGET_RSS_GROWTH = 0.05  # over the run
TARGET_LATENCY_S = 0.2  # median, lecturer's edit to a tab
EDIT_KEY = "body.A"
EDIT_VALUES = (1.0, 1.2)  # kg m^2: the default scene's A and another; the body is drawn anew each time


# ---- the tabs (child process) ----------------------------------------------------------------------------
def client_main(argv: list[str]) -> int:
    from app.share.link import CLASS_KEY

    from .class_client import Tab

    ap = study_parser("", "", prog="python -m bench.classroom --client")
    ap.add_argument("--client", required=True, help="websocket URL")
    ap.add_argument("--tabs", type=bounded(int, 1, 500), required=True)
    ap.add_argument("--seconds", type=bounded(float, 0.0, 86400.0), required=True)
    ap.add_argument("--key", required=True)
    a = ap.parse_args(argv)
    lecturer = Tab({CLASS_KEY: a.key})
    students = [Tab() for _ in range(a.tabs)]

    async def main():
        await asyncio.gather(lecturer.run(a.client, a.seconds), *(s.run(a.client, a.seconds) for s in students))

    asyncio.run(main())
    print(json.dumps([dict(counts=t.counts, shapes=t.shapes, errors=t.errors[:5], n_errors=len(t.errors),
                           lecturer=t is lecturer) for t in [lecturer, *students]]))
    return 0


# ---- the server (this process) -----------------------------------------------------------------------------
def serve_class(tabs: int, seconds: float, *, warmup: float, edit_every: float) -> dict:
    from app.serve.server import App, warm_up

    warm_up()
    app = App(host="127.0.0.1", port=0, class_mode=True)
    room = app.classroom
    room.open()  # the class run starts now; the lecturer's tab joins it like any
    cmd = [sys.executable, "-m", "bench.classroom", "--client", f"ws://127.0.0.1:{app.port}", "--tabs", str(tabs),
           "--seconds", str(seconds), "--key", room.key]
    # the tabs' counts go to files, not pipes: ten minutes of 30 tabs' counts are more than a pipe holds, and
    # the child would wait to write them while this loop waits for it to end
    result_file, error_file = tempfile.TemporaryFile(mode="w+"), tempfile.TemporaryFile(mode="w+")
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=result_file, stderr=error_file, text=True)
    t0 = time.perf_counter()
    rss: list[tuple[float, int]] = []
    load: list[float] = []
    edits: list[float] = []  # time.time() of each edit requested
    frames0 = ticks0 = None
    next_edit = warmup
    try:
        while proc.poll() is None:
            now = time.perf_counter() - t0
            rss.append((now, rss_bytes()))
            load.append(os.getloadavg()[0])
            if now >= warmup and frames0 is None:
                frames0, ticks0 = room.frames, room.ticks
            if now >= next_edit and now < seconds - edit_every / 2:
                edits.append(time.time())
                room.engine.request_value(EDIT_KEY, EDIT_VALUES[len(edits) % 2])
                next_edit += edit_every
            time.sleep(0.25)
        proc.wait()
        result_file.seek(0)
        error_file.seek(0)
        out, err = result_file.read(), error_file.read()
        frames, ticks = room.frames - (frames0 or 0), room.ticks - (ticks0 or 0)
        views = len(room.views)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        app.close()
    if proc.returncode != 0:
        raise RuntimeError(f"the tabs' process failed ({proc.returncode}): {err.strip()[-2000:]}")
    res = summarize(json.loads(out), rss, edits, seconds=seconds, warmup=warmup, edit_every=edit_every)
    res.update(class_frames=frames, class_ticks=ticks, views_at_end=views,
               load_average_1min_median=statistics.median(load) if load else None,
               load_average_1min_max=max(load) if load else None, load_average_at_end=list(os.getloadavg()))
    return res


def _latencies(shapes: list[float], edits: list[float], edit_every: float) -> list[float]:
    """Per edit, the first redrawn shape the tab received after it (and before the next edit): seconds."""
    out = []
    for i, t in enumerate(edits):
        end = edits[i + 1] if i + 1 < len(edits) else t + edit_every
        got = [s for s in shapes if t <= s < end]
        if got:
            out.append(got[0] - t)
    return out


def summarize(per_tab: list[dict], rss, edits, *, seconds: float, warmup: float, edit_every: float) -> dict:
    lo, hi = int(warmup), int(seconds) - 1  # whole seconds measured (the last one may be partial)
    clients, all_lat = [], []
    for i, c in enumerate(t for t in per_tab if not t["lecturer"]):
        counts = (c["counts"] + [0] * int(seconds + 1))[lo:hi]
        lat = _latencies(c["shapes"], edits, edit_every)
        all_lat += lat
        clients.append(dict(
            tab=i, median_updates_per_s=statistics.median(counts) if counts else 0,
            min_updates_per_s=min(counts) if counts else 0,
            share_of_seconds_ge_30=sum(x >= TARGET_UPDATES_PER_S for x in counts) / max(1, len(counts)),
            edits_seen=len(lat), edit_latency_median_s=statistics.median(lat) if lat else None,
            edit_latency_max_s=max(lat) if lat else None, updates_per_s=counts, errors=c["errors"],
            n_errors=c["n_errors"]))
    after = [(t, r) for t, r in rss if t >= warmup]
    k = max(3, len(after) // 20)
    start = statistics.median(r for _, r in after[:k]) if after else float("nan")
    end = statistics.median(r for _, r in after[-k:]) if after else float("nan")
    shares = [c["share_of_seconds_ge_30"] for c in clients]
    return dict(
        tabs=len(clients), seconds=seconds, warmup_s=warmup, edit_every_s=edit_every, edits=len(edits),
        clients=clients,
        tabs_meeting_30_in_95pct=sum(s >= TARGET_SHARE for s in shares),
        worst_share_of_seconds_ge_30=min(shares) if shares else None,
        rss_mb_start=start / 2**20, rss_mb_end=end / 2**20, rss_growth=(end - start) / start if after else None,
        rss_mb_series=[(round(t, 1), round(r / 2**20, 2)) for t, r in rss[:: max(1, len(rss) // 240)]],
        edit_latency_median_s=statistics.median(all_lat) if all_lat else None,
        edit_latency_max_s=max(all_lat) if all_lat else None,
        edit_latencies_s=[round(x, 4) for x in all_lat],
        lecturer_errors=[e for t in per_tab if t["lecturer"] for e in t["errors"]],
        machine=machine(),
    )


def chart(res: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b, c) = plt.subplots(1, 3, figsize=(15, 4.2))
    lo = int(res["warmup_s"])
    for cl in res["clients"]:
        a.plot(range(lo, lo + len(cl["updates_per_s"])), cl["updates_per_s"], lw=0.6, alpha=0.6)
    a.axhline(TARGET_UPDATES_PER_S, color="k", ls="--", lw=1, label="30 updates/s")
    a.set(xlabel="s", ylabel="body updates received per second", title=f"{res['tabs']} following tabs")
    a.legend(loc="lower right")
    t, r = zip(*res["rss_mb_series"], strict=True) if res["rss_mb_series"] else ((), ())
    b.plot(t, r)
    b.axvline(res["warmup_s"], color="gray", ls=":", lw=1)
    b.set(xlabel="s", ylabel="MB", title=f"server RSS ({100 * (res['rss_growth'] or 0):+.1f} % after warm-up)")
    if res["edit_latencies_s"]:
        c.hist([1e3 * x for x in res["edit_latencies_s"]], bins=30)
    c.axvline(1e3 * TARGET_LATENCY_S, color="k", ls="--", lw=1, label="200 ms")
    med = res["edit_latency_median_s"]
    c.set(xlabel="ms", ylabel="edits x tabs", title=f"lecturer's edit to a tab (median "
          f"{1e3 * med:.0f} ms)" if med is not None else "lecturer's edit to a tab")
    c.legend()
    fig.suptitle(f"python -m bench class: load average {res['load_average_1min_median']:.1f} (median, 1 min) on "
                 f"{res['machine'].get('cpus')} CPUs", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("class", __doc__)
    ap.add_argument("--tabs", type=bounded(int, 1, 500), default=30,
                    help="student tabs following the class (default 30)")
    ap.add_argument("--minutes", type=bounded(float, 0.01, 1440.0), default=10.0,
                    help="how long they follow (default 10)")
    ap.add_argument("--warmup", type=bounded(float, 0.0, 3600.0), default=20.0,
                    help="seconds not measured at the start (default 20)")
    ap.add_argument("--edit-every", type=bounded(float, 0.1, 3600.0), default=5.0,
                    help="seconds between the lecturer's edits (default 5)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "class.json",
                    help="the JSON result (default bench/results/class.json); the chart beside it, .png")
    a = ap.parse_args(argv)
    if not 0 <= a.warmup < 60 * a.minutes:
        ap.error(f"--warmup {a.warmup!r}: must be at least 0 and less than the run ({60 * a.minutes:g} s)")
    res = serve_class(a.tabs, 60.0 * a.minutes, warmup=a.warmup, edit_every=a.edit_every)
    res["command"] = "python -m bench class " + " ".join(argv if argv is not None else sys.argv[1:])
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(json.dumps(res, indent=1))
    png = a.out.with_suffix(".png")
    chart(res, png)
    lat = res["edit_latency_median_s"]
    print(f"class: {res['tabs']} tabs, {a.minutes:g} min, load average {res['load_average_1min_median']:.1f}: "
          f"{res['tabs_meeting_30_in_95pct']} of {res['tabs']} tabs at >= 30 updates/s in >= 95 % of seconds "
          f"(worst tab {100 * (res['worst_share_of_seconds_ge_30'] or 0):.0f} %); server RSS "
          f"{res['rss_mb_start']:.1f} -> {res['rss_mb_end']:.1f} MB ({100 * res['rss_growth']:+.2f} %); edit latency "
          f"median {1e3 * lat:.0f} ms, max {1e3 * res['edit_latency_max_s']:.0f} ms" if lat is not None else
          "no edit reached a tab")
    print(f"wrote {a.out} and {png}")
    ok = (res["tabs_meeting_30_in_95pct"] == res["tabs"] and abs(res["rss_growth"]) <= TARGET_RSS_GROWTH
          and lat is not None and lat <= TARGET_LATENCY_S)
    return 0 if ok else 1


if __name__ == "__main__":
    argv = sys.argv[1:]
    if "--client" in argv:
        raise SystemExit(client_main(argv))
    raise SystemExit(main(argv))
