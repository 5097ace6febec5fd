"""The explorer's "speed vs accuracy" panel, headless: a fake gui records the widgets; the sweep is
physics.work_precision for real on a short scene, or a stand-in where a failure is the point."""

from __future__ import annotations

import threading

import pytest

import physics
from physics.reference.problems import moving_mass

pytest.importorskip("plotly")
from fake_gui import FakeGui  # noqa: E402

from app.studies.speed_panel import NOTHING_YET, SpeedPanel, figure  # noqa: E402

ACCURACY = 1e-6  # rad, the scene's requested theta accuracy
JOIN_S = 120.0  # the sweep thread must end well within this


def _scene():
    return moving_mass(0.1, t_end=100.0, samples=101).with_values(**{"run.accuracy": ACCURACY})


def test_sweep_runs_in_the_background_and_the_recommendation_is_applied():
    gui, applied = FakeGui(), []
    scene = _scene()
    panel = SpeedPanel(gui, lambda: scene, applied.append)
    use = gui.button("Use recommended")
    assert use.disabled and use.label == NOTHING_YET
    gui.button("Run speed vs accuracy sweep").fire()
    panel.thread.join(JOIN_S)
    assert not panel.thread.is_alive() and panel.thread.daemon
    best = panel.result.recommended
    assert best is not None and best.error <= ACCURACY
    assert panel.bar.value == 100.0
    assert not use.disabled and use.label.startswith("Use recommended: ")
    assert "Recommended" in panel.status.content
    traces = {t.name for t in panel.plot.figure.data}
    assert {"DOP853", "RK4", "RK8", "recommended"} <= traces
    assert panel.plot.figure.layout.xaxis.type == "log" and panel.plot.figure.layout.yaxis.type == "log"
    use.fire()
    assert len(applied) == 1
    sc = applied[0]
    assert sc.run.method == best.method
    assert (sc.run.rtol if best.method == "auto" else sc.run.dt) == pytest.approx(best.setting)
    assert sc.run.t_end == scene.run.t_end and sc.mass == scene.mass  # only the run settings changed


def test_a_failing_sweep_is_a_message_not_an_exception():
    gui, applied = FakeGui(), []

    def broken(sc, progress=None, cancel=None):
        progress(0.5)
        raise RuntimeError("kernel exploded")

    panel = SpeedPanel(gui, _scene, applied.append, sweep=broken)
    panel.start().join(JOIN_S)
    assert "Sweep failed" in panel.status.content and "kernel exploded" in panel.status.content
    assert gui.button("Use recommended").disabled and not gui.button("Run speed").disabled
    panel.use_recommended()  # nothing to use: says so, applies nothing
    assert applied == [] and "no recommendation" in panel.status.content


def test_recommendation_is_refused_after_the_scene_changed_system():
    from physics.reference.problems import p4

    gui, applied = FakeGui(), []
    scenes = [_scene()]
    panel = SpeedPanel(gui, lambda: scenes[-1], applied.append)
    panel.start().join(JOIN_S)
    scenes.append(p4(10.0))
    assert panel.use_recommended() is None and applied == []
    assert "changed since the sweep" in panel.status.content


def test_empty_figure_has_log_axes():
    fig = figure(None)
    assert not fig.data and fig.layout.xaxis.type == "log"


def test_panel_module_uses_only_physics_exports():
    import ast
    from pathlib import Path

    src = (Path(__file__).resolve().parents[1] / "app" / "studies" / "speed_panel.py").read_text()
    for node in ast.walk(ast.parse(src)):
        if isinstance(node, ast.ImportFrom) and node.module:
            assert not node.module.startswith("physics."), node.module
    assert hasattr(physics, "WorkPrecision") and hasattr(physics, "WorkPrecisionRow")


def test_a_failed_sweep_after_a_good_one_says_the_chart_is_the_earlier_sweep_s_and_keeps_it_usable():
    """The chart and the Use button still hold the first sweep's result when a second one fails; the status line,
    which replaces that result's summary, must say so and keep the summary, and the button must work again."""
    gui, applied = FakeGui(), []
    scene = _scene()
    first = physics.work_precision(scene)
    calls = []
    gate = threading.Event()

    def sweep(sc, progress=None, cancel=None):
        calls.append(sc)
        if len(calls) == 1:
            return first
        gate.wait(JOIN_S)
        raise RuntimeError("kernel exploded")

    panel = SpeedPanel(gui, lambda: scene, applied.append, sweep=sweep)
    panel.start().join(JOIN_S)
    use = gui.button("Use recommended")
    assert first.recommended is not None and not use.disabled
    shown = panel.plot.figure
    label = use.label
    second = panel.start()
    assert "Sweeping" in panel.status.content and "earlier sweep" in panel.status.content
    assert "Recommended" in panel.status.content and use.disabled
    panel.scene_changed()  # the session calls this on every scene change, also while the sweep runs
    assert "Sweeping" in panel.status.content and use.disabled
    gate.set()
    second.join(JOIN_S)
    text = panel.status.content
    assert "Sweep failed" in text and "kernel exploded" in text
    assert "earlier sweep" in text and "Recommended" in text  # the result still on the chart is named
    assert panel.plot.figure is shown and use.label == label and not use.disabled
    use.fire()
    assert len(applied) == 1 and applied[0].run.method == first.recommended.method


def test_a_failed_sweep_after_a_good_one_on_a_changed_scene_says_stale():
    gui = FakeGui()
    scenes = [_scene()]
    first = physics.work_precision(scenes[0])
    outcomes = iter([first, RuntimeError("kernel exploded")])

    def sweep(sc, progress=None, cancel=None):
        out = next(outcomes)
        if isinstance(out, Exception):
            raise out
        return out

    panel = SpeedPanel(gui, lambda: scenes[-1], lambda sc: None, sweep=sweep)
    panel.start().join(JOIN_S)
    scenes.append(scenes[0].with_values(**{"mass.m": scenes[0].mass.m * 2}))
    panel.scene_changed()
    assert panel.stale
    panel.start().join(JOIN_S)
    text = panel.status.content
    assert "Sweep failed" in text and "Stale" in text and "earlier sweep" in text
    assert gui.button("Use recommended").disabled
