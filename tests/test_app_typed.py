"""Numbers typed into a slider's box, as people write them (app/engine/typed.py, app/panel/typed_numbers.py): what
each text is read as or why it is refused; the page script's messages reaching the engine; the script in the page.
The browser side is tests/test_app_browser_typed.py."""

from __future__ import annotations

import json

import pytest

from app.engine import typed
from app.engine.engine import Engine
from app.panel import typed_numbers
from app.share import link

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")
DT = 1.0 / 60.0


@pytest.mark.parametrize(("text", "value"), [
    ("1e-3", 1e-3), ("1.5E2", 150.0), ("-2e+1", -20.0), ("0.001", 1e-3), (" 7 ", 7.0), (".5", 0.5), ("5.", 5.0),
    ("1e308", 1e308), ("\u22123", -3.0), ("1,5", 1.5), ("2,25e-3", 2.25e-3), ("12,5000", 12.5),
])
def test_numbers_are_read_as_people_write_them(text, value):
    assert typed.read_number(text)[0] == value


def test_a_decimal_comma_is_said_to_be_one():
    assert typed.read_number("1,5") == (1.5, True) and typed.read_number("1.5") == (1.5, False)


@pytest.mark.parametrize(("text", "why"), [
    ("", "left empty"), ("   ", "left empty"), ("abc", "not a number"), ("1.2.3", "not a number"),
    ("0x10", "not a number"), ("1_000", "not a number"), ("inf", "not a number"), ("nan", "not a number"),
    ("1e999", "too large"), ("1,500", "write 1.5 or 1500"), ("1,5,5", "not a number"),
])
def test_what_is_no_number_is_refused_with_the_reason(text, why):
    with pytest.raises(typed.Unreadable, match=why):
        typed.read_number(text)


class _Slider:
    def __init__(self, uuid, label="s", value=0.0, lo=-1.0, hi=4.0):
        self._impl = type("Impl", (), {"uuid": uuid})()
        self.label, self.value, self.min, self.max = label, value, lo, hi


class _Gui:
    def add_text(self, label, value, **kw):
        box = _Slider("mailbox", label, value)
        box.on_update = lambda cb: cb
        return box


def _message(uuid: str, text: str, n: int = 1) -> str:
    return json.dumps({"id": uuid, "text": text, "n": n})


def test_the_page_s_messages_reach_the_engine_as_values_or_refusals():
    e = Engine()
    e.request("pause")
    e.tick(DT)
    warped = []
    warp = _Slider("warp", "time warp (log10 x)", 1.0)
    box = typed_numbers.TypedNumbers(_Gui(), {"mass.chi": _Slider("chi"), "mass.Omega": _Slider("Omega")}, e,
                                     [(warp, warped.append)])
    box.received(_message("chi", "1,5"))
    e.tick(DT)
    assert e.scenario.mass.chi == 1.5
    box.received(_message("Omega", "abc"))
    e.tick(DT)
    assert e.guard.note.key == "mass.Omega" and "'abc'" in e.guard.note.text
    for junk in ("not json", json.dumps([1]), _message("nobody", "3"), json.dumps({"id": "chi", "text": 3}),
                 _message("chi", "9" * typed_numbers.MAX_MESSAGE), None):
        box.received(junk)  # a raw client's: dropped, never an exception
    e.tick(DT)
    assert e.scenario.mass.chi == 1.5 and e.changes == {"mass.chi": 1.5}
    box.received(_message("warp", "2,5"))  # a slider that is no parameter: within its span, taken
    assert warped == [2.5] and warp.value == 2.5
    box.received(_message("warp", "1e3"))  # beyond its span (its bound): refused, said at the top
    assert warped == [2.5] and warp.value == 2.5 and "allowed from -1 to 4" in e.error


def test_the_page_carries_the_typed_number_script_after_the_link_script():
    link.install(typed_numbers.PAGE_SCRIPT)
    page = link.with_script(b"<html><head><script>viser()</script></head></html>")
    assert page.index(link.SCRIPT) < page.index(typed_numbers.PAGE_SCRIPT) < page.index(b"<script>viser()")
    assert typed_numbers.MAILBOX_LABEL.encode() in typed_numbers.PAGE_SCRIPT and b"@" not in typed_numbers.PAGE_SCRIPT
