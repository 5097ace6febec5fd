"""``python -m app record [SCENARIO.toml] --seconds N --out demo.html``: write a replay of the scene (app.replay.record)
that any browser plays from the file, with no Python and no network. Bad input gets one line naming the
parameter, and exit status 2."""

from __future__ import annotations

import argparse
import contextlib
import io
import sys
import time
from pathlib import Path

from ..argv import numbers_as_values
from .record import MAX_SECONDS, REPLAY_FPS

DEFAULT_SECONDS = 20.0
TITLE_CHARS = 100  # a title line, not a paragraph


class _Refused(Exception):
    """A bad argument: its one-line message is printed, exit 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # argparse prints its usage too: one line is enough here
        raise _Refused(message)


def parse(argv: list[str] | None = None) -> argparse.Namespace:
    ap = numbers_as_values(_Parser(
        prog="python -m app record", description="Write one self-contained HTML file that replays the explorer's 3-D "
        "scene in any browser (no Python, no network), with the plots and the scenario."))
    ap.add_argument("scenario", nargs="?", metavar="SCENARIO.toml",
                    help="the scenario to play (default: the explorer's default scene)")
    ap.add_argument("--seconds", default=str(DEFAULT_SECONDS),
                    help=f"played seconds (default {DEFAULT_SECONDS:g}; 1/{REPLAY_FPS:g}, one frame, to "
                    f"{MAX_SECONDS:g})")
    ap.add_argument("--out", default="replay.html", help="the HTML file to write (default replay.html)")
    ap.add_argument("--warp", default=None, help="simulated seconds per played second (default: the explorer's "
                    "choice for the scene, 1x for the default scene)")
    return ap.parse_args(argv)


def _title(path: Path, text: str) -> str:
    """The file's name and its first comment line, which says what the scene is."""
    first = next((line.lstrip("#").strip() for line in text.splitlines() if line.startswith("#")), "")
    first = first.removeprefix("preset:").strip()  # a preset file's title line
    title = f"{path.name}: {first}" if first else path.name
    return title if len(title) <= TITLE_CHARS else title[: TITLE_CHARS - 3] + "..."


def _out_path(value: str) -> Path:
    if not value.strip():
        raise _Refused(f"--out {value!r} names no file; give a file name such as demo.html")
    out = Path(value)
    if out.is_dir():
        raise _Refused(f"--out {value!r} is a directory; give a file name such as demo.html")
    if not out.parent.is_dir():
        raise _Refused(f"--out {value!r}: folder {str(out.parent)!r} does not exist; give a file in an existing "
                       "folder")
    return out


def main(argv: list[str] | None = None) -> int:
    try:
        return _main(argv)
    except _Refused as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2


def _main(argv: list[str] | None) -> int:
    args = parse(argv)
    from ..engine import presets
    from .record import check_seconds

    try:
        seconds = check_seconds(args.seconds)
    except ValueError as exc:
        raise _Refused(str(exc)) from None
    warp = None
    if args.warp is not None:
        try:
            warp = float(args.warp)
        except ValueError:
            raise _Refused(f"--warp {args.warp!r} is not a number; allowed: {presets.WARP_MIN:g} to "
                           f"{presets.WARP_MAX:g}") from None
        if not presets.WARP_MIN <= warp <= presets.WARP_MAX:
            raise _Refused(f"--warp {args.warp!r} is out of range; allowed: {presets.WARP_MIN:g} to "
                           f"{presets.WARP_MAX:g}")
    out = _out_path(args.out)
    import physics

    from .record import record

    try:
        if args.scenario:
            path = Path(args.scenario)
            scenario = physics.Scenario.load(path)
            text = path.read_text(encoding="utf-8-sig")
            title = _title(path, text)
        else:
            scenario, text, title = None, None, presets.DEFAULT
        print(f"recording {seconds:g} s of {title} at {REPLAY_FPS:g} frames/s...", file=sys.stderr, flush=True)
        start = time.perf_counter()
        with contextlib.redirect_stdout(io.StringIO()):  # viser's banner: the recording server serves no one
            replay = record(scenario, seconds, title=title, toml_text=text, warp=warp)
    except physics.ScenarioError as exc:
        raise _Refused(str(exc)) from None
    except ValueError as exc:  # the size cap
        raise _Refused(str(exc)) from None
    try:
        out.write_text(replay.html, encoding="utf-8")
    except OSError as exc:
        raise _Refused(f"--out {args.out!r} cannot be written ({exc.strerror})") from None
    print(f"wrote {out} ({replay.size} bytes): {replay.frames} frames, {replay.seconds:g} s played at "
          f"{replay.warp:.3g}x (t = 0 to {replay.simulated:.4g} s), in {time.perf_counter() - start:.1f} s; "
          "open it in any browser", flush=True)
    return 0
