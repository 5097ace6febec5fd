"""``python -m bench work-precision [--quick]``, ``python -m bench stability [--quick]`` and
``python -m bench figures [...]`` (bench/figures.py, its own options), ``python -m bench soak --minutes N``
and ``python -m bench load --clients 10 --minutes 5`` (bench/soak.py, bench/load.py);
``python -m bench sweep SCENARIO.toml --vary KEY=SPEC ...`` (bench/sweep.py, its own options)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["figures"]:
        from .figures import main as figures

        return figures(argv[1:])
    if argv[:1] == ["sweep"]:
        from .sweep import main as sweep

        return sweep(argv[1:])
    if argv[:1] in (["soak"], ["load"]):  # serve the explorer to websocket clients (bench/soak.py, bench/load.py)
        from importlib import import_module

        return import_module(f".{argv[0]}", __package__).main(argv[1:])
    ap = argparse.ArgumentParser(prog="python -m bench", description=__doc__)
    ap.add_argument("command", choices=("work-precision", "stability", "figures", "sweep"))
    ap.add_argument("--quick", action="store_true", help="small sweeps and short horizons (CI: under a minute)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results", help="where the CSV and metadata go")
    ap.add_argument("--img", type=Path, default=ROOT / "docs" / "img", help="where the charts go")
    args = ap.parse_args(argv)
    if args.command == "work-precision":
        from .work_precision import main as run
    else:
        from .stability import main as run
    run(args.quick, args.out, args.img)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
