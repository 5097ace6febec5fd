"""Command line: ``python -m physics run|info [SCENARIO.toml]``.

Bad input exits with status 2 and one line naming the parameter; a numerical fault exits with 1.
No traceback reaches the user.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings
from pathlib import Path

from .defaults import default_scenario
from .derived import derived
from .errors import IntegrationFault, ScenarioError
from .params import FIDELITIES, METHODS
from .scenario import Scenario
from .simulate import simulate


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, status 2, like every other bad input
        self.exit(2, f"error: {message} (see 'python -m physics --help')\n")


def _parser() -> argparse.ArgumentParser:
    ap = _Parser(prog="python -m physics", description="Quasirigid physics: run a scenario or show derived values.")
    sub = ap.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="simulate a scenario (the built-in default when none is given)")
    run.add_argument("scenario", nargs="?", help="scenario TOML file")
    run.add_argument("--out", help="write the trajectory as CSV to this file")
    run.add_argument("--fidelity", choices=FIDELITIES, help="override [run] fidelity")
    run.add_argument("--method", choices=METHODS, help="override [run] method")
    info = sub.add_parser("info", help="print derived quantities, one 'name = value' per line")
    info.add_argument("scenario", nargs="?", help="scenario TOML file")
    for p in (run, info):
        p.error = ap.error  # subparsers get the same one-line errors
    return ap


class _Progress:
    """Shows how far a long integration has got: in place on a terminal, every 10% in a log."""

    def __init__(self):
        self.start = time.perf_counter()
        self.tty = sys.stderr.isatty()
        self.last = 0.0

    def __call__(self, fraction: float) -> None:
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


def _fmt(v) -> str:
    if isinstance(v, float):
        return "inf" if math.isinf(v) else f"{v:.17g}"
    return str(v)


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            sc = _load(args.scenario)
            if args.command == "info":
                for k, v in derived(sc).items():
                    print(f"{k} = {_fmt(v)}")
                return 0
            print(f"scenario: {args.scenario or 'built-in default'}", flush=True)
            tr = simulate(sc, fidelity=args.fidelity, method=args.method, progress=_Progress())
        except ScenarioError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
        except IntegrationFault as exc:
            print(f"error: the integration stopped: {exc}", file=sys.stderr)
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
    if args.out:
        try:
            tr.to_csv(Path(args.out))
        except OSError as exc:
            print(f"error: --out = {args.out!r}: cannot be written ({exc.strerror})", file=sys.stderr)
            return 2
        print(f"wrote {len(tr)} rows to {args.out}")
    return 0
