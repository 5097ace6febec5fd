"""Every value a client sends a control is screened before viser's handler (issue 24, point 2): a value that does
not fit its control is refused in words naming the control, the value and what is allowed, the control is sent
back the value that runs, and the server prints no traceback. A raw websocket client speaks viser's wire format
(msgpack), as bench/load.py does."""

from __future__ import annotations

import asyncio
import time
from types import SimpleNamespace

import pytest
from raw_client import CAMERA, raw_session
from raw_client import encode as _msg
from viser import _messages as msgs

from app.serve.message_guard import refusal, screen_gui_updates, well_formed
from app.studies.sweep_panel import DEFAULT_POINTS, MAX_POINTS


def _state(value, props):
    return SimpleNamespace(value=value, props=props, is_button=False)


def _number_props(**kw):
    base = dict(order=0.0, label="points", hint=None, visible=True, disabled=False, min=1, max=MAX_POINTS,
                step=1, precision=0)
    fields = {f for f in msgs.GuiNumberProps.__dataclass_fields__}
    return msgs.GuiNumberProps(**{k: v for k, v in {**base, **kw}.items() if k in fields})


def test_a_dropdown_takes_only_one_of_its_options():
    s = _state("a", SimpleNamespace(label="parameter", options=("a", "b")))
    assert refusal(s, {"value": "b"}) is None
    for bad in ("c", 1, None, ["a"]):
        why = refusal(s, {"value": bad})
        assert why is not None and why.startswith("parameter:") and "one of a, b" in why


def test_a_slider_takes_any_finite_number_and_nothing_else():
    s = _state(0.5, SimpleNamespace(label="lambda", min=0.0, max=1.0))
    assert refusal(s, {"value": 3}) is None  # past its span: the panel's to take or refuse, not a type error
    assert refusal(s, {"value": 1e300}) is None
    for bad in ("abc", "0.5", {"a": 1}, None, True, float("nan"), float("inf")):
        why = refusal(s, {"value": bad})
        assert why is not None and "lambda" in why and "finite number" in why


def test_a_count_box_takes_only_a_whole_number_within_its_bounds():
    s = _state(DEFAULT_POINTS, _number_props())
    assert refusal(s, {"value": 12}) is None
    assert refusal(s, {"value": 12.0}) is None
    why = refusal(s, {"value": 1e9})
    assert why is not None and "points" in why and "1000000000.0" in why and f"from 1 to {MAX_POINTS}" in why
    assert "whole number" in refusal(s, {"value": 2.5})
    assert refusal(s, {"value": 0}) is not None


def test_a_checkbox_a_text_and_a_vector_take_their_own_types():
    assert refusal(_state(False, SimpleNamespace(label="polhode")), {"value": True}) is None
    assert "true or false" in refusal(_state(False, SimpleNamespace(label="polhode")), {"value": 1})
    assert refusal(_state("", SimpleNamespace(label="paste")), {"value": "qr1:x"}) is None
    assert "text" in refusal(_state("", SimpleNamespace(label="paste")), {"value": 5})
    v = _state((0.0, 0.0, 0.0), SimpleNamespace(label="at"))
    assert refusal(v, {"value": [1, 2, 3]}) is None
    assert refusal(v, {"value": [1, 2]}) is not None
    assert refusal(v, {"value": [1, 2, "x"]}) is not None


def test_only_a_value_can_be_set():
    s = _state(0.5, SimpleNamespace(label="lambda", min=0.0, max=1.0))
    why = refusal(s, {"min": "abc"})
    assert why is not None and "only its value" in why
    assert refusal(s, {"value": 0.5, "max": 9}) is not None
    assert refusal(s, ["value"]) is not None


def test_an_upload_button_takes_no_value_from_an_update():
    s = _state(None, SimpleNamespace(label="Load a scenario"))
    for bad in ({"name": "x.toml"}, {"name": "x", "content": b"x"}, "x", None):
        why = refusal(s, {"value": bad})
        assert why is not None and why.startswith("Load a scenario:") and "only by uploading" in why


def test_a_well_formed_frame_is_its_message():
    assert isinstance(well_formed(_msg(**CAMERA)), msgs.ViewerCameraMessage)
    assert isinstance(well_formed(_msg(**{**CAMERA, "fov": 1})), msgs.ViewerCameraMessage)  # an int for a float
    m = well_formed(_msg(type="GuiUpdateMessage", uuid="u", updates={"value": {"a": [1]}}))
    assert isinstance(m, msgs.GuiUpdateMessage) and m.updates == {"value": {"a": [1]}}  # the value: the guard's


