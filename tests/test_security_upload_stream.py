"""The upload cap holds while the parts arrive (issue 17): a raw websocket client that announces or sends
more than MAX_UPLOAD_BYTES gets refused, and the server does not buffer what it sends; a small scenario
sent the same way still loads. The client speaks viser's wire format (msgpack), as bench/load.py does."""

from __future__ import annotations

import asyncio
import time
from pathlib import Path

import msgspec
import pytest
import viser
from websockets.asyncio.client import connect

from app.engine.upload import MAX_UPLOAD_BYTES

ROOT = Path(__file__).resolve().parents[1]
PART = 1_000_000  # bytes a part: viser's browser client sends parts of about this size


def _msg(**fields) -> bytes:
    return msgspec.msgpack.encode(fields)


@pytest.fixture(scope="module")
def app():
    from app.serve.server import App

    a = App(port=0)
    yield a
    a.close()


def _session(app, before, deadline_s: float = 60.0):
    """The session built for this client: a new client id, not the last test's client still closing."""
    end = time.monotonic() + deadline_s
    while time.monotonic() < end:
        new = [s for cid, s in list(app.sessions.items()) if cid not in before]
        if new:
            return new[0]
        time.sleep(0.05)
    raise AssertionError("no session was built for the raw client")


def _send(app, messages_of) -> object:
    """Connect, let the session build, send what ``messages_of(session)`` gives, wait a little; the session."""
    holder = {}

    async def go():
        before = set(app.sessions)
        # max_queue=None: this client reads nothing, so a bounded queue fills with frames, the server's close
        # frame is never read, and leaving waits out the 10 s close timeout
        async with connect(f"ws://127.0.0.1:{app.port}", subprotocols=[f"viser-v{viser.__version__}"],
                           max_size=None, compression=None, open_timeout=60, max_queue=None) as ws:
            await ws.send(_msg(type="ViewerCameraMessage", wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, -3.4, 1.9),
                               fov=1.3, near=0.01, far=1000.0, image_height=720, image_width=1280,
                               look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0)))
            session = await asyncio.to_thread(_session, app, before)
            holder["session"] = session
            for m in messages_of(session):
                await ws.send(m)
            await asyncio.sleep(1.0)
            holder["buffered"] = dict(session.client.gui._current_file_upload_states)
            holder["note"] = (session.engine.upload_note or ("", ""))[1]  # said beside the upload button
            holder["preset"] = session.engine.preset

    asyncio.run(go())
    return holder


def _upload_uuid(session) -> str:
    return session.panel.upload._impl.uuid


def test_an_announced_size_over_the_cap_is_refused_before_any_part(app):
    def messages(session):
        uuid = _upload_uuid(session)
        yield _msg(type="FileTransferStartUpload", source_component_uuid=uuid, transfer_uuid="big", filename="x.toml",
                   mime_type="application/toml", part_count=600, size_bytes=600 * PART)
        for i in range(5):
            yield _msg(type="FileTransferPart", source_component_uuid=uuid, transfer_uuid="big", part_index=i,
                       content=b"#" * PART)

    out = _send(app, messages)
    assert out["buffered"] == {}  # nothing of the 5 MB sent is held
    assert f"at most {MAX_UPLOAD_BYTES} bytes" in out["note"] and "600000000 bytes" in out["note"]


def test_a_client_that_lies_about_its_size_is_cut_off(app):
    def messages(session):
        uuid = _upload_uuid(session)
        yield _msg(type="FileTransferStartUpload", source_component_uuid=uuid, transfer_uuid="liar", filename="x.toml",
                   mime_type="application/toml", part_count=50, size_bytes=1000)
        for i in range(3):
            yield _msg(type="FileTransferPart", source_component_uuid=uuid, transfer_uuid="liar", part_index=i,
                       content=b"#" * PART)

    out = _send(app, messages)
    assert out["buffered"] == {}
    assert "more than" in out["note"] and "dropped" in out["note"]


def test_a_small_scenario_sent_the_same_way_loads(app):
    content = (ROOT / "assets" / "scenarios" / "oblate_settling.toml").read_bytes()

    def messages(session):
        uuid = _upload_uuid(session)
        yield _msg(type="FileTransferStartUpload", source_component_uuid=uuid, transfer_uuid="ok", filename="o.toml",
                   mime_type="application/toml", part_count=1, size_bytes=len(content))
        yield _msg(type="FileTransferPart", source_component_uuid=uuid, transfer_uuid="ok", part_index=0,
                   content=content)

    out = _send(app, messages)
    assert out["preset"] == "upload o.toml" and out["note"].startswith("Loaded o.toml")


def test_one_part_over_the_message_bound_is_refused_at_its_header(app):
    """Issue 24: one 40 MB part was read whole (viser lets a message be 50 MB) before the cap could see it. A
    message over MAX_MESSAGE_BYTES closes the connection at its header (1009), before its body is read."""
    from app.serve.upload_cap import MAX_MESSAGE_BYTES

    closed = {}

    async def go():
        before = set(app.sessions)
        # not ``async with``: its closing of a connection the server has already closed fails inside asyncio
        ws = await connect(f"ws://127.0.0.1:{app.port}", subprotocols=[f"viser-v{viser.__version__}"],
                           max_size=None, compression=None, open_timeout=60)
        await ws.send(_msg(type="ViewerCameraMessage", wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, -3.4, 1.9),
                           fov=1.3, near=0.01, far=1000.0, image_height=720, image_width=1280,
                           look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0)))
        session = await asyncio.to_thread(_session, app, before)
        uuid = _upload_uuid(session)
        await ws.send(_msg(type="FileTransferStartUpload", source_component_uuid=uuid, transfer_uuid="one",
                           filename="x.toml", mime_type="application/toml", part_count=1, size_bytes=1000))
        try:  # the server may close while the part is still being written: the send itself can fail
            await ws.send(_msg(type="FileTransferPart", source_component_uuid=uuid, transfer_uuid="one",
                               part_index=0, content=b"#" * (40 * MAX_MESSAGE_BYTES)))
        except Exception:  # noqa: BLE001 - what the server said is read below
            pass
        await asyncio.wait_for(ws.wait_closed(), timeout=30)
        closed["code"] = ws.close_code
        closed["buffered"] = dict(session.client.gui._current_file_upload_states)

    asyncio.run(go())
    assert closed["code"] == 1009  # message too big
    assert all(not state["parts"] for state in closed["buffered"].values())  # nothing of the part is held
