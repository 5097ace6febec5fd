"""Every value a client sends a control is screened before viser's handler (issue 24, point 2): a value that does
not fit its control is refused in words naming the control, the value and what is allowed, the control is sent
back the value that runs, and the server prints no traceback. A raw websocket client speaks viser's wire format
(msgpack), as bench/load.py does."""

from __future__ import annotations

import asyncio
import time
from types import SimpleNamespace

import pytest
import viser
from test_security_upload_stream import _msg  # viser's wire format, as that file's raw client speaks it
from viser import _messages as msgs
from websockets.asyncio.client import connect

from app.serve.message_guard import refusal
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
        async with connect(f"ws://127.0.0.1:{app.port}", subprotocols=[f"viser-v{viser.__version__}"],
                           max_size=None, compression=None, open_timeout=60) as ws:
            await ws.send(_msg(type="ViewerCameraMessage", wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, -3.4, 1.9),
                               fov=1.3, near=0.01, far=1000.0, image_height=720, image_width=1280,
                               look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0)))
            session = await asyncio.to_thread(_wait, lambda: next(iter(app.sessions.values()), None))
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
