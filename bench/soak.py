"""Soak: the explorer served for a long time, and how much the server's memory grows.

``python -m bench soak --minutes N`` serves the explorer in this process (``app.serve.server.App``, a free
loopback port) with ``--clients`` websocket clients in a child process (bench/load.py says how they
speak viser's protocol). While they watch, one session loads the next preset every ``--churn``
seconds (its scene redrawn, its run restarted) and the last client disconnects and reconnects every
``--reconnect`` seconds (a session built and torn down), so the change paths are soaked too, not only
the steady loop. After ``--warmup`` (default: a fifth of the run, at most 2 minutes), the server's
resident memory is compared between the start and the end of the measured span (medians of the
first and last tenth of its samples). Target (issue 7): growth under 5 % over 60 minutes. Before the
clients connect, every preset is run once, so the kernels' one-time loading is not counted as growth.

Prints one JSON object (also written to ``bench/results/soak.json``) and a one-line summary; exits
with 1 when the growth reaches the target, a steady client fell below 30 updates per second, or a
``Session`` object is still alive once every client has left (bench/load.py counts them).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from bench.cli import bounded, study_parser

from .load import TARGET_UPDATES_PER_S, serve_and_watch

ROOT = Path(__file__).resolve().parent.parent
TARGET_GROWTH = 0.05  # issue 7: RSS growth after warm-up under 5 % over 60 minutes


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("soak", __doc__)
    ap.add_argument("--minutes", type=bounded(float, 0.01, 1440.0), required=True,
                    help="how long the explorer is served (60: the target)")
    ap.add_argument("--clients", type=bounded(int, 1, 500), default=2, help="websocket clients watching (default 2)")
    ap.add_argument("--warmup", type=bounded(float, 0.0, 3600.0), default=None,
                    help="seconds not measured (default: run/5, <= 120)")
    ap.add_argument("--churn", type=bounded(float, 0.0, 3600.0), default=10.0,
                    help="seconds between preset loads (0: none)")
    ap.add_argument("--reconnect", type=bounded(float, 0.0, 3600.0), default=30.0,
                    help="seconds between reconnections (0: none)")
    ap.add_argument("--trim", action="store_true", help="call glibc malloc_trim before each memory sample (tells a "
                    "leak from freed memory the allocator keeps)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "soak.json",
                    help="the JSON result (default bench/results/soak.json)")
    a = ap.parse_args(argv)
    seconds = 60.0 * a.minutes
    warmup = a.warmup if a.warmup is not None else min(120.0, seconds / 5)
    res = serve_and_watch(a.clients, seconds, warmup=warmup, reconnect_every=a.reconnect or None,
                          churn_every=a.churn or None, trim=a.trim)
    res["command"] = "python -m bench soak " + " ".join(argv if argv is not None else sys.argv[1:])
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(json.dumps(res, indent=1))
    print(json.dumps({k: v for k, v in res.items() if k not in ("rss_mb_series", "delivered")}))
    print(f"soak: {a.minutes:g} min, {a.clients} clients, {res['churned_presets']} preset loads: server RSS "
          f"{res['rss_mb_after_warmup']:.1f} MB after {warmup:g} s warm-up -> {res['rss_mb_end']:.1f} MB at the end "
          f"({100 * res['rss_growth']:+.2f} %, target < {100 * TARGET_GROWTH:g} %); steady clients' worst second "
          f"{res['steady_min_updates_per_s']} updates/s; {res['sessions_opened']} sessions opened, "
          f"{res['sessions_closed']} closed, {res['live_sessions_after_clients_left']} alive after the clients left; "
          f"{res['churned_presets_shown']} preset loads shown")
    ok = (res["rss_growth"] < TARGET_GROWTH and res["steady_min_updates_per_s"] >= TARGET_UPDATES_PER_S
          and res["live_sessions_after_clients_left"] == 0)
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
