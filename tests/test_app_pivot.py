"""The spherical pendulum's pivot in the explorer (issue 17's "a fault that should not be one", made reachable
from the panel), headless: the run that stops at the gimbal pole names the panel's control, not a file key;
choosing "isotropic" there runs the same scene through the pole; the choice is kept across slider edits and an
undo, marks the scene edited, is offered only where a spherical pendulum is, and a raw client's bad value is
refused by name with the choice kept.
"""

from __future__ import annotations

import html
import re
from types import SimpleNamespace

import pytest
from test_app_accuracy import _user
from test_app_words import DT, _RecordingGui
from test_pendulum_pivot import pole

import physics
from app.engine.engine import Engine
from app.panel.panel import Panel

POLE_T = 1.8  # s: the Cardan pivot's pole on tests/test_pendulum_pivot.py's scene (it stops at t = 1.84)


def _play(eng, seconds: float, panel=None):
    fr = None
    for _ in range(round(seconds / DT)):
        fr = eng.tick(DT)
        if panel is not None:
            panel.update(fr, plots_now=True)
        if fr.status != "running":
            break
    return fr


@pytest.fixture
def engine():
    eng = Engine(scenario=pole("cardan"))
    eng.warp = 1.0
    return eng


def test_the_cardan_stop_names_the_panels_control(engine):
    gui = _RecordingGui()
    panel = Panel(SimpleNamespace(gui=gui, scene=None), engine)
    fr = _play(engine, 2 * POLE_T, panel)
    assert fr.status == "fault" and POLE_T < engine.run.t < 2 * POLE_T
    # as the page shows the markdown: the notes escape HTML and markdown (app.markup.plain)
    shown = [re.sub(r"\\(.)", r"\1", html.unescape(h.content)) for h in gui.handles
             if isinstance(h.content, str) and "gimbal" in h.content]
    assert len(shown) >= 2, shown  # the status line and the note with its way out
    for text in shown:
        assert 'choose pivot "isotropic" (folder Pendulum damper)' in text and "pendulum.pivot" not in text
        assert re.search(r"at t = 1\.8\d{0,4} s", text), text  # to 6 digits, not the fault's 17


def test_choosing_isotropic_runs_through_the_pole_and_keeps_k_during_the_swing(engine):
    _play(engine, 1.0)
    t, K = engine.run.t, engine.readouts()["|K|"]
    engine.request("pivot", "isotropic")
    fr = _play(engine, DT)
    assert engine.scenario.pendulum.pivot == "isotropic" and engine.edited and not engine.error
    assert engine.run.t == pytest.approx(t + DT)  # the state carried: the swing goes on, no restart
    assert engine.readouts()["|K|"] == K  # and the inertial K with it (printed to the readout's digits)
    fr = _play(engine, 3 * POLE_T)
    assert fr.status == "running" and engine.run.t > 2 * POLE_T


def test_the_choice_survives_a_slider_edit_and_its_undo(engine):
    engine.request("pivot", "isotropic")
    _play(engine, DT)
    engine.request_value("pendulum.c_d", 2 * engine.values["pendulum.c_d"])
    _play(engine, DT)
    assert engine.scenario.pendulum.pivot == "isotropic" and engine.scenario.pendulum.c_d != pole("cardan").pendulum.c_d
    engine.request("undo")
    _play(engine, DT)
    assert engine.scenario.pendulum.pivot == "isotropic" and engine.pivot_choice == "isotropic"


def test_the_panel_offers_it_only_with_a_spherical_pendulum_and_refuses_a_bad_value(engine):
    panel = Panel(SimpleNamespace(gui=_RecordingGui(), scene=None), engine)
    _play(engine, DT, panel)
    assert panel.pivot.visible and panel.pivot.value == "cardan" and tuple(panel.pivot.options) == physics.PIVOTS
    _user(panel.pivot, "isotropic")
    _play(engine, DT, panel)
    assert engine.scenario.pendulum.pivot == "isotropic"
    for sent in ("gimbal", None, 1):
        _user(panel.pivot, sent)
        _play(engine, DT, panel)
        assert "pivot" in engine.error and repr(sent) in engine.error
        assert engine.scenario.pendulum.pivot == "isotropic" and panel.pivot.value == "isotropic"
    mass = Engine()
    panel = Panel(SimpleNamespace(gui=_RecordingGui(), scene=None), mass)
    _play(mass, DT, panel)
    assert not panel.pivot.visible and not mass.edited
