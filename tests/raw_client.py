"""A raw websocket client of the explorer, speaking viser's wire format (msgpack) as bench/load.py does: for the
tests that send what no browser would (tests/test_message_guard.py, tests/test_security_upload_stream.py)."""

from __future__ import annotations

import asyncio
import time
from contextlib import asynccontextmanager

import msgspec
import viser
from websockets.asyncio.client import connect

# what a browser sends first: the server builds a session's scene once it knows the camera
CAMERA = dict(type="ViewerCameraMessage", wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, -3.4, 1.9), fov=1.3, near=0.01,
              far=1000.0, image_height=720, image_width=1280, look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0))


def encode(**fields) -> bytes:
    """One message of viser's wire format."""
    return msgspec.msgpack.encode(fields)


def new_session(app, before, deadline_s: float = 60.0):
    """The session built for this client: a new client id, not the last test's client still closing."""
    end = time.monotonic() + deadline_s
    while time.monotonic() < end:
        new = [s for cid, s in list(app.sessions.items()) if cid not in before]
        if new:
            return new[0]
        time.sleep(0.05)
    raise AssertionError("no session was built for the raw client")


def dial(app, **options):
    """websockets' connect to ``app`` (app.serve.server.App) as viser's client: awaited, or used with ``async
    with``; ``options`` go to connect."""
    return connect(f"ws://127.0.0.1:{app.port}", subprotocols=[f"viser-v{viser.__version__}"], max_size=None,
                   compression=None, open_timeout=60, **options)


async def introduce(app, ws, before):
    """Send the camera, as a browser does first; the session then built for ``ws`` (``before``: the sessions
    there were before it connected)."""
    await ws.send(encode(**CAMERA))
    return await asyncio.to_thread(new_session, app, before)


@asynccontextmanager
async def raw_session(app):
    """(websocket, session): a raw client of ``app`` whose session has been built."""
    before = set(app.sessions)
    # max_queue=None: this client reads nothing, so a bounded queue fills with frames, the server's close frame is
    # never read, and leaving waits out the 10 s close timeout
    async with dial(app, max_queue=None) as ws:
        yield ws, await introduce(app, ws, before)
