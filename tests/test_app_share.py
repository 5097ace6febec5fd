"""Share codes (app/share/code.py), the page's script (app/share/link.py) and the Share folder with the browser's
storage (app/share/panel.py), headless: a code reproduces the scenario bit for bit, every malformed code is
refused with ShareCodeError naming what was wrong (fuzzed), and the last scene is written only when it
changed, at most once per interval, and never before the stored one was read."""

from __future__ import annotations

import base64
import gzip
import sys
import zlib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import physics
from app.engine import controls, presets
from app.engine.engine import Engine
from app.share import code as share
from app.share import link as share_link
from app.share import panel as share_panel

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fake_gui import FakeGui, Handle  # noqa: E402

PRESETS = presets.preset_names()
_SCENES: dict[str, physics.Scenario] = {}


def preset(name: str) -> physics.Scenario:
    if name not in _SCENES:
        _SCENES[name] = presets.load_preset(name)
    return _SCENES[name]


def code_of_bytes(raw: bytes, version: str = "qr1") -> str:
    return f"{version}:" + base64.urlsafe_b64encode(zlib.compress(raw, 9)).decode().rstrip("=")


def refused(text) -> str:
    with pytest.raises(share.ShareCodeError) as info:
        share.decode(text)
    return str(info.value)


# ---- the code ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", PRESETS)
def test_every_preset_round_trips_bit_for_bit(name):
    sc = preset(name)
    code = share.encode(sc)
    back = share.decode(code)
    assert back == sc
    assert back.to_toml() == sc.to_toml()  # the text written again is the same text
    assert share.encode(back) == code
    assert code.startswith("qr1:") and len(code) < 600  # short enough to paste and to carry in a link


def test_a_slider_edit_is_in_the_code():
    eng = Engine()
    before = share.encode(eng.scenario)
    eng.request_value("mass.chi", 7.25)
    eng.tick(0.0)
    assert eng.scenario.mass.chi == 7.25
    code = share.encode(eng.scenario)
    assert code != before
    assert share.decode(code) == eng.scenario


def test_a_link_or_a_wrapped_code_is_read_too():
    sc = preset(presets.DEFAULT)
    code = share.encode(sc)
    url = share.link("http://127.0.0.1:8080/", code)
    assert url == f"http://127.0.0.1:8080/?scene={code}"
    assert share.decode(url) == sc
    assert share.decode(f"  {code[:50]}\n{code[50:]}  ") == sc  # a code wrapped by a mail client
    assert share.decode(code + "==") == sc  # padding added by a copy


@pytest.mark.parametrize("text, words", [
    ("", "is empty"),
    ("hello", "must start with qr1:"),
    ("qr2:eJwDAAAAAAE", "version qr2"),
    ("qr1:", "nothing after qr1:"),
    ("qr1:ab!cd", "'!' at position 7"),
    ("qr1:abcde", "not whole base64"),
    ("qr1:abcd", "not zlib-compressed"),
    (5, "must be text"),
    ("x" * (share.MAX_CODE_CHARS + 1), "at most 100000 characters"),
    ("http://127.0.0.1:8080/?other=1&scene=", "without a scene= parameter"),
])
def test_malformed_codes_say_what_is_wrong(text, words):
    message = refused(text)
    assert message.startswith("share code = ")
    assert words in message


def test_a_cut_or_padded_stream_is_refused():
    code = share.encode(preset(presets.DEFAULT))
    assert "cut short" in refused(code[:-12])
    good = base64.urlsafe_b64decode(code[4:] + "=" * (-len(code[4:]) % 4))
    extra = "qr1:" + base64.urlsafe_b64encode(good + b"\0\0\0").decode().rstrip("=")
    assert "3 bytes after its compressed data" in refused(extra)


def test_a_zip_bomb_stops_at_the_cap():
    bomb = code_of_bytes(b"a" * 50_000_000)  # 50 MB of TOML in about 65 kB of code
    assert len(bomb) < share.MAX_CODE_CHARS
    assert f"inflates to more than {share.MAX_INFLATED} bytes" in refused(bomb)
    at_cap = code_of_bytes(b"#" * share.MAX_INFLATED)  # exactly the cap: a TOML comment, inflated whole
    assert "body" in refused(at_cap)  # read, and refused by the scenario's own validation


def test_text_toml_and_scenario_errors_are_named():
    assert "not hold UTF-8" in refused(code_of_bytes(b"\xff\xfe[body]"))
    assert "not valid TOML" in refused(code_of_bytes(b"[body\n"))
    assert "body.C = (missing)" in refused(code_of_bytes(b"[body]\nA = 1.0\n"))
    bad = preset(presets.DEFAULT).to_toml().replace("A = 1.0", "A = -1.0").encode()
    assert "body.A" in refused(code_of_bytes(bad))


