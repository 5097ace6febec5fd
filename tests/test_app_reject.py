"""Headless checks of slider values, moved or typed (app/engine/edits.py through app/engine/engine.py): a value physics
rejects is never applied, now or by a later edit; a value beyond the slider's usual span is applied, never clamped,
and the span widens, with a note; a text that is no number is refused in words; a fault offers undo, which brings
back the parameters and the run's state of just before the last change."""

from __future__ import annotations

import time

import numpy as np
import pytest

from app.engine import controls, edits
from app.engine.engine import Engine

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")
DT = 1.0 / 60.0
OMEGA = controls.BY_KEY["mass.Omega"]


def ticks(engine: Engine, n: int):
    fr = None
    for _ in range(n):
        fr = engine.tick(DT)
    return fr


def set_back(engine: Engine) -> dict:
    """The sliders the panel sets back once the user has stopped typing (TYPING_PAUSE_S later)."""
    return engine.guard.take_revert(now=time.perf_counter() + edits.TYPING_PAUSE_S)


def paused_engine(n: int = 5) -> Engine:
    e = Engine()
    ticks(e, n)
    e.request("pause")
    e.tick(DT)
    return e


def test_a_rejected_m_stays_out_and_its_slider_goes_back():
    e = paused_engine()
    m0 = e.scenario.mass.m
    e.request_value("mass.m", -1.0)
    e.tick(DT)
    assert e.scenario.mass is not None and e.scenario.mass.m == m0
    note = e.guard.note
    assert note.kind == "rejected" and note.key == "mass.m"
    assert "-1" in note.text and f"stays {controls.fmt(m0)} kg" in note.text
    assert "mass.m" in e.error  # the engine's error names it; the panel shows it beside the slider instead
    assert note.reason == e.error
    assert e.guard.take_revert(now=time.perf_counter()) == {}  # not while the user may still be typing
    assert set_back(e) == {"mass.m": m0}  # then the slider is set back to the last good value


def test_a_rejected_typed_value_is_set_back_at_once_quoting_what_was_typed():
    """A typed value comes once, when the box is left: its slider need not wait for the typing to stop."""
    e = paused_engine()
    e.request_value("mass.m", 1e308, text="1e308")
    e.tick(DT)
    assert e.scenario.mass.m == 0.2 and "m = 1e308 kg" in e.guard.note.text and "m stays 0.2 kg" in e.guard.note.text
    assert e.guard.take_revert(now=time.perf_counter()) == {"mass.m": 0.2}


def test_a_text_that_is_no_number_is_refused_in_words_and_nothing_changes():
    e = paused_engine()
    sc0, n_undo = e.scenario, len(e.guard.undo)
    e.refuse_typed("mass.Omega", "abc", "not a number")
    e.tick(DT)
    note = e.guard.note
    assert note.kind == "rejected" and note.key == "mass.Omega" and "'abc'" in note.text
    assert f"Omega stays {controls.fmt(sc0.mass.Omega)} rad/s" in note.text
    assert e.scenario is sc0 and len(e.guard.undo) == n_undo and e.changes == {}


def test_a_value_typed_with_a_decimal_comma_is_applied_and_said():
    e = paused_engine()
    e.request_value("mass.chi", 1.5, text="1,5")
    e.tick(DT)
    assert e.scenario.mass.chi == 1.5 and e.guard.note.kind == "read" and "'1,5' read as 1.5 1/s" in e.guard.note.text
    assert e.guard.take_revert(now=time.perf_counter()) == {"mass.chi": 1.5}  # the box shows the value that runs


def test_a_rejection_in_the_same_frame_as_a_good_value_keeps_the_good_one():
    e = paused_engine()
    e.request_value("mass.chi", 4.0)
    e.request_value("mass.m", 5.0)  # m >= M: rejected by physics (and beyond the slider)
    e.tick(DT)
    assert e.scenario.mass.chi == 4.0 and e.scenario.mass.m == 0.2
    assert e.guard.note.key == "mass.m" and "less than body.M" in e.guard.note.text


def test_a_value_beyond_the_slider_is_applied_and_the_span_widens_with_a_note():
    """Nothing is clamped: Omega = 150 (typed 1.5E2, beyond the usual 60) runs, and the slider now reaches it."""
    e = paused_engine()
    e.sliders_changed = False
    e.request_value("mass.Omega", 150.0, text="1.5E2")
    fr = e.tick(DT)
    assert e.scenario.mass.Omega == 150.0 and e.values["mass.Omega"] == 150.0
    lo, hi = controls.slider_range(OMEGA, 150.0)
    assert lo == OMEGA.lo and hi == 300.0 and e.sliders_changed  # the panel widens the slider's span
    note = e.guard.note
    assert note.kind == "widened" and note.key == "mass.Omega" and "'1.5E2'" in note.text and "300" in note.text
    assert e.error == "" and fr.status == "running"
    e.sliders_changed = False
    e.request_value("mass.Omega", 9.0)  # back inside: the span narrows to the usual one
    e.tick(DT)
    assert e.sliders_changed and e.guard.note is None


