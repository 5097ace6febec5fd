"""The upload cap holds while the parts arrive (issue 17): a raw websocket client that announces or sends
more than MAX_UPLOAD_BYTES gets refused, and the server does not buffer what it sends; a small scenario
sent the same way still loads. The client speaks viser's wire format (msgpack), as bench/load.py does."""

from __future__ import annotations

import asyncio
from pathlib import Path

import pytest
from raw_client import dial, introduce, raw_session
from raw_client import encode as _msg

from app.engine.upload import MAX_UPLOAD_BYTES

ROOT = Path(__file__).resolve().parents[1]
PART = 1_000_000  # bytes a part: viser's browser client sends parts of about this size


@pytest.fixture(scope="module")
def app():
    from app.serve.server import App

    a = App(port=0)
    yield a
    a.close()


def _send(app, messages_of) -> object:
    """Connect, let the session build, send what ``messages_of(session)`` gives, wait a little; the session."""
    holder = {}

    async def go():
        async with raw_session(app) as (ws, session):
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
        ws = await dial(app)
        session = await introduce(app, ws, before)
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
