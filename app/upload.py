"""A scenario file uploaded from a browser: size-capped, decoded, and through the parser.

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


def cap_streamed_uploads(gui, refused, max_bytes: int = MAX_UPLOAD_BYTES) -> None:
    """Enforce ``max_bytes`` while an upload's parts arrive, not after viser has buffered them all (a raw
    client sent 600 MB to a 64 kB cap: the server grew by 600 MB before the check). An announced size over
    the cap is refused at the start; a client that lies about its size is cut off at the part that
    crosses the cap, and viser's buffer for it is dropped. ``refused(message)`` tells the user.

    Wraps the two upload handlers viser 1.1 registers on this tab's connection (``gui`` is the tab's
    ``client.gui``); a viser without them is left as it is."""
    from viser import _messages as msgs

    ws = getattr(gui, "_websock_interface", None)
    handlers = getattr(ws, "_incoming_handlers", None)
    states = getattr(gui, "_current_file_upload_states", None)
    start_cls, part_cls = getattr(msgs, "FileTransferStartUpload", None), getattr(msgs, "FileTransferPart", None)
    if handlers is None or states is None or start_cls is None or part_cls is None:
        return
    received: dict[str, int] = {}  # transfer -> bytes so far, for the transfers that were let start

    def wrap(cls, check):
        inner = list(handlers.get(cls, []))

        def handler(client_id, message):
            if check(message):
                for cb in inner:
                    cb(client_id, message)

        handlers[cls] = [handler]

    def start(message) -> bool:
        size = int(message.size_bytes)
        if size > max_bytes:
            refused(f"upload {display_name(message.filename)} ({size} bytes) must be at most {max_bytes} bytes "
                    "(a scenario is a short TOML file)")
            return False
        if len(received) > 16:  # a client opening transfers it never finishes: keep the newest few
            received.pop(next(iter(received)))
        received[message.transfer_uuid] = 0
        return True

    def part(message) -> bool:
        uuid = message.transfer_uuid
        if uuid not in received:
            return False  # refused at its start, or cut off: nothing of it is buffered
        received[uuid] += len(message.content)
        if received[uuid] > max_bytes:
            del received[uuid]
            states.pop(uuid, None)
            refused(f"upload sent more than {max_bytes} bytes (more than it announced); dropped")
            return False
        return True

    wrap(start_cls, start)
    wrap(part_cls, part)


__all__ = ["MAX_UPLOAD_BYTES", "cap_streamed_uploads", "display_name", "parse_upload"]