def test_the_shown_value_is_bounded():
    message = refused("qr1:" + "A" * 5000 + "!")
    assert len(message) < 400


# ---- fuzzing ---------------------------------------------------------------------------------------------

def decodes_or_refuses(text) -> None:
    """decode returns a scenario that round-trips, or raises ShareCodeError: nothing else."""
    try:
        sc = share.decode(text)
    except share.ShareCodeError as exc:
        assert str(exc).startswith("share code = ")
        return
    assert share.decode(share.encode(sc)) == sc


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.text(max_size=300), st.text(alphabet="qr1:ABCabc019-_=+/ \n?&", max_size=300),
                 st.binary(max_size=300).map(lambda b: "qr1:" + base64.urlsafe_b64encode(b).decode())))
def test_fuzz_random_text_is_refused_cleanly(text):
    decodes_or_refuses(text)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.binary(max_size=400), st.text(max_size=400).map(str.encode)))
def test_fuzz_any_compressed_content_is_refused_cleanly(raw):
    decodes_or_refuses(code_of_bytes(raw))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(PRESETS), st.integers(min_value=0, max_value=10_000), st.sampled_from("A_-z0=!"))
def test_fuzz_a_code_with_one_character_changed(name, at, ch):
    code = share.encode(preset(name))
    i = 4 + at % (len(code) - 4)
    decodes_or_refuses(code[:i] + ch + code[i + 1:])


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(PRESETS), st.data())
def test_fuzz_edited_presets_round_trip(name, data):
    """Scenarios built from the presets with any slider moved anywhere in its range: the code decodes to the
    same scenario, and encoding that again gives the same code."""
    base = preset(name)
    values = controls.values_of(base)
    keys = [k for k in values if base.system in controls.BY_KEY[k].systems]
    changes = {}
    for key in data.draw(st.lists(st.sampled_from(keys), max_size=3, unique=True)):
        lo, hi = controls.slider_range(controls.BY_KEY[key], values[key])
        changes[key] = data.draw(st.floats(min_value=lo, max_value=hi, allow_nan=False))
    try:
        sc = controls.apply_changes(base, changes)
    except physics.ScenarioError:
        event("a combination physics refuses")
        return  # not a scene one can share
    event(f"{len(changes)} sliders moved")
    code = share.encode(sc)
    assert share.decode(code) == sc
    assert share.encode(share.decode(code)) == code


# ---- the page's script -----------------------------------------------------------------------------------

def _viser_page(gzipped: bool):
    from websockets.datastructures import Headers
    from websockets.http11 import Response

    html = b"<!doctype html><html><head><meta charset='utf-8'><script>viser()</script></head><body></body></html>"
    body = gzip.compress(html) if gzipped else html
    return Response(200, "OK", Headers({"Content-Type": "text/html; charset=utf-8", "Content-Length": str(len(body)),
                                        "Content-Encoding": "gzip" if gzipped else "identity"}), body)


@pytest.mark.parametrize("gzipped", [False, True])
def test_the_page_gets_the_script_before_viser_s_own(gzipped):
    out = share_link._page_response(_viser_page(gzipped))
    body = gzip.decompress(out.body) if gzipped else out.body
    assert body.index(share_link.SCRIPT) < body.index(b"<script>viser()")
    assert body.index(b"<head>") < body.index(share_link.SCRIPT)
    assert out.headers["Content-Length"] == str(len(out.body))
    assert out.headers["Content-Encoding"] == ("gzip" if gzipped else "identity")
    assert b"viser-user:quasirigid.link" in share_link.SCRIPT  # the key client.local_storage reads back


def test_other_responses_pass_as_they_are():
    from websockets.datastructures import Headers
    from websockets.http11 import Response

    refusal = Response(403, "Forbidden", Headers({"Content-Type": "text/plain"}), b"refused")
    script = Response(200, "OK", Headers({"Content-Type": "application/javascript"}), b"x()")
    assert share_link._page_response(refusal) is refusal
    assert share_link._page_response(script) is script
    assert share_link._page_response(None) is None  # a websocket handshake


# ---- the Share folder and the browser's storage -----------------------------------------------------------

class Gui(FakeGui):
    class _Box:
        def __init__(self):
            self.closed = False

        def __enter__(self):
            return self

        def __exit__(self, *args):
            return False

        def close(self):
            self.closed = True

    def add_folder(self, title, **kw):
        return self._Box()

    def add_modal(self, title, **kw):
        box = self._Box()
        box.title = title
        self.modals = getattr(self, "modals", []) + [box]
        return box

    def add_text(self, label, initial_value, **kw):
        h = self._add(Handle("text", label, initial_value))
        h.visible = kw.get("visible", True)
        return h

    def add_button(self, label, **kw):  # the modal's buttons chain .on_click(cb)
        h = super().add_button(label, **kw)
        h.on_click = lambda cb: (h.callbacks.append(cb), cb)[1]
        return h


