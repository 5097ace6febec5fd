"""A scenario file uploaded from a browser: size-capped, decoded, and through the parser
(the cap while its parts arrive is viser's side: app.serve.upload_cap).

Nothing here touches the file system: the name the browser reports is only shown, never opened, so an
upload cannot read or write a server path. The content goes through ``physics.Scenario.from_toml``,
the one parser every scenario file takes, so an upload is validated like a file on the command line.
"""

from __future__ import annotations

import re

import physics

MAX_UPLOAD_BYTES = 64_000  # a scenario is a few hundred bytes; the largest shipped one is under 2 kB
MAX_NAME = 80  # characters of the reported file name that are shown
_UNSAFE = re.compile(r"[^A-Za-z0-9 ._()+-]")  # what may be shown of a name (no markup, no path, no control)


def display_name(name: object) -> str:
    """The browser's file name made safe to show: its last path part, plain characters only, bounded."""
    text = str(name).replace("\\", "/").rsplit("/", 1)[-1]
    text = _UNSAFE.sub("_", text)[:MAX_NAME].strip()
    return text or "scenario.toml"


def parse_upload(name: str, content: bytes, max_bytes: int = MAX_UPLOAD_BYTES) -> physics.Scenario:
    """The scenario in an uploaded file, or ScenarioError naming what is wrong with it.

    ``content`` must be at most ``max_bytes`` bytes of UTF-8 TOML (a byte-order mark is allowed)."""
    shown = display_name(name)
    if not isinstance(content, (bytes, bytearray, memoryview)):
        raise physics.ScenarioError("upload", type(content).__name__, "must be the bytes of a file")
    size = len(bytes(content)) if isinstance(content, memoryview) else len(content)
    if size > max_bytes:
        raise physics.ScenarioError("upload", f"{shown} ({size} bytes)",
                                    f"must be at most {max_bytes} bytes (a scenario is a short TOML file)")
    if size == 0:
        raise physics.ScenarioError("upload", f"{shown} (empty)", "must be a TOML scenario file with [body], "
                                    "[initial] and [run]")
    try:
        text = bytes(content).decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise physics.ScenarioError("upload", shown, f"must be UTF-8 text (a TOML scenario file); byte {exc.start} "
                                    "is not") from None
    return physics.Scenario.from_toml(text)


__all__ = ["MAX_UPLOAD_BYTES", "display_name", "parse_upload"]
