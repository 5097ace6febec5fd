"""A raw viser client for class mode: a browser tab as far as the server can tell, without the browser.

It does what bench/load.py's client does (offers viser's subprotocol, sends the camera message a browser sends
first, counts the windows that turn its session's body, ``load._body_moved``) and two things more a class needs:
it answers the server's reads of its storage (``LocalStorageGetItemRequestMessage``) from a dict, as the page's
script would have filled it (``{"quasirigid.class": KEY}`` for the lecturer's link, nothing for a student's), and
it records the wall time (``time.time()``, comparable across processes of one machine) at which its session's
body shape is drawn anew, which a lecturer's edit of the body does (bench/classroom.py's latency). It can also
send any message (``send``), as a raw client can.
"""

from __future__ import annotations

import asyncio
import threading
import time

from .load import BODY_NODE, _camera_message

SHAPE_NODE = "/body/shape"  # the body's mesh under the session's root (app/scene/drawing.py)


def _encode(message: dict) -> bytes:
    import msgspec

    return msgspec.msgpack.encode(message)


def _messages(raw: bytes) -> list[dict]:
    """The messages of one viser window (zstd-compressed msgpack, viser.infra._infra._message_producer)."""
    import msgspec
    import zstandard

    size = int.from_bytes(raw[:8], "little")
    clen = int.from_bytes(raw[8:16], "little")
    inner = zstandard.ZstdDecompressor().decompress(raw[16:16 + clen], max_output_size=size)
    return list(msgspec.msgpack.decode(inner)["messages"])


class Tab:
    """One raw client's record: body updates per second, shape redraws' times, the storage it answers from."""

    def __init__(self, storage: dict[str, str] | None = None):
        self.storage = dict(storage or {})
        self.counts: list[int] = []  # body updates received in each second since the start
        self.shapes: list[float] = []  # time.time() of each window that drew the session's body shape anew
        self.errors: list[str] = []
        self.storage_reads = 0
        self.texts: list[str] = []  # the markdown the server put in this tab's panel, in order
        self.outbox: asyncio.Queue | None = None
        self.loop: asyncio.AbstractEventLoop | None = None

    def send(self, message: dict) -> None:
        """Send a message (a dict with its ``type``) from any thread."""
        self.loop.call_soon_threadsafe(self.outbox.put_nowait, _encode(message))

    def _take(self, raw: bytes, start: float) -> list[bytes]:
        """Count one window; the replies it asks for."""
        replies = []
        second = int(time.perf_counter() - start)
        while len(self.counts) <= second:
            self.counts.append(0)
        body = shape = False
        for m in _messages(raw):
            kind, name = m.get("type"), str(m.get("name", ""))
            if kind == "LocalStorageGetItemRequestMessage":
                self.storage_reads += 1
                replies.append(_encode(dict(type="LocalStorageGetItemResponseMessage", request_uuid=m["request_uuid"],
                                            value=self.storage.get(m["key"]), error=None)))
            elif kind == "GuiMarkdownMessage":
                self.texts.append(str(m.get("props", {}).get("_markdown", "")))
            elif name.startswith("/s") and name.endswith(BODY_NODE) and kind == "SetOrientationMessage":
                body = True
            elif name.startswith("/s") and name.endswith(SHAPE_NODE) and kind != "RemoveSceneNodeMessage":
                shape = True
        if body:
            self.counts[second] += 1
        if shape:
            self.shapes.append(time.time())
        return replies

    async def run(self, url: str, seconds: float) -> None:
        import viser
        from websockets.asyncio.client import connect

        self.loop, self.outbox = asyncio.get_running_loop(), asyncio.Queue()
        start = time.perf_counter()
        end = start + seconds
        try:
            async with connect(url, subprotocols=[f"viser-v{viser.__version__}"], max_size=None, compression=None,
                               open_timeout=60) as ws:
                await ws.send(_camera_message())

                async def sender():
                    while True:
                        await ws.send(await self.outbox.get())

                task = asyncio.create_task(sender())
                try:
                    while (left := end - time.perf_counter()) > 0:
                        try:
                            raw = await asyncio.wait_for(ws.recv(), timeout=left)
                        except TimeoutError:
                            break
                        if isinstance(raw, bytes):
                            for reply in self._take(raw, start):
                                await ws.send(reply)
                finally:
                    task.cancel()
        except Exception as exc:  # recorded and reported: a tab that cannot stay connected is a failure
            self.errors.append(f"{type(exc).__name__}: {exc}")


def run_tabs(url: str, tabs: list[Tab], seconds: float, stagger: float = 0.0) -> threading.Thread:
    """Run ``tabs`` for ``seconds`` in a background thread's event loop (``stagger`` s between their starts);
    returns the thread (join it)."""

    async def main():
        async def one(i, tab):
            await asyncio.sleep(i * stagger)
            await tab.run(url, seconds - i * stagger)

        await asyncio.gather(*(one(i, t) for i, t in enumerate(tabs)))

    thread = threading.Thread(target=lambda: asyncio.run(main()), name="class-tabs", daemon=True)
    thread.start()
    return thread


__all__ = ["SHAPE_NODE", "Tab", "run_tabs"]
