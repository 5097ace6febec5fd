"""The explorer's sweep panel, headless: a fake gui records the widgets, the sweep runs for real."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import physics

pytest.importorskip("plotly")
from fake_gui import FakeGui, Handle, in_a_row  # noqa: E402

from app.engine.controls import BY_KEY  # noqa: E402
from app.studies import slider_choice, sweep_panel  # noqa: E402
from app.studies.sweep_panel import MAX_POINTS, NONE, SweepPanel  # noqa: E402


def named(key: str) -> str:
    """The text a parameter dropdown offers for the slider ``key`` (its label and unit, as the slider reads)."""
    return BY_KEY[key].text


ROOT = Path(__file__).resolve().parent.parent


def _scene() -> physics.Scenario:
    sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / "pendulum_resonant.toml")
    return sc.with_values(**{"run.t_end": 12.0, "run.samples": 121})


def test_panel_offers_the_systems_sliders_only():
    sc = _scene()
    keys = slider_choice.sweepable(sc)
    assert "pendulum.k" in keys and "pendulum.c_d" in keys and "mass.chi" not in keys
    plane = physics.Scenario.load(ROOT / "assets" / "scenarios" / "plane_pendulums_three.toml")
    assert "pendulum.h" not in slider_choice.sweepable(plane)  # the spherical pendulum's pivot only
    mass = physics.Scenario.load(ROOT / "assets" / "scenarios" / "oblate_settling.toml")
    assert {"mass.chi", "medium.lambda", "control.b"} <= set(slider_choice.sweepable(mass))
    assert "cavity.nu" not in slider_choice.sweepable(mass)  # no cavity in that file


def test_panel_runs_a_heat_map_and_loads_the_best_point():
    sc = _scene()
    loaded = []
    gui = FakeGui()
    panel = SweepPanel(gui, lambda: sc, loaded.append, executor="serial")
    assert {h.kind for h in gui.handles} >= {"dropdown", "number", "button", "progress", "plotly"}
    panel.key1.value = named("pendulum.k")
    panel.key1.fire()  # k = "resonant" in the file: the range is around the stiffness it tunes to
    k = physics.derived(sc)["k"]
    assert (panel.lo1.value, panel.hi1.value) == (float(f"{k / 2:.4g}"), float(f"{2 * k:.4g}"))
    panel.key1.value = named("pendulum.c_d")
    panel.key1.fire()  # the range follows the parameter: around the scene's c_d = 8
    assert (panel.lo1.value, panel.hi1.value) == (4.0, 16.0)
    panel.n1.value = 3
    panel.key2.value = named("pendulum.m")
    panel.key2.fire()
    panel.n2.value = 2
    panel.metric.value = "decay_time"
    panel.run_btn.fire()
    panel.thread.join(timeout=60)
    assert not panel.thread.is_alive()
    assert panel.bar.value == 100.0 and not panel.run_btn.disabled
    table = panel.table
    assert table.keys == ("pendulum.c_d", "pendulum.m") and table.shape == (3, 2)
    heat = panel.plot.figure.data[0]
    assert heat.type == "heatmap" and len(heat.z) == 3 and len(heat.z[0]) == 2
    # the dropdown lists the points best first; loading hands that scenario to the scene
    values = [table.rows[i]["decay_time"] for i in panel._points.values()]
    assert values == sorted(values) and panel.point.value == panel.point.options[0]
    panel.load_btn.fire()
    best = min(table.rows, key=lambda r: r["decay_time"])
    assert len(loaded) == 1
    assert loaded[0].pendulum.c_d == best["pendulum.c_d"] and loaded[0].pendulum.m == best["pendulum.m"]


def test_panel_reports_errors_instead_of_raising():
    sc = _scene()
    gui = FakeGui()
    panel = SweepPanel(gui, lambda: sc, lambda s: None, executor="serial")
    panel.key1.value = named("pendulum.k")
    panel.key2.value = named("pendulum.k")
    panel.run_btn.fire()  # the same slider twice
    assert panel.thread is None and "Cannot start" in panel.status.content
    panel.key2.value = NONE
    panel.log1.value, panel.lo1.value = True, -1.0  # log spacing from a negative value
    panel.run_btn.fire()
    assert panel.thread is None and "LO > 0" in panel.status.content
    panel.load_btn.fire()  # nothing computed yet
    assert "Run a sweep first" in panel.status.content

    def broken():
        raise RuntimeError("scene gone")

    panel.get_scenario = broken
    panel.run_btn.fire()
    assert "scene gone" in panel.status.content


def test_panel_one_parameter_draws_a_curve_on_worker_processes():
    sc = _scene()
    gui = FakeGui()
    panel = SweepPanel(gui, lambda: sc, lambda s: None, workers=1)  # the default: local worker processes
    panel.key1.value = named("pendulum.c_d")
    panel.key1.fire()
    panel.n1.value = 2
    panel.start().join(timeout=120)
    curve = panel.plot.figure.data[0]
    assert curve.type == "scatter" and len(curve.x) == 2
    assert all(math.isfinite(v) for v in curve.y) and "2 points" in panel.status.content


class FakeScene:
    """Records the board's cells; a cell's click callback is fired by the test."""

    def __init__(self):
        self.nodes = {}

    def _add(self, name, **kw):
        h = Handle("node", name)
        h.kw = kw
        h.remove = lambda name=name: self.nodes.pop(name, None)
        self.nodes[name] = h
        return h

    def add_box(self, name, **kw):
        return self._add(name, **kw)

    def add_label(self, name, text, **kw):
        return self._add(name, text=text, **kw)


def test_clicking_a_cell_of_the_scene_board_loads_its_point():
    sc = _scene()
    loaded = []
    scene = FakeScene()
    panel = SweepPanel(FakeGui(), lambda: sc, loaded.append, executor="serial", scene=scene)
    panel.board_box.value = True  # the board is opt-in: the result's own window holds the heat map
    panel.key1.value = named("pendulum.c_d")
    panel.key1.fire()
    panel.n1.value = 3
    panel.key2.value = named("pendulum.m")
    panel.key2.fire()
    panel.n2.value = 2
    panel.run_btn.fire()
    panel.thread.join(timeout=60)
    table = panel.table
    cells = {name: h for name, h in scene.nodes.items() if "/cell" in name}
    assert len(cells) == 6 and "Click a cell" in panel.status.content
    values = table.column("decay_time")
    darkest = min(cells.values(), key=lambda h: sum(h.kw["color"]))
    assert darkest.label.endswith(f"cell{int(np.argmin(values))}")  # the smallest metric is the darkest cell
    i = 4
    cells[f"/sweep_board/cell{i}"].fire()  # a click
    assert len(loaded) == 1
    row = table.rows[i]
    assert loaded[0].pendulum.c_d == row["pendulum.c_d"] and loaded[0].pendulum.m == row["pendulum.m"]
    panel.run_btn.fire()  # a new sweep replaces the board
    panel.thread.join(timeout=60)
    assert len([n for n in scene.nodes if "/cell" in n]) == 6


@pytest.mark.parametrize("sent", [1e9, 0, -3, 2.5, MAX_POINTS + 1, "abc", None, {"a": 1}, True])
def test_a_points_count_the_browser_would_not_send_is_refused_on_the_server(sent):
    """The points boxes' bounds hold only in the browser (issue 24: a raw client's 1e9, then a parameter change,
    grew the server to 3.5 GB): the server refuses it in words, the box shows the count kept, a range reset and
    a run use that count."""
    gui = FakeGui()
    panel = SweepPanel(gui, _scene, lambda sc: None, executor="serial")
    panel.n1.value = 5
    panel.n1.fire()
    panel.n1.value = sent
    panel.n1.fire()
    assert panel.n1.value == 5
    assert "points" in panel.status.content and "refused" in panel.status.content
    assert f"from 1 to {MAX_POINTS}" in panel.status.content
    panel.n1.value = sent  # had it reached the box unscreened, a range reset and a run still refuse it
    panel.key1.fire()
    with pytest.raises(physics.ScenarioError, match="points"):
        panel.request()


def test_a_stopped_sweep_says_its_points_were_not_run_rather_than_failed():
    """Stop 1 s into points of 12 s or more (t_end 4e5 s: auto runs the full model): the runs end, and the panel
    counts the points the stop left as not run; it said "4 failed" and listed them as failures."""
    sc = _scene().with_values(**{"run.t_end": 4e5, "run.samples": 201})
    panel = SweepPanel(FakeGui(), lambda: sc, lambda _: None, executor="serial")
    panel.key1.value = named("pendulum.k")
    panel.key1.fire()
    panel.n1.value = 3
    panel.run_btn.fire()
    panel.thread.join(timeout=1.0)
    panel.stop_btn.fire()
    panel.thread.join(timeout=30)
    assert not panel.thread.is_alive()
    assert panel.table.stopped and panel.table.failed == 0
    assert "3 points in" in panel.status.content and "(stopped: 3 not run)" in panel.status.content
    assert "failed" not in panel.status.content, panel.status.content
    summary = panel.result_md.content
    assert "3 point(s) not run (#0, #1, #2): the sweep was stopped first" in summary and "failed" not in summary


def test_a_sweep_that_fails_says_so_in_the_window_too(monkeypatch):
    """With no earlier result the Sweep window showed only its placeholder after a failed sweep; the status line
    sits a scroll above Run at 1024x768, so the failure is said in the window as well."""
    def broken(*args, **kwargs):
        raise RuntimeError("the pool broke")

    monkeypatch.setattr(sweep_panel.physics, "sweep", broken)
    panel = SweepPanel(FakeGui(), _scene, lambda _: None, executor="serial")
    panel.start().join(timeout=30)
    assert "**Sweep failed:** RuntimeError: the pool broke" in panel.status.content
    assert panel.result_md.content == panel.status.content


def test_the_status_line_sits_under_run_and_stop():
    """As the design panel's (tests/test_design_panel.py): the refusal is said where the click was."""
    sc = _scene()
    gui = FakeGui()
    panel = SweepPanel(gui, lambda: sc, lambda s: None, executor="serial")
    assert in_a_row(gui, panel.run_btn, panel.stop_btn, panel.bar, panel.status)
    panel.key1.value = panel.key2.value = named("pendulum.k")
    panel.run_btn.fire()
    assert "Cannot start" in panel.status.content
    # at 1400x900 that line sits below the panel's fold: the window, with no result yet, says it too
    assert panel.result_md.content == panel.status.content
    panel.key2.value = NONE
    panel.run_btn.fire()  # the next Run's news replaces the refusal there
    assert panel.result_md.content.startswith("Running ") and panel.result_md.content == panel.status.content
    panel.thread.join(timeout=60)
    summary = panel.result_md.content
    assert panel.table is not None and "Running" not in summary
    panel.key2.value = named("pendulum.k")
    panel.run_btn.fire()  # a window with a result keeps it; the refusal is in the status line
    assert "Cannot start" in panel.status.content and panel.result_md.content == summary


