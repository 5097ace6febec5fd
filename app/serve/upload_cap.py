"""An upload's size cap, held while its parts arrive over the tab's websocket rather than after viser has buffered
them all. It reaches into viser's connection (its upload handlers and buffers), so it lives with the server;
what an upload may be is app.engine.upload's."""

from __future__ import annotations

from viser import _messages as msgs

from ..engine.upload import MAX_UPLOAD_BYTES, display_name
from .handlers import put_in_front

# the largest websocket message a tab's client may send (bytes). viser's page sends an upload in parts of
# 512 kB and every other message it sends is small; viser lets a message be 50 MB, which websockets reads whole
# before anyone sees it (a raw client's one 40 MB part: +83 MB). A message over this closes the connection at
# its header, before its body is read (websockets' max_size; close code 1009).
MAX_MESSAGE_BYTES = 1 << 20


def cap_streamed_uploads(gui, refused, max_bytes: int = MAX_UPLOAD_BYTES) -> None:
    """Enforce ``max_bytes`` while an upload's parts arrive, not after viser has buffered them all (a raw
    client sent 600 MB to a 64 kB cap: the server grew by 600 MB before the check). An announced size over
    the cap is refused at the start; a client that lies about its size is cut off at the part that
    crosses the cap, and viser's buffer for it is dropped. ``refused(message)`` tells the user.

    Wraps the two upload handlers viser 1.1 registers on this tab's connection (``gui`` is the tab's
    ``client.gui``); a viser without them is left as it is."""
    ws = getattr(gui, "_websock_interface", None)
    handlers = getattr(ws, "_incoming_handlers", None)
    states = getattr(gui, "_current_file_upload_states", None)
    start_cls, part_cls = getattr(msgs, "FileTransferStartUpload", None), getattr(msgs, "FileTransferPart", None)
    if handlers is None or states is None or start_cls is None or part_cls is None:
        return
    received: dict[str, int] = {}  # transfer -> bytes so far, for the transfers that were let start

    def wrap(cls, check):
        def make(inner):
            def handler(client_id, message):
                if check(message):
                    for cb in inner:
                        cb(client_id, message)

            return handler

        put_in_front(handlers, cls, make)

    def start(message) -> bool:
        size = int(message.size_bytes)
        if size > max_bytes:
            refused(f"upload {display_name(message.filename)} ({size} bytes) must be at most {max_bytes} bytes "
                    "(a scenario is a short TOML file)")
            return False
        if size < 0 or int(message.part_count) < 0:
            refused(f"upload {display_name(message.filename)} announced {size} bytes in {message.part_count} parts; "
                    "both must be 0 or more")
            return False
        if len(received) > 16:  # a client opening transfers it never finishes: keep the newest few, here and in viser
            oldest = next(iter(received))
            del received[oldest]
            states.pop(oldest, None)
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
