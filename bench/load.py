"""Many websocket clients on one explorer server, and the server's memory while they watch.

``python -m bench load --clients 10 --minutes 5`` serves the explorer in this process
(``app.serve.server.App`` on a free loopback port) and starts the clients in a child process, so the
resident memory sampled here is the server's alone. Each client speaks viser's protocol only as far
as a browser tab must to get a session: it connects to ``ws://127.0.0.1:PORT`` offering the
subprotocol ``viser-v<version>`` (viser rejects other versions), sends the one message a browser sends
first (its camera, ``ViewerCameraMessage``: viser counts a client as connected, and the app builds its
session, only after it), then reads. Every websocket message
the server sends is one window of updates (msgpack, zstd-compressed as viser sends it); the client
decodes each and counts, per second, the windows that move the body (a ``SetOrientationMessage`` for the body frame),
which is what a browser would redraw.

Prints one JSON object (also written to ``bench/results/load.json``): per client the minimum and
median updates per second over the measured seconds, and the server's RSS over time. The first
``--warmup`` seconds (sessions starting, JIT caches loading) are not measured. Counts too, which a busy
machine does not change (tests/test_load.py, tests/test_soak.py assert them): per session, the body updates
its client received over the frames the server published for it (``delivered``); sessions opened and
closed; and the ``Session`` objects still alive once every client has left and the server's cleanup ran.
"""

from __future__ import annotations

import asyncio
import ctypes
import json
import os
import statistics
import subprocess
import sys
import threading
import time
import warnings
import weakref
from pathlib import Path

from bench.cli import bounded, study_parser

from .machine import machine

ROOT = Path(__file__).resolve().parent.parent
TARGET_UPDATES_PER_S = 30.0  # issue 7: each client keeps receiving at least this many
BODY_NODE = "/body"  # the session's body frame is /s<client id>/body (app/serve/server.py)


# ---- the client side (child process) ---------------------------------------------------------------
def _body_moved(raw: bytes) -> int | None:
    """The client id of the session whose body frame one viser window (see
    viser.infra._infra._message_producer) turns (its node is /s<id>/body), or None."""
    import msgspec
    import zstandard

    size = int.from_bytes(raw[:8], "little")
    clen = int.from_bytes(raw[8:16], "little")
    inner = zstandard.ZstdDecompressor().decompress(raw[16:16 + clen], max_output_size=size)
    for m in msgspec.msgpack.decode(inner)["messages"]:
        name = str(m.get("name", ""))
        if m.get("type") == "SetOrientationMessage" and name.startswith("/s") and name.endswith(BODY_NODE):
            root = name[2:-len(BODY_NODE)]
            return int(root) if root.isdigit() else None
    return None


def _moves_body(raw: bytes) -> bool:
    """Whether one viser window updates a session's body frame's pose."""
    return _body_moved(raw) is not None


def _camera_message() -> bytes:
    """What a browser sends on connecting: its camera (msgpack of the message's fields and its type)."""
    import msgspec

    return msgspec.msgpack.encode(dict(
        type="ViewerCameraMessage", wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, -3.4, 1.9), fov=1.3, near=0.01,
        far=1000.0, image_height=720, image_width=1280, look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0)))


async def _client(url: str, seconds: float, reconnect_every: float | None, counts: list[int],
                  windows: list[int], errors: list[str], by_session: dict[str, int]) -> None:
    """``by_session``: body updates received, per session (client id) this client was given."""
    import viser
    from websockets.asyncio.client import connect

    start = time.perf_counter()
    end = start + seconds
    while time.perf_counter() < end:
        stay = end if reconnect_every is None else min(end, time.perf_counter() + reconnect_every)
        try:
            async with connect(url, subprotocols=[f"viser-v{viser.__version__}"], max_size=None,
                               compression=None, open_timeout=60) as ws:
                await ws.send(_camera_message())
                while (left := stay - time.perf_counter()) > 0:
                    try:
                        raw = await asyncio.wait_for(ws.recv(), timeout=left)
                    except TimeoutError:
                        break
                    second = int(time.perf_counter() - start)
                    while len(counts) <= second:
                        counts.append(0)
                        windows.append(0)
                    windows[second] += 1
                    if isinstance(raw, bytes) and (sid := _body_moved(raw)) is not None:
                        counts[second] += 1
                        by_session[str(sid)] = by_session.get(str(sid), 0) + 1
        except Exception as exc:  # recorded and reported: a client that cannot stay connected is a failure
            errors.append(f"{type(exc).__name__}: {exc}")
            await asyncio.sleep(0.5)


