"""The study panels' parameter lists name a slider as the slider reads ("spring k (N m/rad)"), not by its scenario
key, and turn a chosen name back into the key; a name the system does not offer (a raw client) is refused with the
names that are."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

import physics

pytest.importorskip("plotly")
from fake_gui import FakeGui  # noqa: E402

from app.engine import controls  # noqa: E402
from app.studies import slider_choice  # noqa: E402
from app.studies.design_panel import DesignPanel  # noqa: E402
from app.studies.slider_choice import NONE, key_of, options, sweepable, text_of  # noqa: E402
from app.studies.sweep_panel import SweepPanel  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
SCENES = ("oblate_settling.toml", "pendulum_resonant.toml", "plane_pendulums_three.toml")


@pytest.mark.parametrize("name", SCENES)
def test_every_option_is_the_slider_s_own_text_and_names_its_key(name):
    sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / name)
    texts = options(sc, optional=False)
    assert texts and NONE not in texts
    assert [key_of(t, sc.system) for t in texts] == sweepable(sc)
    for t in texts:
        key = key_of(t, sc.system)
        assert t == controls.BY_KEY[key].text and "." not in t.split(" (")[0], t  # "m (kg)", never "mass.m"
        assert text_of(key, sc.system) == t
    assert options(sc, optional=True) == [NONE, *texts]


def test_texts_not_offered_name_no_key():
    system = physics.default_scenario().system
    for raw in (NONE, "mass.m", "m", "", "spring k (N m/rad)", None, 3.0, ["m (kg)"]):
        assert key_of(raw, system) is None, raw
    assert key_of("m (kg)", system) == "mass.m"


def test_two_sliders_that_read_alike_are_told_apart_by_key(monkeypatch):
    # through the registry: BY_KEY is read from it at each use (a module __getattr__), and an attribute set on the
    # module would outlive the test and hide systems registered later (the toy system's test failed on it)
    reg = controls.registry()
    a, b = reg.by_key["mass.chi"], reg.by_key["mass.Omega"]
    twin = {**reg.by_key, "mass.Omega": dataclasses.replace(b, label=a.label, unit=a.unit)}
    monkeypatch.setattr(controls, "registry", lambda: dataclasses.replace(reg, by_key=twin))
    names = slider_choice.names("moving_mass")
    assert names["chi (1/s) [mass.chi]"] == "mass.chi" and names["chi (1/s) [mass.Omega]"] == "mass.Omega"
    assert "chi (1/s)" not in names and len(set(names.values())) == len(names)


@pytest.mark.parametrize("make", [SweepPanel, DesignPanel])
def test_a_panel_refuses_a_raw_parameter_with_the_names_it_offers(make):
    sc = physics.default_scenario().with_values(**{"run.t_end": 2.0, "run.samples": 21})
    panel = make(FakeGui(), lambda: sc, lambda s: None, executor="serial")
    first = panel.key1 if make is SweepPanel else panel.slots[0][0]
    assert first.value == controls.BY_KEY["mass.m"].text  # the first slider, by its text
    first.value = "mass.m"  # the old key is not a name the panel offers
    with pytest.raises(physics.ScenarioError) as err:
        panel.request()
    said = str(err.value)
    assert "parameter" in said and "'mass.m'" in said and "m (kg)" in said and "chi (1/s)" in said, said
    panel.run_btn.fire()
    assert panel.thread is None and "m (kg)" in panel.status.content
