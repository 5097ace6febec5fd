"""The explorer's lists come from physics' registry (issue 14): a System registered in this file alone shows in
the System dropdown, brings its slider in its own folder, and a slider value applies to its scenarios; the
app names no system. Unregistered, it is gone from the lists again.

The toy is a bare body carrying a table ``[tag]`` of its own (one number, ``h``). Its model is the moving
mass's full model registered again under the toy's name: a scenario without a mass is the free rigid body,
which that model runs, and ``h`` is a number the dynamics ignore (what is tested here is the app's plumbing;
tests/test_toy_system.py runs a toy with dynamics of its own).
"""

from __future__ import annotations

import dataclasses
import math
from contextlib import contextmanager
from types import SimpleNamespace

import pytest
from test_app_words import _RecordingGui

import physics
from app.engine import controls, presets
from app.engine.engine import Engine
from app.panel.panel import Panel

NAME, LABEL, FOLDER = "free_body", "free body (test toy)", "Tag"
DT = 1.0 / 60.0


@dataclasses.dataclass(frozen=True)
class Tag:
    """One number carried by the scenario (kg m^2/s); the borrowed dynamics ignore it."""

    h: float

    def __post_init__(self):
        if isinstance(self.h, bool) or not isinstance(self.h, (int, float)) or not math.isfinite(self.h):
            raise physics.ScenarioError("tag.h", self.h, "must be a finite number")
        object.__setattr__(self, "h", float(self.h))


EXAMPLE = """
[body]
A = 1.0
C = 1.5
M = 1.0

[tag]
h = 0.1

[initial]
G0 = 2.0
theta0 = 0.4

[run]
fidelity = "full"
t_end = 20.0
"""
PARAM = physics.Param("tag.h", "h", "kg m^2/s", "the tag's number (a test toy's only parameter)", -2.0, 2.0, 0.01,
                      folder=FOLDER)


@contextmanager
def toy_system():
    """The toy registered while the block runs (no ``edit`` hook: its keys go through physics.edit_dict)."""
    borrowed = physics.get_model("moving_mass", "full")
    physics.register_model(dataclasses.replace(borrowed, name=f"{NAME}/full", system=NAME))
    try:
        yield physics.register_system(physics.System(
            name=NAME, label=LABEL, summary="a bare body with a tag (test toy)", tables=(physics.Table("tag", Tag),),
            example=EXAMPLE, params=(PARAM,), folders=(FOLDER,),
            values=lambda sc, item=None: {"tag.h": sc.tag.h if sc.tag is not None else 0.0}))
    finally:
        physics.unregister_system(NAME)


@pytest.fixture
def toy():
    with toy_system() as system:
        yield system


def test_the_lists_and_sliders_include_a_registered_system(toy):
    assert controls.SYSTEM_LABELS[LABEL] == NAME
    slider = controls.BY_KEY["tag.h"]
    assert slider.systems == (NAME,) and slider.text == "h (kg m^2/s)" and slider.hint == PARAM.meaning
    assert (FOLDER, ("tag.h",)) in controls.FOLDERS
    assert controls.FOLDERS[-1][0] == "Initial state"  # a system's folder comes before the start's
    assert controls.BY_KEY["body.A"].systems[-1] == NAME  # the body's sliders apply to it too
    assert set(controls.FIDELITIES) >= set(toy.fidelities)


def test_the_panel_shows_the_toy_in_its_dropdown_and_its_slider_hidden_on_another_systems_scene(toy):
    eng = Engine()  # the default scene: a moving mass
    gui = _RecordingGui()
    panel = Panel(SimpleNamespace(gui=gui, scene=None), eng)
    assert LABEL in panel.system.options
    handle = panel.sliders["tag.h"]
    assert handle.label == "h (kg m^2/s)" and handle.hint == PARAM.meaning
    panel.sync()
    assert handle.disabled is True and panel.folders[FOLDER].visible is False
    assert panel.folders["Body inertia"].visible is True


def test_a_slider_value_applies_to_a_toy_scenario(toy):
    sc = physics.Scenario.from_toml(EXAMPLE)
    assert sc.system == NAME and controls.values_of(sc)["tag.h"] == 0.1
    changed = controls.apply_changes(sc, {"tag.h": 0.25, "body.A": 1.2, "mass.m": 0.1})
    assert changed.system == NAME and changed.tag == Tag(0.25) and changed.body.A == 1.2
    assert changed.mass is None  # a moving-mass slider on the toy's scene is kept for later, not applied
    with pytest.raises(physics.ScenarioError, match=r"tag\.h = nan: must be a finite number"):
        controls.apply_changes(sc, {"tag.h": float("nan")})
    default = physics.default_scenario()
    assert controls.apply_changes(default, {"tag.h": 0.5}) == default  # and the toy's on another scene


def test_choosing_the_toy_keeps_the_body_and_its_slider_edits_the_run(toy):
    eng = Engine()
    gui = _RecordingGui()
    panel = Panel(SimpleNamespace(gui=gui, scene=None), eng)
    eng.request_value("body.A", 1.3)
    eng.tick(DT)
    eng.request("system", NAME)
    eng.tick(DT)
    assert eng.error == "" and eng.scenario.system == NAME and eng.scenario.body.A == 1.3
    assert eng.preset == f"{presets.system_template(NAME)[1]}, body kept"
    eng.request_value("tag.h", 0.4)
    eng.tick(DT)
    assert eng.error == "" and eng.scenario.tag == Tag(0.4) and eng.values["tag.h"] == 0.4
    panel.sync()
    assert panel.folders[FOLDER].visible is True and panel.sliders["tag.h"].disabled is False
    mass_folder = controls.FOLDERS[0][0]
    assert panel.folders[mass_folder].visible is False and panel.sliders["mass.m"].disabled is True
    assert panel.system.value == LABEL


def test_an_unregistered_system_leaves_the_lists():
    with toy_system():
        assert LABEL in controls.SYSTEM_LABELS
    assert LABEL not in controls.SYSTEM_LABELS and "tag.h" not in controls.BY_KEY
    assert all(FOLDER != title for title, _ in controls.FOLDERS)
