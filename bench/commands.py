"""``python -m bench commands``: every command's options given hostile values, each command run as a user runs it.

Each case is the real command in a subprocess (``python -m physics design``, ``python -m app record``, ``python -m
app``), never a stub: one option set to one value (numbers from 5e-324 to 1e308, nan, inf, negatives written with
and without ``=``, words, the empty string), the others good. A case ends in one of:

- ``ran``: status 0 (the explorer: it printed its "ready" line, and is then stopped);
- ``refused``: status 2 and a last line with ``error: ...`` that names the option (for ``--vary``, or the key it
  bounds) or the value given; ``unnamed``: one that names neither;
- ``traceback``: "Traceback" anywhere in what it printed; ``hung``: still going after the time bound; ``other``:
  any other status.

The bad outcomes are traceback, hung, other and unnamed. The same commands run by hand across magnitudes found
five faults (docs/reliability.md); this study keeps looking. Writes a JSON file (machine, command, counts, and
every case that neither ran nor was refused by name).
"""

from __future__ import annotations

import itertools
import json
import os
import queue
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from .cli import study_parser
from .machine import machine

ROOT = Path(__file__).resolve().parents[1]
# 100000: a whole number argparse's int takes, far past any sensible count (--workers 100000 forked without end)
NUMBERS = ("5e-324", "-5e-324", "1e-300", "1e308", "-1e308", "nan", "inf", "-inf", "0", "-1", "1e999", "2.5",
           "100000")
WORDS = ("abc", "", " ", "x" * 300, "1,5")
TIME_BOUND_S = 120.0  # per case: a design of 13 short runs, or the explorer's start
QUICK = ("5e-324", "-1e308", "nan", "")  # --quick: CI's sample of the values
ALSO_NAMED = {"--vary": ("mass.Omega",)}  # a refusal of a design's bounds may name the key they bound


def _scenario(tmp: Path) -> Path:
    """The default scene shortened to 5 s, so that a design the values let through ends within the bound."""
    text = (ROOT / "assets" / "scenarios" / "oblate_settling.toml").read_text()
    out = tmp / "short.toml"
    out.write_text(text.replace("t_end = 60000.0", "t_end = 5.0"))
    return out


def cases(tmp: Path, values) -> list[tuple[str, str, str, list[str]]]:
    """(command, option, value, argv after ``python -m``) for every option and value, each value written both
    as ``--option=value`` and as ``--option value``."""
    sc = str(_scenario(tmp))
    design = ["physics", "design", sc]
    good = design + ["--vary", "mass.Omega=1:3"]  # the bounds the other options' cases keep
    short = ["--budget", "13", "--workers", "1"]
    names = itertools.count()

    def record() -> list[str]:  # a file for each case: cases may run at once
        return ["app", "record", "--out", str(tmp / f"r{next(names)}.html")]

    out = []
    for v in values:
        out += [("physics design", "--vary", v, design + ["--vary", f"mass.Omega={v}:3", *short]),
                ("physics design", "--vary", v, design + ["--vary", f"mass.Omega=1:{v}", *short])]
        for form in (lambda option, v=v: [f"{option}={v}"], lambda option, v=v: [option, v]):
            out += [("physics design", "--accuracy", v, good + [*short, *form("--accuracy")]),
                    ("physics design", "--budget", v, good + ["--workers", "1", *form("--budget")]),
                    ("physics design", "--workers", v, good + ["--budget", "13", *form("--workers")]),
                    ("app record", "--seconds", v, record() + form("--seconds")),
                    ("app record", "--warp", v, record() + ["--seconds", "1", *form("--warp")]),
                    ("app", "--port", v, ["app", *form("--port")])]
    for host in ("", "192.0.2.1", "a" * 64 + ".example", "1e308"):
        out.append(("app", "--host", host, ["app", "--host", host, "--port", "0"]))
    return out


