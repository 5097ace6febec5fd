"""A choice on the page is read when it arrives. viser stores a client's value on its event loop and runs a plain
callback later on a pool thread; the frame loop sets each dropdown back to the engine's value every frame
(app.panel.panel._sync_choices), so a callback that reads the control on the pool thread can read the old value
back and lose the user's choice. On a loaded machine that window is wide: the likely cause of the intermittent
failure of tests/test_app_browser_controls.py's auto-accuracy test ("timed out waiting for auto running the closed
form"), which passed 3 of 3 runs beside two CPU burners once the callbacks read the value as it arrives.

Here the pool is held busy while the choice arrives, which makes that window as wide as one likes, and the
frame loop is left to run past it."""

from __future__ import annotations

import asyncio
import contextlib
import operator
import threading
import time

import pytest
from raw_client import encode, raw_session

from app.engine import controls


@pytest.fixture(scope="module")
def app():
    from app.serve.server import App

    a = App(port=0)
    yield a
    a.close()


def _wait(predicate, deadline_s: float = 30.0) -> bool:
    end = time.monotonic() + deadline_s
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.02)
    return False


@contextlib.asynccontextmanager
async def _pool_held(app):
    """Every thread of the server's callback pool held while the block runs; then freed, and a callback it
    delayed has run."""
    pool = app.server._thread_executor
    gate = threading.Event()
    held = [pool.submit(gate.wait, 30) for _ in range(pool._max_workers)]
    try:
        yield
    finally:
        gate.set()
        await asyncio.to_thread(lambda: [h.result(30) for h in held])
        await asyncio.to_thread(pool.submit(lambda: None).result, 30)  # a late callback has run


def _choose_with_the_pool_busy(app, control, label: str, frames_applied) -> dict:
    """Send ``label`` to ``control`` (a dotted name on the session's panel) while every pool thread is held; let
    the frame loop run until ``frames_applied(session)`` or a second has passed, then free the pool."""
    seen = {}

    async def go():
        async with raw_session(app) as (ws, session):
            handle = operator.attrgetter(control)(session.panel)
            async with _pool_held(app):
                stamp = handle._impl.update_timestamp
                await ws.send(encode(type="GuiUpdateMessage", uuid=handle._impl.uuid, updates={"value": label}))
                assert await asyncio.to_thread(_wait, lambda: handle._impl.update_timestamp != stamp), \
                    "the server did not take the value"
                # the frame loop runs on: it applies a request made at once, or sets the control back
                await asyncio.to_thread(_wait, lambda: frames_applied(session), 1.0)
            seen["applied"] = await asyncio.to_thread(_wait, lambda: frames_applied(session), 10.0)

    asyncio.run(go())
    return seen


def test_auto_s_accuracy_chosen_while_the_pool_is_busy_is_applied(app):
    label = "0.1 rad"
    assert controls.accuracy_options(None)[label] == 0.1
    seen = _choose_with_the_pool_busy(app, "accuracy", label, lambda s: s.engine.accuracy_choice == 0.1)
    assert seen["applied"], "the accuracy chosen was lost: read after the frame loop set the dropdown back"


def test_a_fidelity_chosen_while_the_pool_is_busy_is_applied(app):
    seen = _choose_with_the_pool_busy(app, "fidelity", "auto", lambda s: s.engine.fidelity_choice == "auto")
    assert seen["applied"], "the fidelity chosen was lost"


def test_two_texts_typed_while_the_pool_is_busy_both_reach_their_sliders(app):
    """The page's script sends what is typed into a slider's box through one text control (the mailbox); a second
    message stores its text there before a pool thread would have read the first."""
    seen = {}

    async def go():
        async with raw_session(app) as (ws, session):
            panel, eng = session.panel, session.engine
            (k1, s1), (k2, s2) = list(panel.sliders.items())[:2]
            want = {k1: 0.9 * eng.values[k1], k2: 0.9 * eng.values[k2]}  # smaller m and rho: a scene any body takes
            async with _pool_held(app):
                for n, (k, s) in enumerate(((k1, s1), (k2, s2))):
                    text = f'{{"id": "{s._impl.uuid}", "text": "{want[k]!r}", "n": {n}}}'
                    await ws.send(encode(type="GuiUpdateMessage", uuid=panel.typed.box._impl.uuid,
                                         updates={"value": text}))
                await asyncio.to_thread(_wait, lambda: all(eng.values[k] == v for k, v in want.items()), 1.0)
            seen["applied"] = await asyncio.to_thread(
                _wait, lambda: all(eng.values[k] == v for k, v in want.items()), 10.0)
            seen["values"] = {k: eng.values[k] for k in want}, want, eng.error

    asyncio.run(go())
    assert seen["applied"], seen["values"]



def test_a_comparison_chosen_while_the_pool_is_busy_is_applied(app):
    """The Compare folder's ``sync`` sets "compare with" back to "off" every frame while the engine runs no
    comparison, so its callback too must read the choice as it arrives."""
    from app.engine.compare import Comparison
    from app.panel.compare_panel import FIDELITY

    seen = _choose_with_the_pool_busy(app, "compare.mode", FIDELITY,
                                      lambda s: isinstance(s.engine.compare, Comparison))
    assert seen["applied"], "the comparison chosen was lost"
