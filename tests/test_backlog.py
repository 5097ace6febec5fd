"""A tab's loop does not publish a frame over one viser has not sent yet (app.serve.backlog): on a real viser
server with one raw websocket client, the last frame counts as unsent while viser's sender cannot take it (inside
``client.atomic()``, which holds the sender back) and as sent once the sender has moved past it. A change the user
asked for is still shown at once while the sender is behind: its first frame replaces the unsent one."""

from __future__ import annotations

import asyncio
import threading
import time

import pytest
import viser
from raw_client import CAMERA, encode, raw_session
from websockets.asyncio.client import connect

from app.engine import presets
from app.serve.backlog import Backlog


def _client_reading(port: int, stop: threading.Event) -> threading.Thread:
    async def run():
        async with connect(f"ws://127.0.0.1:{port}", subprotocols=[f"viser-v{viser.__version__}"], max_size=None,
                           compression=None, open_timeout=30) as ws:
            await ws.send(encode(**CAMERA))
            while not stop.is_set():
                try:
                    await asyncio.wait_for(ws.recv(), 0.1)
                except TimeoutError:
                    pass

    t = threading.Thread(target=lambda: asyncio.run(run()), daemon=True)
    t.start()
    return t


def _until(predicate, seconds: float = 20.0) -> bool:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.02)
    return False


def test_a_frame_counts_as_unsent_until_viser_s_sender_takes_it():
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    stop = threading.Event()
    reader = _client_reading(server.get_port(), stop)
    try:
        assert _until(lambda: len(server.get_clients()) == 1), "the raw client never connected"
        client = next(iter(server.get_clients().values()))
        backlog = Backlog(client)
        frame = client.scene.add_frame("/body", show_axes=False)
        assert _until(lambda: not backlog.behind()), "nothing published yet, and still behind"
        with client.atomic():  # viser's sender takes nothing from the buffer inside an atomic block
            frame.wxyz = (0.0, 1.0, 0.0, 0.0)
            backlog.published()
            time.sleep(0.2)  # several of the sender's windows
            assert backlog.behind(), "a frame the sender could not take counts as sent"
        assert _until(lambda: not backlog.behind()), "the sender took the frame, and the backlog still says behind"
    finally:
        stop.set()
        reader.join(5)
        server.stop()


def test_a_client_without_viser_s_sender_is_never_behind():
    class Bare:
        client_id = 7

    backlog = Backlog(Bare())
    backlog.published()
    assert not backlog.behind()


@pytest.fixture(scope="module")
def app():
    from app.serve.server import App

    a = App(port=0)
    yield a
    a.close()


def test_while_the_sender_is_behind_only_a_change_s_first_frame_is_published(app):
    async def run():
        async with raw_session(app) as (_ws, session):
            assert await asyncio.to_thread(_until, lambda: session.published >= 3), "the tab never published"
            session.backlog.behind = lambda: True  # the sender stays behind from here on
            await asyncio.sleep(0.3)  # a frame being published when the flag changed
            held = session.published
            await asyncio.sleep(1.0)  # 20 turns of the loop or more
            assert session.published == held, "frames were published over an unsent one"
            seq = session.engine.request("preset", presets.preset_names()[1])
            shown = await asyncio.to_thread(_until, lambda: seq in session.first_frame_after, 60.0)
            assert shown, "a preset load was never shown while the sender was behind"
            after = session.published
            assert after > held
            await asyncio.sleep(1.0)
            assert session.published == after, "frames went on being published after the change was shown"

    asyncio.run(run())
