"""``python -m bench challenge``: the braking challenge's scripted player against the optimal law (issue 25).

The player (app.engine.challenge.scripted) fires the body-axis thruster most nearly opposite the body's J w,
deciding again every ``reaction`` simulated seconds (0.05 s: a program; 0.25 s and 0.5 s: a person's reaction),
on every level and start number asked for, through a tab's engine without a page (app.engine.challenge.play).
The bound it should meet is sqrt(3) T: the best body axis is at most arccos(1/sqrt 3) from -K.

Writes ``<out>/challenge.csv`` (level, start, reaction_s, T_s, T_player_s, ratio T_player / T, score T / T_player,
thrust_s: simulated seconds with a thruster on), ``<out>/challenge.meta.json`` (command, date, machine) and the
chart ``<img>/challenge.png`` (the ratio by level and reaction, the sqrt 3 bound drawn).
"""

from __future__ import annotations

import csv
import json
import math
import sys
import time
from datetime import UTC, datetime
from pathlib import Path

from .cli import ROOT, bounded, study_parser
from .machine import machine
from .runners import log, save_figure

FIELDS = ("level", "start", "reaction_s", "T_s", "T_player_s", "ratio", "score", "thrust_s")


def run(levels, starts, reactions) -> list[dict]:
    from app.engine import challenge  # noqa: PLC0415 - the app only when the study runs
    from app.engine.engine import Engine  # noqa: PLC0415

    rows = []
    for level in levels:
        for start in starts:
            for reaction in reactions:
                eng = Engine()
                eng.request("challenge", (level, start))
                eng._apply_pending()
                if eng.challenge is None:
                    raise SystemExit(f"challenge {level} {start}: {eng.error}")
                ch = challenge.play(eng, challenge.scripted, reaction)
                T_player = ch.finished_at if ch.finished_at is not None else math.inf
                rows.append(dict(level=level, start=start, reaction_s=reaction, T_s=ch.T, T_player_s=T_player,
                                 ratio=T_player / ch.T, score=ch.score if ch.score is not None else 0.0,
                                 thrust_s=ch.fired))
                log(f"{level} start {start} reaction {reaction:g} s: {T_player:.3f} s = {T_player / ch.T:.3f} T")
    return rows


def chart(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    levels = list(dict.fromkeys(r["level"] for r in rows))
    reactions = sorted({r["reaction_s"] for r in rows})
    fig, ax = plt.subplots(figsize=(7, 4))
    width = 0.8 / len(reactions)
    limit, crossed = 3.0, False  # app.engine.challenge.LIMIT
    for j, reaction in enumerate(reactions):
        for i, level in enumerate(levels):
            ratios = [r["ratio"] for r in rows if r["level"] == level and r["reaction_s"] == reaction]
            done = [x for x in ratios if math.isfinite(x)]
            xj = i + (j - (len(reactions) - 1) / 2) * width
            ax.plot([xj] * len(done), done, "o", color=f"C{j}",
                    label=f"decides every {reaction:g} s" if i == 0 else None)
            if len(done) < len(ratios):  # out of time: drawn at the limit, a cross per attempt
                ax.plot([xj] * (len(ratios) - len(done)), [limit] * (len(ratios) - len(done)), "x", color=f"C{j}",
                        ms=9, label="out of time (3 T)" if not crossed else None)
                crossed = True
    ax.axhline(math.sqrt(3), color="k", ls="--", lw=1, label="bound sqrt(3) T")
    ax.axhline(1.0, color="0.5", ls=":", lw=1, label="the optimal law, T")
    ax.set_xticks(range(len(levels)), levels)
    ax.set_ylabel("T_player / T")
    ax.legend(fontsize=8)
    save_figure(fig, path, "Braking challenge: the scripted player against the optimal law")


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("challenge", __doc__)
    ap.add_argument("--starts", type=bounded(int, 0, 99), nargs="+", default=[0, 1, 2, 3, 4],
                    help="start numbers (default 0-4)")
    ap.add_argument("--reactions", type=bounded(float, 1e-3, 60.0), nargs="+", default=[0.05, 0.25, 0.5],
                    help="the player's decision intervals, simulated s (default 0.05 0.25 0.5)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results", help="default bench/results")
    ap.add_argument("--img", type=Path, default=ROOT / "docs" / "img", help="default docs/img")
    args = ap.parse_args(argv)
    from app.engine import challenge  # noqa: PLC0415

    t0 = time.perf_counter()
    rows = run(challenge.LEVELS, args.starts, args.reactions)
    args.out.mkdir(parents=True, exist_ok=True)
    args.img.mkdir(parents=True, exist_ok=True)
    with open(args.out / "challenge.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    meta = dict(command="python -m bench challenge " + " ".join(argv if argv is not None else sys.argv[2:]),
                date=datetime.now(UTC).isoformat(timespec="seconds"), seconds=round(time.perf_counter() - t0, 1),
                machine=machine())
    (args.out / "challenge.meta.json").write_text(json.dumps(meta, indent=1) + "\n")
    chart(rows, args.img / "challenge.png")
    log(f"wrote {args.out / 'challenge.csv'}, {args.img / 'challenge.png'}")
    return 0
