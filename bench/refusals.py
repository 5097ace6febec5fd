"""Extreme-value edits of the shipped scenarios: how many refusals name the key that was changed (issue 24).

Each edit sets one numeric key of one shipped scenario (physics.numeric_keys) to one of VALUES and runs it with
physics.simulate. A ScenarioError or IntegrationFault is a refusal; it names the changed key when its message
holds the dotted key (or, for a table of several blocks, ``table[i].name``). A run still going after WALL_S
seconds of wall time is stopped and counted as running, not as a refusal, so the counts move a little with the
machine's load.

    python -m bench refusals [--out FILE] [--wall S]
"""

from __future__ import annotations

import json
import sys
import time
import warnings
from pathlib import Path

from bench.cli import bounded, study_parser

ROOT = Path(__file__).resolve().parent.parent
VALUES = (1e-300, 1e300, 1e30, 1e-30, 9.2e18)
WALL_S = 1.0


class _Slow(BaseException):
    """Raised from the progress callback: the run took longer than WALL_S (not a refusal)."""


def names(message: str, key: str) -> bool:
    table, name = key.split(".", 1)
    return key in message or (f"{table}[" in message and f"].{name} " in message)


def measure(wall_s: float = WALL_S) -> dict:
    import physics

    stats = dict(edits=0, refused=0, named=0, running=0)
    misses = []
    warnings.simplefilter("ignore")
    for path in sorted((ROOT / "assets" / "scenarios").glob("*.toml")):
        base = physics.Scenario.load(path)
        for key in physics.numeric_keys(base):
            for v in VALUES:
                stats["edits"] += 1
                start = time.perf_counter()

                def progress(_fraction, start=start):
                    if time.perf_counter() - start > wall_s:
                        raise _Slow

                try:
                    physics.simulate(base.with_values(**{key: v}), progress=progress)
                except _Slow:
                    stats["running"] += 1
                except (physics.ScenarioError, physics.IntegrationFault) as exc:
                    stats["refused"] += 1
                    if names(str(exc), key):
                        stats["named"] += 1
                    else:
                        misses.append(f"{path.stem}: {key} = {v:g}: {str(exc)[:200]}")
    return {**stats, "not_named": stats["refused"] - stats["named"], "misses": misses}


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("refusals", __doc__.splitlines()[0])
    ap.add_argument("--wall", type=bounded(float, 0.1, 3600.0), default=WALL_S,
                    help="seconds a run may take before it counts as running")
    ap.add_argument("--out", type=Path, default=None, help="JSON file for the counts and the refusals not naming "
                                                           "their key (with the machine)")
    args = ap.parse_args(argv)
    out = measure(args.wall)
    print(f"{out['edits']} edits, {out['refused']} refused, {out['named']} of them name the changed key, "
          f"{out['not_named']} do not; {out['running']} still running after {args.wall:g} s")
    if args.out is not None:
        from .machine import machine

        command = "python -m bench refusals " + " ".join(argv if argv is not None else sys.argv[2:])
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps({"command": command.strip(), "machine": machine(), **out}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