class Storage:
    def __init__(self, items=None):
        self.items = dict(items or {})
        self.writes: list[tuple[str, str]] = []

    def get_item(self, key, timeout=None):
        return self.items.get(key)

    def set_item(self, key, value):
        self.writes.append((key, value))
        self.items[key] = value

    def remove_item(self, key):
        self.items.pop(key, None)


class Client:
    client_id = 1

    def __init__(self, items=None):
        self.gui = Gui()
        self.local_storage = Storage(items)
        self.notifications: list[tuple[str, str]] = []

    def add_notification(self, title, body, **kw):
        self.notifications.append((title, body))


def panel_for(items=None, restore=True):
    eng = Engine()
    client = Client(items)
    panel = share_panel.SharePanel(client.gui, eng, client, read=False)
    if restore:
        panel.ready.clear()
        panel._read_storage()  # what the tab's storage thread does, here on the test's thread
    return eng, client, panel


def test_share_shows_the_code_and_the_link_of_the_page():
    eng, client, panel = panel_for({share_link.PAGE_KEY: "http://127.0.0.1:8080/"})
    eng.request_value("mass.chi", 9.0)
    eng.tick(0.0)
    code = panel.share()
    assert share.decode(code) == eng.scenario
    assert panel.code.value == code and panel.code.visible
    assert panel.link.value == f"http://127.0.0.1:8080/?scene={code}"


def test_loading_a_pasted_code_requests_the_scene_and_a_bad_one_says_why():
    eng, client, panel = panel_for(restore=False)
    other = preset("Asymmetric body: intermediate-axis flip")
    assert panel.load_pasted("qr1:abcd") is False
    assert "Not loaded" in panel.note_md.content and "zlib" in panel.note_md.content
    assert eng._actions == []  # nothing requested: the scene stays
    assert panel.load_pasted(share.encode(other)) is True
    eng.tick(0.0)
    assert eng.scenario == other and eng.run.t == 0.0
    assert eng.preset == "Asymmetric body: intermediate-axis flip"  # an unedited preset keeps its name


def test_a_stored_scene_is_restored_and_said():
    stored = physics.Scenario.from_toml(preset(presets.DEFAULT).to_toml().replace("chi = 5.0", "chi = 11.0"))
    eng, client, panel = panel_for({share_panel.SAVE_KEY: share.encode(stored)})
    eng.tick(0.0)
    assert eng.scenario == stored
    assert eng.preset == share_panel.RESTORED
    assert "restored your last scene" in panel.status()


def test_a_stored_value_that_does_not_decode_is_ignored_with_a_notice():
    eng, client, panel = panel_for({share_panel.SAVE_KEY: "qr1:not-a-scene"})
    before = eng.scenario
    eng.tick(0.0)
    assert eng.scenario is before
    assert "could not be read" in panel.status()
    assert len(client.notifications) == 1 and "share code" in client.notifications[0][1]


def test_a_link_is_offered_in_a_dialog_not_loaded_silently():
    other = preset("Asymmetric body: intermediate-axis flip")
    eng, client, panel = panel_for({share_link.LINK_KEY: share.encode(other)})
    eng.tick(0.0)
    assert eng.scenario != other  # not loaded until the user says so
    assert share_link.LINK_KEY not in client.local_storage.items  # offered once
    (modal,) = client.gui.modals
    client.gui.button("Load the shared scene").fire()
    eng.tick(0.0)
    assert modal.closed and eng.scenario == other


def test_a_bad_link_says_so_and_keeps_the_scene():
    eng, client, panel = panel_for({share_link.LINK_KEY: "qr9:whatever"})
    (modal,) = client.gui.modals
    assert "cannot be opened" in modal.title
    text = " ".join(h.content for h in client.gui.handles if h.kind == "markdown")
    assert "version qr9" in text


class SilentStorage(Storage):
    """A browser that stays connected and never answers (viser's get_item raises TimeoutError)."""

    def get_item(self, key, timeout=None):
        self.timeouts = getattr(self, "timeouts", []) + [timeout]
        raise TimeoutError(key)


