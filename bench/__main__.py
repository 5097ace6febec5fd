"""``python -m bench STUDY [options]``: one subcommand per study; ``python -m bench STUDY --help`` gives the
study's own options (each module parses them in its ``main(argv) -> int``)."""

from __future__ import annotations

import argparse
import sys
from importlib import import_module

# subcommand -> (module in bench/, one line for --help). Modules are imported only when their study runs (or
# shows its help): the explorer benchmarks pull in playwright and the app, the studies scipy and MuJoCo.
STUDIES = {
    "work-precision": ("work_precision", "error against cost for every method on problems P1-P4 (issue 5)"),
    "stability": ("stability", "where methods fail: stiffness, drift, validity, braking (issue 5)"),
    "figures": ("figures", "the papers' figures redrawn by the project's code, and the explorer's figure presets"),
    "sweep": ("sweep", "a parameter sweep of a scenario file, or --scaling: wall time against workers"),
    "soak": ("soak", "the explorer served for N minutes: the server's memory growth"),
    "load": ("load", "the explorer served to several websocket clients: updates per second, memory"),
    "refusals": ("refusals", "extreme-value edits of the shipped scenarios: refusals that do not name their key"),
    "class": ("classroom", "class mode: N student tabs following the lecturer's run: updates/s, memory, edit latency"),
    "api-escapes": ("api_escapes", "hostile arguments to every public API entry point: errors of undocumented types"),
    "hostile": ("hostile", "hostile values from a raw websocket client to every control: server tracebacks, memory"),
    "commands": ("commands", "hostile values to every option of python -m physics design, python -m app record and "
                             "python -m app, each run as a subprocess: tracebacks, hangs, unnamed refusals"),
    "explorer-rates": ("explorer_rates", "frames per second, achieved warp and slider latency of the explorer"),
    "fidelity": ("fidelity", "cheaper fidelities' actual theta error against their stated estimate (issue 15)"),
    "corrections": ("corrections", "the evidence figures of docs/corrections.md, recomputed (issue 17)"),
    "challenge": ("challenge", "the braking challenge's scripted player against the optimal law, every level"),
    "design": ("design", "a damper's design against the 20 x 20 grid over the same bounds: runs, wall time, optimum"),
    "pendulum-hardening": ("pendulum_hardening", "the pendulum's averaged model with a detuning that follows the bob's "
                                                 "swing, against the full model (issue 23)"),
    "pendulum-ceiling": ("pendulum_ceiling", "the most of the oracle's cheap runs auto could take with the pendulum's "
                                             "estimate as built, its safety factors fitted (issue 23)"),
    "pendulum-prediction": ("pendulum_prediction", "the pendulum's nonlinear error predicted by coefficients that "
                                                   "follow the spin-up, swing and arm, against the measured error "
                                                   "(issue 23)"),
    "explorer-startup": ("explorer_startup", "time from `python -m app` to the scene drawn in chromium (--cold: "
                                             "first start)"),
}


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="python -m bench", description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="study", metavar="STUDY", required=True)
    for name, (_module, line) in STUDIES.items():
        # add_help=False and no arguments of its own: everything after the name, --help included, goes to the
        # study's parser, so each study's options are written once, in its module
        sub.add_parser(name, help=line, description=line, add_help=False)
    return ap


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    args, rest = parser().parse_known_args(argv)
    return import_module(f".{STUDIES[args.study][0]}", __package__).main(rest)


if __name__ == "__main__":
    raise SystemExit(main())
