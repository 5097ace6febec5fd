"""Command line: ``python -m physics run|info [SCENARIO.toml]``, ``python -m physics design SCENARIO.toml --vary
KEY=LO:HI ...``.

Bad input exits with status 2 and one line naming the parameter; a numerical fault exits with 1 and
one line; Ctrl-C stops within a fraction of a second ("interrupted", status 130, physics/__main__.py).
No traceback reaches the user.
"""

from __future__ import annotations

import argparse
import math
import os
import signal
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from physics.core.blame import guarded
from physics.core.errors import IntegrationFault, NumericalFault, ScenarioError
from physics.info_text import as_json, text_lines
from physics.scenario.defaults import default_scenario
from physics.scenario.params import FIDELITIES, METHODS
from physics.scenario.scenario import Scenario
from physics.stepping.simulate import simulate
from physics.studies.design import BUDGET, OBJECTIVES
from physics.studies.design_cli import run_design
from physics.systems.derived import derived

NUMPY_FLOATING = r"(invalid value|divide by zero|overflow|underflow) encountered"  # numpy's floating-point warnings


class _Parser(argparse.ArgumentParser):
    def parse_args(self, args=None, namespace=None):
        return super().parse_args(_attached(sys.argv[1:] if args is None else list(args)), namespace)

    def error(self, message):  # one line, status 2, like every other bad input
        # an argument may hold a newline or be huge: escape control characters and cut what is echoed
        text = "".join(c if c.isprintable() else repr(c)[1:-1] for c in message)
        text = text if len(text) <= 300 else text[:297] + "..."
        self.exit(2, f"error: {text} (see 'python -m physics --help')\n")


def _attached(argv: list[str]) -> list[str]:
    """``--opt -1e-3`` as ``--opt=-1e-3``: argparse takes only ``-1`` and ``-.5`` for negative numbers, so a value
    such as -1e308, -5e-324 or -inf after an option was read as an option of its own, and the error ("expected one
    argument") named neither the value nor what is allowed. Attached, the value reaches the option's own check."""
    out: list[str] = []
    for word in argv:
        if out and out[-1].startswith("--") and "=" not in out[-1] and word.startswith("-") and _number(word):
            out[-1] = f"{out[-1]}={word}"
        else:
            out.append(word)
    return out


def _writable(option: str, value: str) -> None:
    """A file the command is to write, checked before its run or design: a long run ended to be told that the
    name was a folder, or in a folder that does not exist, and nothing of it was kept. (A full disk is still
    found only when writing.)"""
    path = Path(value)
    if not value.strip():
        why = "names no file; give a file name"
    elif path.is_dir():
        why = "is a folder; give a file name in it"
    elif not path.parent.is_dir():
        why = f"its folder {str(path.parent)!r} does not exist; give a file in an existing folder"
    elif not os.access(path if path.exists() else path.parent, os.W_OK):
        why = "cannot be written (no permission)"
    else:
        return
    raise ScenarioError(option, value, why)


def _number(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def _parser() -> argparse.ArgumentParser:
    ap = _Parser(prog="python -m physics", description="Quasirigid physics: run a scenario or show derived values.")
    sub = ap.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="simulate a scenario (the built-in default when none is given)")
    run.add_argument("scenario", nargs="?", help="scenario TOML file")
    run.add_argument("--out", help="write the trajectory as CSV to this file")
    run.add_argument("--fidelity", choices=FIDELITIES, help="override [run] fidelity")
    run.add_argument("--method", choices=METHODS, help="override [run] method")
    info = sub.add_parser("info", help="print derived quantities, one 'name = value unit  meaning' per line")
    info.add_argument("scenario", nargs="?", help="scenario TOML file")
    info.add_argument("--json", action="store_true", help="print them as JSON, every number to full precision")
    des = sub.add_parser("design", help="find the parameters within bounds that make a metric best (a damper's "
                         "design)")
    des.add_argument("scenario", help="scenario TOML file")
    des.add_argument("--vary", action="append", required=True, metavar="KEY=LO:HI",
                     help="a parameter and its bounds, e.g. k=10:80 or pendulum.c_d=1:40 (one to four)")
    des.add_argument("--objective", default="decay_time", choices=tuple(OBJECTIVES),
                     help="the metric to make best (decay_time: smallest positive; energy_dissipated: largest; "
                          "others: smallest)")
    des.add_argument("--budget", type=int, default=BUDGET, help=f"most runs (default {BUDGET})")
    des.add_argument("--accuracy", type=float, help="theta accuracy (rad) auto's points run at (default: from "
                                                    "the objective)")
    des.add_argument("--workers", type=int, help="local processes (default: all cores)")
    des.add_argument("--dask", metavar="ADDRESS", help="run the points on this dask.distributed scheduler")
    des.add_argument("--out", help="write every run of the design as CSV to this file")
    des.add_argument("--save", help="write the optimum as a scenario TOML file")
    des.add_argument("--json", action="store_true", help="print the result as JSON")
    for p in (run, info, des):
        p.error = ap.error  # subparsers get the same one-line errors
    return ap