async def _clients(url: str, n: int, seconds: float, reconnect_every: float | None) -> list[dict]:
    results = [dict(counts=[], windows=[], errors=[], by_session={}) for _ in range(n)]
    # only the last client reconnects, so the others measure a steady tab's rate
    await asyncio.gather(*(_client(url, seconds, reconnect_every if i == n - 1 else None, r["counts"],
                                   r["windows"], r["errors"], r["by_session"]) for i, r in enumerate(results)))
    return results


def client_main(argv: list[str]) -> int:
    ap = study_parser("", "", prog="python -m bench.load --client")
    ap.add_argument("--client", required=True, help="websocket URL")
    ap.add_argument("--clients", type=bounded(int, 1, 500), required=True)
    ap.add_argument("--seconds", type=bounded(float, 0.0, 86400.0), required=True)
    ap.add_argument("--reconnect-every", type=bounded(float, 0.1, 86400.0), default=None)
    a = ap.parse_args(argv)
    out = asyncio.run(_clients(a.client, a.clients, a.seconds, a.reconnect_every))
    print(json.dumps(out))
    return 0


# ---- the server side (this process) ---------------------------------------------------------------
def rss_bytes(pid: int | str = "self") -> int:
    """Resident set size of a process, bytes (Linux /proc)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    raise RuntimeError("no VmRSS")


def malloc_trim() -> None:
    """Give the C allocator's free memory back to the system (glibc); a no-op elsewhere."""
    try:
        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        pass


def serve_and_watch(clients: int, seconds: float, *, warmup: float, reconnect_every: float | None = None,
                    churn_every: float | None = None, sample_every: float = 1.0, trim: bool = False) -> dict:
    """Serve the explorer, run ``clients`` websocket clients for ``seconds`` and return the figures.

    ``churn_every`` (s): every so often one session loads the next preset (its scene is redrawn and its
    run restarted), so a soak exercises the change paths and not only the steady loop. ``trim``: call
    glibc's malloc_trim before each memory sample, which tells live memory (a leak) from freed memory the
    allocator keeps."""
    import physics
    from app.engine import presets
    from app.serve.server import App, warm_up

    warm_up()
    if churn_every:  # every system's kernels loaded once now, so their one-time cost is not counted as growth
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for name in presets.preset_names():
                try:
                    physics.LiveRun(presets.load_preset(name)).advance(0.01)
                except Exception:  # a preset that does not run is the app's to report, not the soak's
                    pass
    app = App(host="127.0.0.1", port=0)
    url = f"ws://127.0.0.1:{app.port}"
    cmd = [sys.executable, "-m", "bench.load", "--client", url, "--clients", str(clients),
           "--seconds", str(seconds)]
    if reconnect_every:
        cmd += ["--reconnect-every", str(reconnect_every)]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.perf_counter()
    rss: list[tuple[float, int]] = []
    frames: list[tuple[float, int]] = []
    frame_ms: dict[int, tuple[float, float]] = {}  # session -> median (tick, publish) wall ms, last seen
    load: list[float] = []
    names = presets.preset_names()
    churned = 0
    churns: list[tuple[weakref.ref, int]] = []  # (session, change seq) of each preset load asked for
    churn_shown: set[int] = set()  # indices into churns whose session published a frame showing the load
    next_churn = warmup if churn_every else float("inf")
    visited = False
    try:
        while proc.poll() is None:
            now = time.perf_counter() - t0
            if trim:
                malloc_trim()
            rss.append((now, rss_bytes()))
            frames.append((now, app.stats.get("frames", 0)))
            load.append(os.getloadavg()[0])
            _note_shown(churns, churn_shown)
            for cid, session in list(app.sessions.items()):
                recent = list(session.frame_ms)
                if recent:
                    frame_ms[cid] = tuple(statistics.median(x[i] for x in recent) for i in (0, 1))
            if not visited and churn_every and app.sessions and now < warmup:
                # every preset shown once in a tab during the warm-up: a scene's first showing loads what
                # it needs once (its kernels, the badge's analyses), which is not growth
                session = next(iter(app.sessions.values()))
                for name in names:
                    session.engine.request("preset", name)
                    time.sleep(0.25)
                session.engine.request("preset", names[0])
                visited = True
            # none in the clients' last churn interval: a load asked for as the tab leaves has no frame to show it
            if now >= next_churn and app.sessions and now <= seconds - churn_every:
                session = next(iter(app.sessions.values()))
                churned += 1
                churns.append((weakref.ref(session), session.engine.request("preset", names[churned % len(names)])))
                next_churn += churn_every
            session = None  # the bench must hold no session: the live sessions are counted at the end
            time.sleep(sample_every)
        out, err = proc.communicate()
        _note_shown(churns, churn_shown)
        ends = _after_clients_left(app)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        sessions_left = len(app.sessions)
        app.close()
    if proc.returncode != 0:
        raise RuntimeError(f"the clients' process failed ({proc.returncode}): {err.strip()[-2000:]}")
    per_client = json.loads(out)
    res = summarize(per_client, rss, frames, seconds=seconds, warmup=warmup, clients=clients,
                    churned=churned, sessions_left=sessions_left, reconnect_every=reconnect_every)
    res.update(ends)
    res["churned_presets_shown"] = len(churn_shown)
    res.update(_delivered(per_client, ends["published_by_session"]))
    res["median_tick_ms"] = statistics.median(v[0] for v in frame_ms.values()) if frame_ms else None
    res["median_publish_ms"] = statistics.median(v[1] for v in frame_ms.values()) if frame_ms else None
    res["load_average_1min_median"] = statistics.median(load) if load else None  # other work on the machine
    res["malloc_trim_before_samples"] = trim
    return res