@pytest.mark.parametrize("frame", [
    "a text frame", b"", b"\xc1", b"not msgpack", _msg(x=1), b"\x92\x01\x02",
    _msg(type="NoSuchMessage"), _msg(type=7), _msg(type="GuiUpdateMessage"),
    _msg(type="GuiUpdateMessage", uuid=5, updates={}), _msg(type="GuiUpdateMessage", uuid="u", updates=[1]),
    _msg(type="GuiUpdateMessage", uuid="u", updates={}, extra=1), _msg(**{**CAMERA, "fov": "abc"}),
    _msg(**{**CAMERA, "fov": True}), _msg(**{**CAMERA, "wxyz": (1.0,)}),
    _msg(type="GuiButtonHoldMessage", uuid="u", held=None),
    _msg(type="FileTransferStartUpload", source_component_uuid="u", transfer_uuid="t", filename="x",
         mime_type="x", part_count="abc", size_bytes=[1]),
    _msg(type="PointCloudMessage", name="x"),  # a kind only the server sends
])
def test_a_frame_that_is_no_well_formed_message_is_dropped(frame):
    assert well_formed(frame) is None


# ---- against the real server ----------------------------------------------------------------------
@pytest.fixture(scope="module")
def app():
    from app.serve.server import App

    a = App(port=0)
    yield a
    a.close()


def _wait(predicate, deadline_s: float = 60.0):
    end = time.monotonic() + deadline_s
    while time.monotonic() < end:
        out = predicate()
        if out:
            return out
        time.sleep(0.05)
    raise AssertionError("the server did not get there")


def _run(app, script) -> None:
    """Connect a raw client, let the session build, then ``await script(ws, session)``."""
    async def go():
        async with raw_session(app) as (ws, session):
            await script(ws, session)

    asyncio.run(go())


def _update(handle, value) -> bytes:
    return _msg(type="GuiUpdateMessage", uuid=handle._impl.uuid, updates={"value": value})


def test_hostile_values_to_a_slider_and_a_dropdown_are_refused_in_words_and_print_nothing(app, capfd):
    seen = {}

    async def script(ws, session):
        slider = next(iter(session.panel.sliders.values()))
        before = slider.value
        for v in ("abc", {"a": 1}, None, "nan"):
            await ws.send(_update(slider, v))
        await ws.send(_update(session.panel.compare.param, "not a parameter"))
        await ws.send(_msg(type="GuiUpdateMessage", uuid=slider._impl.uuid, updates={"min": "abc"}))
        await asyncio.to_thread(_wait, lambda: "refused" in session.engine.error and "only its value"
                                in session.engine.error)
        seen.update(before=before, after=slider.value, error=session.engine.error)

    _run(app, script)
    assert seen["after"] == seen["before"]
    err = capfd.readouterr().err
    assert "Traceback" not in err


def test_a_sweep_count_past_its_bound_is_refused_and_the_box_keeps_the_count_that_runs(app, capfd):
    seen = {}

    async def script(ws, session):
        opener = next(h for h in session.client.gui._gui_input_handle_from_uuid.values()
                      if h._impl.props.label == "Open the sweep panel")
        await ws.send(_msg(type="GuiUpdateMessage", uuid=opener._impl.uuid, updates={"value": True}))
        panel = await asyncio.to_thread(_wait, lambda: session.panel.panels.get("Sweep"))
        await ws.send(_update(panel.n1, 1e9))
        await asyncio.to_thread(_wait, lambda: "points" in session.engine.error)
        seen.update(points=panel.n1.value, error=session.engine.error)

    _run(app, script)
    assert seen["points"] == DEFAULT_POINTS
    assert "1000000000.0" in seen["error"] and f"from 1 to {MAX_POINTS}" in seen["error"]
    assert "Traceback" not in capfd.readouterr().err


