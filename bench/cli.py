"""Argument parsers that several studies share, so ``python -m bench NAME --help`` reads alike for each."""

from __future__ import annotations

import argparse
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def study_parser(name: str, doc: str, prog: str | None = None) -> argparse.ArgumentParser:
    """A study's parser: its usage line names the command that runs it (``python -m bench NAME`` unless the
    study was started another way, ``prog``), its description the first paragraph of the module's docstring."""
    return argparse.ArgumentParser(prog=prog or f"python -m bench {name}", description=doc.split("\n\n")[0])


def quick_out_img_parser(name: str, doc: str) -> argparse.ArgumentParser:
    """The options of the studies that write a CSV set and charts (work-precision, stability)."""
    ap = study_parser(name, doc)
    ap.add_argument("--quick", action="store_true", help="small sweeps and short horizons (CI: under a minute)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results", help="where the CSV and metadata go "
                    "(default bench/results)")
    ap.add_argument("--img", type=Path, default=ROOT / "docs" / "img", help="where the charts go (default docs/img)")
    return ap