def _note_shown(churns: list, shown: set[int]) -> None:
    """Which preset loads a frame has shown: the session records the first frame after each change."""
    for i, (ref, seq) in enumerate(churns):
        session = ref()
        if i not in shown and session is not None and seq in session.first_frame_after:
            shown.add(i)


def _after_clients_left(app, wait: float = 15.0) -> dict:
    """Counts once every client has gone: sessions opened and closed, the frames each session published,
    and the ``Session`` objects still alive. A closed session is cyclic garbage that App frees in its
    ``collect-sessions`` thread (app/serve/closing.py ``Collector``); that thread is waited for, and
    nothing here runs a collection itself, so a session that cleanup missed is counted."""
    import gc

    from app.serve.session import Session

    end = time.perf_counter() + wait
    while app.sessions and time.perf_counter() < end:  # the clients' last disconnections being handled
        time.sleep(0.1)
    time.sleep(0.5)  # the collector is given the session by the disconnect callback, just after the pop above
    for t in threading.enumerate():
        if t.name == "collect-sessions":
            t.join(timeout=max(0.1, end - time.perf_counter()))
    published = {str(cid): n for cid, n in app.closed_frames}
    published.update({str(cid): s.published for cid, s in app.sessions.items()})
    objects = gc.get_objects()
    live = sum(isinstance(o, Session) for o in objects)
    return dict(sessions_opened=app.stats.get("opened", 0), sessions_closed=app.stats.get("closed", 0),
                tabs_told_full=app.stats.get("full", 0),  # beyond app.serve.capacity.MAX_TABS
                live_sessions_after_clients_left=live - len(app.sessions), gc_objects_after_clients_left=len(objects),
                published_by_session=published)


def _delivered(per_client: list[dict], published: dict[str, int]) -> dict:
    """Per session, the body updates its client received over the frames the server published for it (one
    frame, one body turn): a client that falls behind, or whose updates the server drops, receives fewer."""
    rows = []
    for i, c in enumerate(per_client):
        for sid, got in c["by_session"].items():
            sent = published.get(sid, 0)
            rows.append(dict(client=i, session=sid, received=got, published=sent,
                             fraction=got / sent if sent else float("nan")))
    fractions = [r["fraction"] for r in rows if r["published"]]
    return dict(delivered=rows, min_delivered_fraction=min(fractions) if fractions else float("nan"),
                sessions_seen_by_clients=len(rows))


