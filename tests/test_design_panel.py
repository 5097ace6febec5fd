"""The explorer's Design panel, headless: a fake gui records the widgets, the design runs for real (issue 26)."""

from __future__ import annotations

from pathlib import Path

import pytest

import physics

pytest.importorskip("plotly")
from fake_gui import FakeGui, in_a_row  # noqa: E402

from app.engine.compare import SLIDERS, parse  # noqa: E402
from app.engine.controls import BY_KEY  # noqa: E402
from app.studies.design_panel import BESIDE_SCENE, MAX_RUNS, NONE, DesignPanel  # noqa: E402


def named(key: str) -> str:
    """The text a parameter dropdown offers for the slider ``key`` (its label and unit, as the slider reads)."""
    return BY_KEY[key].text


ROOT = Path(__file__).resolve().parent.parent


def _scene() -> physics.Scenario:
    sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / "pendulum_resonant.toml")
    return sc.with_values(**{"run.t_end": 20.0, "run.samples": 201})


class _Recording:
    """A plot handle that keeps every figure it was given."""

    def __init__(self, handle, charts):
        object.__setattr__(self, "_handle", handle)
        object.__setattr__(self, "_charts", charts)

    def __getattr__(self, name):
        return getattr(self._handle, name)

    def __setattr__(self, name, value):
        if name == "figure":
            self._charts.append(value)
        setattr(self._handle, name, value)


def _panel():
    loaded, compared = [], []
    sc = _scene()
    panel = DesignPanel(FakeGui(), lambda: sc, loaded.append, compare=compared.append, executor="serial")
    return panel, loaded, compared


def test_a_design_from_the_panel_is_shown_taken_and_compared_beside_the_papers_tuning():
    panel, loaded, compared = _panel()
    (key1, lo1, hi1), (key2, lo2, hi2), (key3, _, _) = panel.slots
    key1.value = named("pendulum.k")
    key1.fire()
    k = physics.derived(_scene())["k"]
    assert (lo1.value, hi1.value) == (float(f"{k / 2:.4g}"), float(f"{2 * k:.4g}"))  # the sweep's default range
    key2.value = named("pendulum.c_d")
    key2.fire()
    assert key3.value == NONE
    panel.runs.value = 60
    panel.runs.fire()
    charts = []
    panel.plot = _Recording(panel.plot, charts)
    panel.run_btn.fire()
    panel.thread.join(timeout=120)
    assert not panel.thread.is_alive() and not panel.run_btn.disabled and panel.stop_btn.disabled
    # the runs were charted as they came, then once more when done
    counts = [sum(len(t.x) for t in fig.data if t.mode == "markers") for fig in charts]
    assert counts[0] == 1 and counts[1:4] == [5, 10, 15] and counts[-1] == panel.result.evaluations
    result = panel.result
    assert result is not None and result.keys == ("pendulum.k", "pendulum.c_d") and result.evaluations <= 60
    assert panel.bar.value == 100.0
    text = panel.result_md.content
    assert "**Optimum**" in text and "from the full model" in text and "resonance" in text
    assert "k = " in text and "N m/rad" in text
    scatter = [t for t in panel.plot.figure.data if t.mode == "markers"]
    assert sum(len(t.x) for t in scatter) == result.evaluations
    # one click: the optimum
    panel.take_btn.fire()
    assert loaded[-1].pendulum.k == result.best["pendulum.k"] and loaded[-1].pendulum.c_d == result.best["pendulum.c_d"]
    # beside this scene: compare mode with both sliders as one difference
    assert panel.beside.options[0] == BESIDE_SCENE and len(panel.beside.options) == 3
    panel.compare_btn.fire()
    spec = compared[-1]
    assert spec[0] == SLIDERS and dict(spec[1]) == result.best
    assert parse(spec).pairs() == tuple(result.best.items())  # the engine takes it as it is
    # beside the papers' resonance: that scene is loaded first, as the first run
    panel.beside.value = panel.beside.options[1]
    panel.compare_btn.fire()
    tuned = result.references[panel.beside.value][0]
    assert loaded[-1].pendulum.k == pytest.approx(tuned["pendulum.k"]) and compared[-1] == spec