def test_a_span_widened_for_the_largest_number_stays_finite():
    assert controls.slider_range(OMEGA, 1e308) == (OMEGA.lo, 1e308)


def test_a_good_value_typed_after_a_rejected_one_is_not_set_back():
    e = paused_engine()
    e.request_value("mass.m", -1.0)  # typed -1, then corrected to 0.3
    e.tick(DT)
    e.request_value("mass.m", 0.3)
    e.tick(DT)
    assert e.scenario.mass.m == 0.3 and set_back(e) == {} and e.guard.note is None


def test_an_accepted_edit_clears_an_older_note():
    e = paused_engine()
    e.request_value("mass.m", -1.0)
    e.tick(DT)
    assert e.guard.note is not None
    e.request_value("mass.chi", 3.0)
    e.tick(DT)
    assert e.guard.note is None and e.error == ""


def test_undo_restores_the_parameters_and_the_state_of_just_before_the_change():
    e = Engine()
    ticks(e, 10)
    t0, y0, sc0 = e.run.t, e.run.y.copy(), e.scenario
    rows0 = e.plot.values()
    for omega in (6.0, 7.0, 8.0):  # one drag: one change
        e.request_value("mass.Omega", omega)
        ticks(e, 3)
    assert e.scenario.mass.Omega == 8.0 and e.run.t > t0 and len(e.guard.undo) == 1
    e.request("undo")
    fr = e.tick(0.0)
    assert e.scenario == sc0 and e.values == controls.values_of(sc0)
    assert e.run.t == t0 and np.array_equal(e.run.y, y0) and fr.t == t0
    np.testing.assert_array_equal(e.plot.values(), rows0)  # the plots turn back with the clock
    assert e.guard.undo == [] and e.sliders_changed
    ticks(e, 3)
    assert e.run.t > t0 and e.run.status == "running"  # it runs on from there


def test_undo_after_a_fault_brings_the_run_back():
    e = Engine()
    ticks(e, 5)
    t0, y0 = e.run.t, e.run.y.copy()
    omega0 = e.scenario.mass.Omega
    e.request_value("mass.Omega", 1e6)  # applied (physics takes it), and the run cannot go on
    fr = ticks(e, 3)
    assert fr.status == "fault"
    note = edits.shown_note(e.guard, fr.status, fr.message)
    assert note.kind == "fault" and note.key == "mass.Omega"
    assert "Undo the last change" in note.text and "reset the scene" in note.text and fr.message in note.text
    e.request("undo")
    fr = e.tick(0.0)
    assert fr.status == "running" and e.scenario.mass.Omega == omega0
    assert e.run.t == t0 and np.array_equal(e.run.y, y0)
    assert edits.shown_note(e.guard, fr.status, fr.message) is None
    fr = ticks(e, 5)
    assert fr.status == "running" and fr.t > t0


def test_undo_steps_back_one_change_at_a_time_and_stops_at_the_load():
    e = paused_engine()
    sc0 = e.scenario
    e.request_value("mass.chi", 3.0)
    e.tick(DT)
    e.request_value("mass.Omega", 9.0)
    e.tick(DT)
    e.request("undo")
    e.tick(DT)
    assert e.scenario.mass.chi == 3.0 and e.scenario.mass.Omega == sc0.mass.Omega
    e.request("undo")
    e.tick(DT)
    assert e.scenario == sc0
    e.request("undo")  # nothing left: a no-op, not an error
    e.tick(DT)
    assert e.scenario == sc0 and e.error == ""


def test_undo_of_a_change_that_restarted_the_run_restores_its_state():
    e = Engine()
    ticks(e, 8)
    t0, y0 = e.run.t, e.run.y.copy()
    e.request_value("initial.theta0", 0.3)  # restarts from t = 0
    ticks(e, 2)
    assert e.run.t < t0
    e.request("undo")
    e.tick(0.0)
    assert e.run.t == t0 and np.array_equal(e.run.y, y0)
    assert e.plot.values()[-1, 0] == t0  # the buffers start again from the restored state


def test_reset_the_scene_reloads_it_as_loaded():
    e = Engine()
    loaded = e.scenario
    ticks(e, 3)
    e.request_value("mass.Omega", 1e6)
    fr = ticks(e, 3)
    assert fr.status == "fault"
    e.request("reload")
    fr = e.tick(0.0)
    assert fr.status == "running" and e.run.t == 0.0 and e.scenario == loaded and e.changes == {}
    assert e.guard.undo == []