def summarize(per_client, rss, frames, *, seconds, warmup, clients, churned, sessions_left, reconnect_every):
    lo, hi = int(warmup), int(seconds) - 1  # whole seconds measured (the last one may be partial)
    rates = []
    for i, c in enumerate(per_client):
        counts = (c["counts"] + [0] * int(seconds + 1))[lo:hi]
        windows = (c["windows"] + [0] * int(seconds + 1))[lo:hi]
        steady = reconnect_every is None or i < clients - 1
        rates.append(dict(steady=steady, min_updates_per_s=min(counts) if counts else 0,
                          median_updates_per_s=statistics.median(counts) if counts else 0,
                          median_windows_per_s=statistics.median(windows) if windows else 0,
                          seconds_at_target=sum(c >= TARGET_UPDATES_PER_S for c in counts) / max(1, len(counts)),
                          errors=c["errors"][:5], n_errors=len(c["errors"])))
    after = [(t, r) for t, r in rss if t >= warmup]
    base = statistics.median(r for _, r in after[: max(3, len(after) // 10)]) if after else float("nan")
    last = statistics.median(r for _, r in after[-max(3, len(after) // 10):]) if after else float("nan")
    return dict(
        clients=clients, seconds=seconds, warmup_s=warmup, churned_presets=churned, reconnect_every=reconnect_every,
        steady_min_updates_per_s=min((r["min_updates_per_s"] for r in rates if r["steady"]), default=0),
        clients_detail=rates,
        rss_mb_after_warmup=base / 2**20, rss_mb_end=last / 2**20,
        rss_mb_max=max(r for _, r in after) / 2**20 if after else float("nan"),
        rss_growth=(last - base) / base if after else float("nan"),
        rss_mb_series=[(round(t, 1), round(r / 2**20, 2)) for t, r in rss[:: max(1, len(rss) // 120)]],
        server_frames=frames[-1][1] if frames else 0, sessions_left_at_end=sessions_left,
        machine=machine(),
    )


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("load", __doc__)
    ap.add_argument("--clients", type=bounded(int, 1, 500), default=10,
                    help="websocket clients watching at once (default 10)")
    ap.add_argument("--minutes", type=bounded(float, 0.01, 1440.0), default=5.0, help="how long they watch (default 5)")
    ap.add_argument("--warmup", type=bounded(float, 0.0, 3600.0), default=15.0,
                    help="seconds not measured at the start")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "load.json",
                    help="the JSON result (default bench/results/load.json)")
    a = ap.parse_args(argv)
    res = serve_and_watch(a.clients, 60.0 * a.minutes, warmup=a.warmup)
    res["command"] = "python -m bench load " + " ".join(argv if argv is not None else sys.argv[1:])
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(json.dumps(res, indent=1))
    print(json.dumps({k: v for k, v in res.items() if k not in ("rss_mb_series", "clients_detail", "delivered")}))
    ok = res["steady_min_updates_per_s"] >= TARGET_UPDATES_PER_S
    print(f"load: {a.clients} clients, {a.minutes:g} min: slowest client's worst second "
          f"{res['steady_min_updates_per_s']} updates/s (target >= {TARGET_UPDATES_PER_S:g}); server RSS "
          f"{res['rss_mb_after_warmup']:.1f} -> {res['rss_mb_end']:.1f} MB ({100 * res['rss_growth']:+.2f} %); each "
          f"session's client received >= {res['min_delivered_fraction']:.3f} of its published frames; sessions opened "
          f"{res['sessions_opened']}, closed {res['sessions_closed']}, alive after the clients left "
          f"{res['live_sessions_after_clients_left']}")
    return 0 if ok else 1


if __name__ == "__main__":
    argv = sys.argv[1:]
    if "--client" in argv:
        raise SystemExit(client_main(argv))
    raise SystemExit(main(argv))