def run_case(argv: list[str], cwd: Path) -> dict:
    """Run ``python -m ARGV``; the explorer is stopped once it says it is ready. Its output is read by a thread of
    its own, so that a command that hangs without printing a line is still stopped at the bound."""
    start = time.perf_counter()
    p = subprocess.Popen([sys.executable, "-m", *argv], cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, env={**os.environ, "PYTHONPATH": str(ROOT)})
    lines: queue.Queue = queue.Queue()
    threading.Thread(target=lambda: [lines.put(line) for line in p.stdout] + [lines.put(None)], daemon=True).start()
    explorer = argv[0] == "app" and argv[1:2] != ["record"]
    text, ready, hung = [], False, False
    while True:
        try:
            line = lines.get(timeout=max(TIME_BOUND_S - (time.perf_counter() - start), 0.0))
        except queue.Empty:
            hung = True
            break
        if line is None:  # the command ended
            break
        text.append(line)
        if explorer and "explorer ready in" in line:
            ready = True
            break
    if ready or hung:
        p.kill()
    p.wait()
    out = "".join(text)
    last = next((s for s in reversed(out.strip().splitlines()) if s.strip()), "")
    return dict(argv=argv, status=p.returncode, seconds=round(time.perf_counter() - start, 2), ready=ready, hung=hung,
                traceback="Traceback" in out, last=last[:300])


def outcome(case: dict, option: str, value: str) -> str:
    if case["traceback"]:
        return "traceback"
    if case["hung"]:
        return "hung"
    if case["status"] == 0 or case["ready"]:
        return "ran"
    if case["status"] == 2 and "error: " in case["last"]:  # argparse's own: "python -m app: error: ..."
        names = ALSO_NAMED.get(option, ()) + (option.lstrip("-"),)
        named = any(n in case["last"] for n in names) or bool(value.strip() and value[:40] in case["last"])
        return "refused" if named else "unnamed"
    return "other"


def main(argv=None) -> int:
    ap = study_parser("commands", __doc__)
    ap.add_argument("--quick", action="store_true", help=f"only the values {', '.join(map(repr, QUICK))} (CI)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "commands.json")
    ap.add_argument("--note", default="", help="what was run (a commit), kept in the file")
    ap.add_argument("--jobs", type=int, default=1, choices=range(1, 9), metavar="1..8",
                    help="cases run at once (default 1: a case's time then is its own)")
    args = ap.parse_args(argv)
    values = QUICK if args.quick else NUMBERS + WORDS
    counts, bad, wall = Counter(), [], time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        all_cases = cases(Path(tmp), values)
        with ThreadPoolExecutor(args.jobs) as pool:  # each case is a subprocess: threads only wait on them
            ran = pool.map(lambda c: run_case(c[3], Path(tmp)), all_cases)
            for i, ((command, option, value, case_argv), case) in enumerate(zip(all_cases, ran, strict=True), 1):
                kind = outcome(case, option, value)
                counts[kind] += 1
                if kind not in ("ran", "refused"):
                    bad.append({"command": command, "option": option, "outcome": kind, **case})
                print(f"{i}/{len(all_cases)} {kind:9s} {case['seconds']:6.1f} s  python -m {' '.join(case_argv)[:90]}",
                      file=sys.stderr, flush=True)
    record = {"command": "python -m bench commands " + " ".join(argv if argv is not None else sys.argv[1:]),
              "note": args.note, "machine": machine(), "values": list(values), "time_bound_s": TIME_BOUND_S,
              "jobs": args.jobs,
              "wall_s": round(time.perf_counter() - wall, 1), "cases": sum(counts.values()), "counts": dict(counts),
              "bad": bad}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(record, indent=1) + "\n")
    print(f"{record['cases']} cases: " + ", ".join(f"{counts.get(k, 0)} {k}" for k in
          ("ran", "refused", "unnamed", "traceback", "hung", "other")) + f" -> {args.out}")
    return 0