def test_junk_frames_are_dropped_and_the_connection_goes_on(app, capfd):
    """Issue 24, point 6: a frame that is no message ended the connection with a traceback in viser's reader."""
    seen = {}

    async def script(ws, session):
        for frame in ("text", b"\xc1", b"not msgpack", _msg(type="NoSuchMessage"), _msg(**{**CAMERA, "fov": "x"}),
                      _msg(type="GuiButtonHoldMessage", uuid="u", held=None)):
            await ws.send(frame)
        await ws.send(_update(session.panel.compare.param, "not a parameter"))  # the same connection still heard
        await asyncio.to_thread(_wait, lambda: "not a parameter" in session.engine.error)
        seen["error"] = session.engine.error

    _run(app, script)
    assert "refused" in seen["error"]
    assert "Traceback" not in capfd.readouterr().err


def test_an_upload_announcing_a_negative_size_or_count_is_refused(app):
    seen = {}

    async def script(ws, session):
        uuid = session.panel.upload._impl.uuid
        await ws.send(_msg(type="FileTransferStartUpload", source_component_uuid=uuid, transfer_uuid="neg",
                           filename="x.toml", mime_type="application/toml", part_count=-1, size_bytes=10))
        # an upload's refusal is said beside the Load button (engine.upload_note), not at the top of the panel
        await asyncio.to_thread(_wait, lambda: "must be 0 or more" in (session.engine.upload_note or ("", ""))[1])
        seen.update(error=session.engine.upload_note[1], held=dict(session.client.gui._current_file_upload_states))

    _run(app, script)
    assert "-1 parts" in seen["error"] and "neg" not in seen["held"]


def test_a_client_cannot_open_viser_s_public_share_tunnel(app, monkeypatch):
    """viser opens a public tunnel for any client's ShareUrlRequest; the explorer drops the request. A slider's
    hostile value sent after it shows the connection's messages were handled in order past it."""
    asked = []
    monkeypatch.setattr(app.server, "request_share_url", lambda *a, **k: asked.append("share"))
    monkeypatch.setattr(app.server, "disconnect_share_url", lambda *a, **k: asked.append("disconnect"))

    async def script(ws, session):
        session.engine.error = None
        await ws.send(_msg(type="ShareUrlRequest"))
        await ws.send(_msg(type="ShareUrlDisconnect"))
        await ws.send(_update(next(iter(session.panel.sliders.values())), "abc"))
        await asyncio.to_thread(_wait, lambda: session.engine.error and "refused" in session.engine.error)
        await asyncio.to_thread(app.server._thread_executor.submit(lambda: None).result, 30)

    _run(app, script)
    assert asked == []


def test_screening_a_tab_again_replaces_its_screen_and_the_last_refusal_callback_hears():
    """Class mode builds a new view on a tab at each explore and follow, screening its messages again."""
    inner = []
    gui = SimpleNamespace(_websock_interface=SimpleNamespace(_incoming_handlers={msgs.GuiUpdateMessage: [inner]}),
                          _gui_input_handle_from_uuid={})
    for _cycle in range(5):
        screen_gui_updates(gui, lambda why: None)
    (screen,) = gui._websock_interface._incoming_handlers[msgs.GuiUpdateMessage]
    assert screen.screens == [inner]  # viser's own handler, once, under the one screen


MARKUP = "<img src=x onerror=alert(1)>**b**"


def test_text_typed_into_a_slider_s_box_is_quoted_beside_it_and_at_the_top_never_rendered(app):
    """viser renders a markdown element's HTML as it comes: a text typed into a slider's box (the page's script
    sends it to the tab's mailbox) is quoted in the note beside the slider and, for the time warp, at the top of
    the panel, escaped."""
    seen = {}

    async def script(ws, session):
        panel = session.panel
        key, slider = next(iter(panel.sliders.items()))
        box = panel.typed.box
        await ws.send(_update(box, f'{{"id": "{slider._impl.uuid}", "text": "{MARKUP}", "n": 1}}'))
        await asyncio.to_thread(_wait, lambda: panel.notes.handles)
        seen["note"] = panel.notes.handles[0].content
        await ws.send(_update(box, f'{{"id": "{panel.warp._impl.uuid}", "text": "{MARKUP}", "n": 2}}'))
        await asyncio.to_thread(_wait, lambda: "onerror" in panel.error_md.content)
        seen["top"] = panel.error_md.content

    _run(app, script)
    for shown in (seen["note"], seen["top"]):
        assert "Rejected" in shown and "&lt;img src=x onerror=alert\\(1\\)&gt;" in shown, shown
        assert "<img" not in shown and "**b**" not in shown, shown
