"""Argument parsers that several studies share, so ``python -m bench NAME --help`` reads alike for each."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from pathlib import Path

from app.argv import numbers_as_values

ROOT = Path(__file__).resolve().parent.parent


def study_parser(name: str, doc: str, prog: str | None = None) -> argparse.ArgumentParser:
    """A study's parser: its usage line names the command that runs it (``python -m bench NAME`` unless the
    study was started another way, ``prog``), its description the first paragraph of the module's docstring. A
    value that begins with a minus (``--minutes -1e308``) is the option's value, so the option's own check names it
    (app/argv.py), not argparse's "expected one argument"."""
    return numbers_as_values(argparse.ArgumentParser(prog=prog or f"python -m bench {name}",
                                                     description=doc.split("\n\n")[0]))


def bounded(kind: type, lo: float, hi: float) -> Callable[[str], float]:
    """An option's type: a number (``kind`` float) or a whole number (int) from ``lo`` to ``hi``. Anything else is
    refused by argparse as "argument --OPT: VALUE ... allowed: LO to HI", so a study never starts on a value it cannot
    finish (a minute count of -inf or 1e308, a million clients)."""
    word = "a whole number" if kind is int else "a number"
    allowed = f"{lo:d} to {hi:d}" if kind is int else f"{lo:g} to {hi:g}"

    def parse(text: str) -> float:
        shown = text if len(text) <= 40 else text[:37] + "..."
        try:
            value = kind(text)
        except (ValueError, OverflowError):
            raise argparse.ArgumentTypeError(f"{shown!r} is not {word}; allowed: {allowed}") from None
        if not (math.isfinite(value) and lo <= value <= hi):
            raise argparse.ArgumentTypeError(f"{shown!r} is outside what is allowed: {allowed}")
        return value

    parse.__name__ = word  # argparse's fallback message names the type by it
    return parse


def quick_out_img_parser(name: str, doc: str) -> argparse.ArgumentParser:
    """The options of the studies that write a CSV set and charts (work-precision, stability)."""
    ap = study_parser(name, doc)
    ap.add_argument("--quick", action="store_true", help="small sweeps and short horizons (CI: under a minute)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results", help="where the CSV and metadata go "
                    "(default bench/results)")
    ap.add_argument("--img", type=Path, default=ROOT / "docs" / "img", help="where the charts go (default docs/img)")
    return ap
