"""A study's results as the benchmarks write them: ``<stem>.csv`` (one row per scenario) and ``<stem>.meta.json``
(the command, what the study read, the date, its wall time, the machine and its summary)."""

from __future__ import annotations

import csv
import json
from datetime import UTC, datetime
from pathlib import Path

from bench.machine import machine


def write_results(out: Path, stem: str, columns, rows: list[dict], *, command: str, wall_s: float, summary: dict,
                  **read) -> None:
    """Write ``out/<stem>.csv`` (``columns`` in order) and ``out/<stem>.meta.json``; ``read``: what the study read
    (its input files), recorded after the command."""
    out.mkdir(parents=True, exist_ok=True)
    with open(out / f"{stem}.csv", "w", newline="") as f:
        w = csv.DictWriter(f, columns)
        w.writeheader()
        w.writerows(rows)
    meta = dict(command=command, **read, date=datetime.now(UTC).isoformat(timespec="seconds"), wall_s=wall_s,
                machine=machine(), summary=summary)
    (out / f"{stem}.meta.json").write_text(json.dumps(meta, indent=2) + "\n")