class _Interrupt:
    """SIGINT handler. Raising KeyboardInterrupt while a compiled (numba) call returns makes that call fail
    with SystemError, so during a run the handler only notes the request and the progress callback, which
    simulate calls between compiled calls (each a fraction of a second), raises it. Elsewhere, or on a
    second Ctrl-C, or when progress has not been reported for a second (Python code is running: raising
    there is safe), it raises at once."""

    def __init__(self):
        self.deferred = False
        self.requested = False
        self.seen = -math.inf  # when the progress callback last ran (perf_counter seconds)

    def __call__(self, signum, frame):
        if self.deferred and not self.requested and time.perf_counter() - self.seen < 1.0:
            self.requested = True
            return
        raise KeyboardInterrupt


class _Progress:
    """Shows how far a long integration has got: in place on a terminal, every 10% in a log; raises
    KeyboardInterrupt between compiled calls once Ctrl-C was pressed."""

    def __init__(self, interrupt: _Interrupt | None = None):
        self.start = time.perf_counter()
        self.tty = sys.stderr.isatty()
        self.last = 0.0
        self.interrupt = interrupt

    def __call__(self, fraction: float) -> None:
        if self.interrupt is not None:
            if self.interrupt.requested:
                raise KeyboardInterrupt
            self.interrupt.seen = time.perf_counter()
        if time.perf_counter() - self.start < 1.0:
            return  # short runs stay quiet
        if self.tty:
            end = "\n" if fraction >= 1 else ""
            print(f"\rintegrating: {100 * fraction:5.1f}%", end=end, file=sys.stderr, flush=True)
        elif fraction - self.last >= 0.1 or fraction >= 1:
            self.last = fraction
            print(f"integrating: {100 * fraction:.0f}%", file=sys.stderr, flush=True)


def _load(path: str | None) -> Scenario:
    return default_scenario() if path is None else Scenario.load(path)


def _run(sc: Scenario, args):
    """simulate, with Ctrl-C deferred to the moments between compiled calls (main thread only)."""
    interrupt = _Interrupt()
    try:
        previous = signal.signal(signal.SIGINT, interrupt)
    except ValueError:  # not the main thread (an embedding program): its own handling applies
        return simulate(sc, fidelity=args.fidelity, method=args.method, progress=_Progress())
    interrupt.deferred = True
    try:
        return simulate(sc, fidelity=args.fidelity, method=args.method, progress=_Progress(interrupt))
    finally:
        signal.signal(signal.SIGINT, previous)
        if interrupt.requested:
            raise KeyboardInterrupt


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    # numpy's overflow and divide warnings say nothing to a user: the values printed show inf or nan. errstate
    # holds in this thread only; a design's refinements run in threads of their own, so their numpy warnings
    # (14 lines of "invalid value encountered in divide" over one design) are filtered here, for every thread
    with warnings.catch_warnings(record=True) as caught, np.errstate(all="ignore"):
        warnings.simplefilter("always")
        warnings.filterwarnings("ignore", NUMPY_FLOATING, RuntimeWarning)
        try:
            sc = _load(args.scenario)
            for option in ("out", "save"):  # before the run, which a name that cannot be written would waste
                if (value := getattr(args, option, None)) is not None:
                    _writable(f"--{option}", value)
            if args.command == "design":
                return run_design(sc, args)
            if args.command == "info":
                with guarded(sc, "computing the derived quantities"):
                    values = derived(sc)
                print(as_json(values, sc.system) if args.json else "\n".join(text_lines(values, sc.system)))
                return 0
            print(f"scenario: {args.scenario or 'built-in default'}", flush=True)
            tr = _run(sc, args)
        except ScenarioError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
        except NumericalFault as exc:  # arithmetic that failed on accepted input
            print(f"error: numerical fault: {exc}", file=sys.stderr)
            return 1
        except IntegrationFault as exc:
            print(f"error: the integration stopped: {exc}", file=sys.stderr)
            return 1
        except MemoryError:
            print("error: out of memory (lower run.samples or run.t_end)", file=sys.stderr)
            return 1
        finally:
            for w in caught:
                print(f"warning: {w.message}", file=sys.stderr)
    inf = tr.info
    print(f"model: {inf['model']} ({inf['reason']})")
    print(f"method: {inf['method']}, {inf['steps']} steps, {inf['nfev']} evaluations, {inf['wall_s']:.3g} s")
    print(f"ended: {inf['stop_reason']} at t = {inf['t_stop']:.17g}")
    print(f"theta: {tr.theta[0]:.6g} -> {tr.theta[-1]:.6g} rad;  |K|: {tr.K[0]:.6g} -> {tr.K[-1]:.6g};  "
          f"E: {tr.E[0]:.6g} -> {tr.E[-1]:.6g}")
    if args.out is not None:
        try:
            tr.to_csv(Path(args.out))
        except OSError as exc:
            print(f"error: --out = {args.out!r}: cannot be written ({exc.strerror})", file=sys.stderr)
            return 2
        print(f"wrote {len(tr)} rows to {args.out}")
    return 0