def test_an_end_no_scene_can_take_is_refused_before_the_sweep_starts():
    """A user typed from = 5 kg for m in a 1 kg body: the sweep used to start and fail as
    "Sweep failed: ScenarioError: ...". It is refused at Run, in words, with no thread started."""
    sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / "oblate_settling.toml").with_values(
        **{"run.t_end": 2.0})
    panel = SweepPanel(FakeGui(), lambda: sc, lambda s: None, executor="serial")
    panel.key1.value = named("mass.m")
    panel.key1.fire()
    panel.lo1.value = 5.0
    panel.run_btn.fire()
    said = panel.status.content
    assert panel.thread is None and said.startswith("**Cannot start:**"), said
    assert "mass.m = 5.0" in said and "must be less than body.M" in said and "ScenarioError" not in said
    panel.n1.value = 1  # one point runs "from" alone: a "to" no scene can take is not in the sweep
    panel.n1.fire()
    panel.lo1.value, panel.hi1.value = 0.1, 5.0
    panel.run_btn.fire()
    assert panel.thread is not None, panel.status.content
    panel.thread.join(timeout=120)
    assert panel.table is not None and len(panel.table.rows) == 1


def test_before_its_first_sweep_the_chart_says_what_it_will_show_and_draws_no_axes():
    """An empty plotly chart drew placeholder ticks (0 to 6 by -1 to 4) that read as data."""
    sc = _scene()
    panel = SweepPanel(FakeGui(), lambda: sc, lambda s: None, executor="serial")
    fig = panel.plot.figure
    assert fig.layout.xaxis.visible is False and fig.layout.yaxis.visible is False and not fig.data
    assert [a.text for a in fig.layout.annotations] == ["the metric over the points swept, once they are run"]