def test_the_same_slider_moved_again_after_a_pause_is_a_new_change(monkeypatch):
    monkeypatch.setattr(edits, "TYPING_PAUSE_S", 0.0)  # every value comes after a pause
    e = paused_engine()
    omega0 = e.scenario.mass.Omega
    for omega in (6.0, 7.0):
        e.request_value("mass.Omega", omega)
        e.tick(DT)
    assert len(e.guard.undo) == 2
    e.request("undo")
    e.tick(DT)
    assert e.scenario.mass.Omega == 6.0
    e.request("undo")
    e.tick(DT)
    assert e.scenario.mass.Omega == omega0


# ---- where the note goes (app/panel/control_notes.py), on a stand-in for viser's GUI ----------------------------

class _Element:
    def __init__(self, gui, kind, text, order):
        self.gui, self.kind, self.text, self.order = gui, kind, text, order
        self.container = gui.container
        self.disabled, self.visible, self.clicks = False, True, []

    def remove(self):
        self.gui.elements.remove(self)

    def on_click(self, cb):
        self.clicks.append(cb)


class _Folder(_Element):
    def __enter__(self):
        self.outer, self.gui.container = self.gui.container, self
        return self

    def __exit__(self, *exc):
        self.gui.container = self.outer


class _Gui:
    """Elements with viser's ``order`` and the folder they were made in."""

    def __init__(self):
        self.elements, self.container, self.count = [], None, 0

    def _add(self, cls, kind, text, order):
        self.count += 1
        el = cls(self, kind, text, self.count if order is None else order)
        self.elements.append(el)
        return el

    def add_folder(self, title):
        return self._add(_Folder, "folder", title, None)

    def add_slider(self, label):
        return self._add(_Element, "slider", label, None)

    def add_markdown(self, text, order=None):
        return self._add(_Element, "markdown", text, order)

    def add_button(self, label, order=None, **_kw):
        return self._add(_Element, "button", label, order)

    def column(self, container):
        """What a container shows, in viser's order."""
        return [(e.kind, e.text) for e in sorted(self.elements, key=lambda e: e.order) if e.container is container]


def _panel():
    from app.panel.control_notes import NotePlace

    gui = _Gui()
    top = gui.add_markdown("error")
    with gui.add_folder("mass") as folder:
        sliders = {"mass.m": gui.add_slider("m"), "mass.rho": gui.add_slider("rho")}
    actions = []
    notes = NotePlace(gui, sliders, {k: folder for k in sliders}, top.order, undo=lambda: actions.append("undo"),
                      reset=lambda: actions.append("reload"))
    return gui, folder, sliders, notes, actions


def test_a_note_goes_right_under_its_slider_in_its_folder():
    gui, folder, _, notes, _ = _panel()
    notes.show(edits.Note("mass.m", "rejected", "Rejected: m = -1 kg"), can_undo=False)
    assert [text for _, text in gui.column(folder)] == ["m", "<span style='color:#c00'>Rejected: m = -1 kg</span>",
                                                       "rho"]
    notes.show(None, can_undo=False)
    assert gui.column(folder) == [("slider", "m"), ("slider", "rho")]


def test_a_faults_note_carries_undo_and_reset_and_they_request_them():
    gui, folder, _, notes, actions = _panel()
    notes.show(edits.Note("mass.rho", "fault", "The run stopped"), can_undo=True)
    column = gui.column(folder)
    assert [k for k, _ in column] == ["slider", "slider", "markdown", "button", "button"]
    assert [t for k, t in column if k == "button"] == ["Undo the last change", "Reset the scene"]
    for el in gui.elements:
        if el.kind == "button":
            el.clicks[0](None)
    assert actions == ["undo", "reload"]
    notes.show(edits.Note("mass.rho", "fault", "The run stopped"), can_undo=False)  # nothing left to undo
    assert [t for k, t in gui.column(folder) if k == "button"] == ["Reset the scene"]


def test_a_note_about_a_hidden_slider_or_none_goes_to_the_top():
    gui, folder, sliders, notes, _ = _panel()
    sliders["mass.m"].disabled = True  # a pendulum scene: the mass sliders are off
    notes.show(edits.Note("mass.m", "widened", "m widened"), can_undo=False)
    top = gui.column(None)
    assert [k for k, _ in top] == ["markdown", "markdown", "folder"]  # under the panel's error line
    assert top[1][1].endswith("m widened</span>") and len(gui.column(folder)) == 2
    notes.show(edits.Note(None, "fault", "stopped"), can_undo=False)
    assert [t for k, t in gui.column(None) if k == "button"] == ["Reset the scene"]