def test_bad_input_is_said_in_the_panel():
    panel, _, _ = _panel()
    (key1, _, _), (key2, _, _), _ = panel.slots
    key1.value = key2.value = named("pendulum.k")
    panel.run_btn.fire()
    assert panel.thread is None and "chosen twice" in panel.status.content
    key2.value = NONE
    lo, hi = panel.slots[0][1], panel.slots[0][2]
    lo.value, hi.value = hi.value, lo.value
    panel.run_btn.fire()
    assert panel.thread is None and "must be finite with from < to" in panel.status.content
    panel.runs.value = 1e9  # a raw client: refused, the last good count kept
    panel.runs.fire()
    assert panel.runs.value == 120 and f"from 20 to {MAX_RUNS}" in panel.status.content
    lo.value, hi.value = hi.value, lo.value
    panel.objective.value = "speed"  # a raw client's text: refused by name before a thread starts
    panel.run_btn.fire()
    assert panel.thread is None and "objective = 'speed': must be one of decay_time" in panel.status.content
    panel.take_btn.fire()
    assert "Run a design first" in panel.status.content


def test_the_result_goes_stale_when_the_scene_changes():
    sc = _scene()
    scenes = [sc]
    panel = DesignPanel(FakeGui(), lambda: scenes[-1], lambda s: None, executor="serial")
    panel.slots[0][0].value = named("pendulum.c_d")
    panel.slots[0][0].fire()
    panel.run_btn.fire()
    panel.thread.join(timeout=120)
    assert not panel.stale
    scenes.append(sc.with_values(**{"pendulum.c_d": 3.0}))  # only the designed key: still current
    panel.scene_changed()
    assert not panel.stale
    scenes.append(sc.with_values(**{"pendulum.m": 4.0}))
    panel.scene_changed()
    assert panel.stale and "Stale" in panel.result_md.content


def test_stop_during_the_first_run_says_there_is_nothing_to_show():
    """A scene whose first run takes tens of seconds (t_end 4e5 s: too long for the averaged model's attitude
    budget, so auto runs the full model): Stop ends it, the panel says why no optimum came and the buttons are
    ready for the next design (Stop waited for the whole first run before)."""
    sc = _scene().with_values(**{"run.t_end": 4e5})
    panel = DesignPanel(FakeGui(), lambda: sc, lambda _: None, executor="serial")
    key1 = panel.slots[0][0]
    key1.value = named("pendulum.k")
    key1.fire()
    panel.run_btn.fire()
    assert panel.thread is not None and not panel.stop_btn.disabled
    panel.thread.join(timeout=1.0)
    panel.stop_btn.fire()
    panel.thread.join(timeout=30)
    assert not panel.thread.is_alive(), "the design went on after Stop for 30 s"
    assert "Stopped before the first run ended: there is no optimum to show" in panel.status.content
    assert panel.result_md.content == panel.status.content  # the window says it too: it has no result to show
    assert panel.result is None and not panel.run_btn.disabled and panel.stop_btn.disabled


def test_the_status_line_sits_under_run_and_stop():
    """At 1024x768 the folder's top is a scroll away from Run once the panel is open, so a refusal said there
    looked like a click with no answer: the line that says it comes right after the buttons and the bar."""
    gui = FakeGui()
    sc = _scene()
    panel = DesignPanel(gui, lambda: sc, lambda s: None, executor="serial")
    assert in_a_row(gui, panel.run_btn, panel.stop_btn, panel.bar, panel.status)
    (key1, _, _), (key2, _, _), _ = panel.slots
    key1.value = key2.value = named("pendulum.k")
    panel.run_btn.fire()
    assert "chosen twice" in panel.status.content
    assert panel.result_md.content == panel.status.content  # the window, below the fold's line, says it too


@pytest.mark.parametrize("raised, said", [
    (KeyError("x"), "**Design failed:** KeyError: 'x'"),  # said as "'x'" alone before
    (physics.ScenarioError("run.t_end", 5.0, "must be more"), "**Design failed:** run.t_end = 5.0: must be more"),
])
def test_a_design_that_fails_says_what_ended_it(monkeypatch, raised, said):
    def fail(*_, **__):
        raise raised

    monkeypatch.setattr(physics, "design", fail)
    panel, _, _ = _panel()
    panel.run_btn.fire()
    panel.thread.join(timeout=30)
    assert panel.status.content == said and panel.result_md.content == said


def test_before_its_first_design_the_chart_says_what_it_will_show_and_draws_no_axes():
    """An empty plotly chart drew placeholder ticks (0 to 6 by -1 to 4) that read as data."""
    panel, _, _ = _panel()
    fig = panel.plot.figure
    assert fig.layout.xaxis.visible is False and fig.layout.yaxis.visible is False and not fig.data
    assert [a.text for a in fig.layout.annotations] == ["each run's objective, drawn as the design runs"]
