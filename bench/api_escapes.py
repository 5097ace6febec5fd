"""``python -m bench api-escapes``: hostile arguments to the public API, counting the errors that escape it.

The API promises two error types for bad input and failed runs, ``ScenarioError`` and ``IntegrationFault``
(issue 24 point 3). This study calls each public entry point with each hostile value (wrong types, an object whose
every text conversion raises, and numbers across magnitudes, 5e-324 to 1e308, nan and inf) and counts the calls
that end in any other exception ("escapes"), in a warning-free run with a time bound per call.

``--root DIR`` imports ``physics`` from another tree (a ``git worktree`` of an older commit) to count before a change;
an entry point that tree lacks is counted as absent, not as an escape. Writes a JSON file (machine, command, counts,
each escape's call, value and exception).
"""

from __future__ import annotations

import json
import os
import signal
import sys
import tempfile
import warnings
from collections import Counter
from pathlib import Path

from bench.cli import study_parser

from .machine import machine

ROOT = Path(__file__).resolve().parents[1]
TIME_BOUND_S = 20  # per call: a hostile value that makes a run go on is counted, not waited for


class Unshowable:
    """An object whose every text or number conversion raises."""

    def __repr__(self):
        raise KeyError("repr")

    def __str__(self):
        raise KeyError("str")

    def __format__(self, spec):
        raise KeyError("format")

    def __float__(self):
        raise KeyError("float")


HOSTILE = {
    "unshowable": Unshowable(), "dict": {"a": 1}, "text": "x", "None": None, "list": [1, 2], "int 3": 3,
    "nan": float("nan"), "inf": float("inf"), "-inf": float("-inf"), "5e-324": 5e-324, "1e308": 1e308,
    "-1e308": -1e308, "0": 0.0, "-1": -1.0, "10**400": 10**400, "bytes": b"\x00\xff", "object": object(),
}


def calls(physics) -> dict:
    """Entry point name -> f(scenario, value). Each passes the value where a caller could."""
    return {
        "derived": lambda sc, v: physics.derived(v),
        "choose_fidelity": lambda sc, v: physics.choose_fidelity(v),
        "numeric_keys": lambda sc, v: physics.numeric_keys(v),
        "simulate": lambda sc, v: physics.simulate(v),
        "simulate progress": lambda sc, v: physics.simulate(sc, progress=v),
        "simulate method": lambda sc, v: physics.simulate(sc, method=v),
        "simulate fidelity": lambda sc, v: physics.simulate(sc, fidelity=v),
        "axis_values": lambda sc, v: physics.axis_values(v),
        "axis_values count": lambda sc, v: physics.axis_values((0.0, 1.0, v)),
        "sweep vary": lambda sc, v: physics.sweep(sc, v, executor="serial"),
        "sweep spec": lambda sc, v: physics.sweep(sc, {"mass.chi": v}, executor="serial"),
        "sweep metric": lambda sc, v: physics.sweep(sc, {"mass.chi": "1:2:2"}, v, executor="serial"),
        "sweep progress": lambda sc, v: physics.sweep(sc, {"mass.chi": "1:2:2"}, executor="serial", progress=v),
        "sweep workers": lambda sc, v: physics.sweep(sc, {"mass.chi": "1:2:2"}, executor="serial", workers=v),
        "sweep executor": lambda sc, v: physics.sweep(sc, {"mass.chi": "1:2:2"}, executor=v),
        "resolve_key": lambda sc, v: physics.resolve_key(sc, v),
        "point_scenario": lambda sc, v: physics.point_scenario(sc, {"mass.chi": v}),
        "check_point": lambda sc, v: physics.check_point(sc, v),
        "with_values chi": lambda sc, v: sc.with_values(**{"mass.chi": v}),
        "with_values t_end": lambda sc, v: sc.with_values(**{"run.t_end": v}),
        "from_dict": lambda sc, v: physics.Scenario.from_dict(v),
        "from_dict body.A": lambda sc, v: physics.Scenario.from_dict({"body": {"A": v, "C": 1.5, "M": 1.0}}),
        "end_state": lambda sc, v: physics.end_state(v),
        "edit_dict key": lambda sc, v: physics.edit_dict(sc.to_dict(), v, 1.0),
        "edit_dict value": lambda sc, v: physics.edit_dict(sc.to_dict(), "mass.m", v),
    }


class TookTooLong(Exception):
    pass


def _alarm(_signum, _frame):
    raise TookTooLong


def probe(root: Path) -> dict:
    if root != ROOT:  # another tree's physics, in place of this one's (a study run on its own, never in tests)
        sys.path.insert(0, str(root))
        for name in [m for m in sys.modules if m == "physics" or m.startswith("physics.")]:
            del sys.modules[name]
    import physics

    documented = tuple(t for t in (getattr(physics, "ScenarioError", None), getattr(physics, "IntegrationFault", None))
                       if t is not None)
    sc = physics.Scenario.load(root / "assets" / "scenarios" / "oblate_settling.toml").with_values(
        **{"run.t_end": 0.1})
    counts, escapes, absent = Counter(), [], []
    signal.signal(signal.SIGALRM, _alarm)
    cwd = os.getcwd()
    with tempfile.TemporaryDirectory() as tmp:
        os.chdir(tmp)  # a sweep told to write "x" writes it here
        try:
            for name, call in calls(physics).items():
                for label, value in HOSTILE.items():
                    counts["calls"] += 1
                    signal.alarm(TIME_BOUND_S)
                    try:
                        with warnings.catch_warnings():
                            warnings.simplefilter("ignore")
                            call(sc, value)
                        counts["accepted"] += 1
                    except TookTooLong:
                        counts["over the time bound"] += 1
                    except documented:
                        counts["documented error"] += 1
                    except AttributeError as exc:
                        if "module 'physics' has no attribute" in str(exc):
                            counts["absent"] += 1
                            absent.append(name)
                        else:
                            counts["escapes"] += 1
                            escapes.append({"call": name, "value": label, "error": f"AttributeError: {exc}"[:200]})
                    except Exception as exc:  # noqa: BLE001 - what the study counts
                        counts["escapes"] += 1
                        try:
                            text = f"{type(exc).__name__}: {exc}"
                        except Exception:  # noqa: BLE001
                            text = type(exc).__name__
                        escapes.append({"call": name, "value": label, "error": text[:200]})
                    finally:
                        signal.alarm(0)
        finally:
            os.chdir(cwd)
    return {"counts": dict(counts), "absent": sorted(set(absent)), "escapes": escapes}


def main(argv=None) -> int:
    ap = study_parser("api-escapes", __doc__)
    ap.add_argument("--root", type=Path, default=ROOT, help="the tree whose physics is probed (default: this one)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "api_escapes.json")
    ap.add_argument("--note", default="", help="what was probed (a commit), kept in the file")
    args = ap.parse_args(argv)
    result = probe(args.root.resolve())
    record = {"command": "python -m bench api-escapes " + " ".join(argv if argv is not None else sys.argv[1:]),
              "note": args.note, "machine": machine(), "hostile_values": list(HOSTILE),
              "time_bound_s": TIME_BOUND_S, **result}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(record, indent=1) + "\n")
    c = result["counts"]
    print(f"{c.get('calls', 0)} calls: {c.get('escapes', 0)} escapes, {c.get('documented error', 0)} documented "
          f"errors, {c.get('accepted', 0)} accepted, {c.get('over the time bound', 0)} over {TIME_BOUND_S} s, "
          f"{c.get('absent', 0)} absent -> {args.out}")
    return 0