def test_a_browser_that_does_not_answer_is_waited_for_and_then_said():
    eng, client, panel = panel_for(restore=False)
    client.local_storage = SilentStorage()
    panel.ready.clear()
    panel._read_storage()
    # a tab still building its scene in software WebGL answered after 10 s in CI: the wait is generous
    assert client.local_storage.timeouts == [share_panel.READ_TIMEOUT] and share_panel.READ_TIMEOUT >= 30.0
    assert "did not answer" in panel.status() and panel.ready.is_set()


def test_the_last_scene_is_written_when_it_changes_at_most_once_per_interval(monkeypatch):
    now = [100.0]
    monkeypatch.setattr(share_panel.time, "monotonic", lambda: now[0])
    eng, client, panel = panel_for()
    writes = client.local_storage.writes
    panel.tick()
    assert len(writes) == 1 and writes[0] == (share_panel.SAVE_KEY, share.encode(eng.scenario))
    for _ in range(5):  # frames with the scene unchanged
        now[0] += 0.5
        panel.tick()
    assert len(writes) == 1
    for chi in (6.0, 7.0, 8.0):  # three changes within one interval: the first is written, the rest waits
        eng.request_value("mass.chi", chi)
        eng.tick(0.0)
        now[0] += 0.3
        panel.tick()
    assert len(writes) == 2
    now[0] += share_panel.SAVE_INTERVAL
    panel.tick()
    assert len(writes) == 3 and share.decode(writes[-1][1]).mass.chi == 8.0  # the last change kept


def test_nothing_is_written_before_the_stored_scene_is_read():
    eng, client, panel = panel_for(restore=False)
    panel.ready.clear()
    panel.tick()
    assert client.local_storage.writes == []


def test_a_refusal_shows_pasted_markup_as_text():
    eng, client, panel = panel_for(restore=False)
    panel.load_pasted("<img src=x onerror=alert(1)>[link](javascript:x)")
    note = panel.note_md.content
    assert "Not loaded" in note
    assert "<img" not in note and "](javascript" not in note  # escaped: shown, never rendered


def test_any_failure_to_start_the_scene_is_said(monkeypatch):
    eng, client, panel = panel_for(restore=False)

    def refuses(sc):
        raise RuntimeError("the kernels are gone")

    monkeypatch.setattr(share_panel.physics, "LiveRun", refuses)
    assert panel.load_pasted(share.encode(preset(presets.DEFAULT))) is False
    assert "RuntimeError: the kernels are gone" in panel.note_md.content
    assert eng._actions == []


def test_a_server_started_on_its_own_scene_keeps_it_over_the_browsers_last():
    """``python -m app --scenario FILE`` shows FILE: the stored last scene is not restored (a link is still offered)."""
    stored = share.encode(physics.default_scenario().with_values(**{"mass.chi": 9.5}))
    eng = Engine()
    client = Client({share_panel.SAVE_KEY: stored})
    panel = share_panel.SharePanel(client.gui, eng, client, restore=False, read=False)
    panel.ready.clear()
    panel._read_storage()
    eng.tick(0.0)
    assert eng.scenario.mass.chi != 9.5 and "restored" not in panel.status()
    restoring = share_panel.SharePanel(client.gui, Engine(), client, read=False)
    restoring.ready.clear()
    restoring._read_storage()
    restoring.engine.tick(0.0)
    assert restoring.engine.scenario.mass.chi == 9.5 and "restored" in restoring.status()


def test_every_preset_title_is_offered_once_and_means_one_scene():
    """A title both a system's example and a shipped file carry (the wheel damper's) is one option: the page's
    dropdown refuses repeated options, and no session started when it had one. Where an example and a file
    share a title they must be the same scene, or one would hide the other."""
    assert len(PRESETS) == len(set(PRESETS))
    files, shown = presets.preset_files(), presets.examples()
    for title in set(files) & set(shown):
        assert physics.Scenario.load(files[title]).to_dict() == physics.Scenario.from_toml(shown[title]).to_dict()


def test_the_code_shown_follows_the_scene(monkeypatch):
    """The Share folder says "Code of the scene as it is now": after a preset change (or a slider), it is the new
    scene's code, not the one shown before (issue 24)."""
    monkeypatch.setattr(share_panel, "SAVE_INTERVAL", 0.0)
    eng, client, panel = panel_for(restore=False)
    old = panel.share()
    other = "Asymmetric body: intermediate-axis flip"
    eng.request("preset", other)
    eng.tick(0.0)
    panel.tick()
    assert panel.code.value != old and share.decode(panel.code.value) == eng.scenario == preset(other)
    eng.request_value("body.M", 3.0)
    eng.tick(0.0)
    panel.tick()
    assert share.decode(panel.code.value) == eng.scenario and eng.scenario.body.M == 3.0
    assert panel.link.value.endswith(f"?scene={panel.code.value}")
