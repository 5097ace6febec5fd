"""The sweep and design panels run one study at a time (app/studies/background.py): a second Run while one runs is
told so and starts nothing, Run and Stop are enabled as the study runs and ends, and a study that raises is said in
the panel with its kind, the buttons given back."""

from __future__ import annotations

import threading

import pytest

import physics

pytest.importorskip("plotly")
from fake_gui import FakeGui  # noqa: E402

from app.studies.design_panel import DesignPanel  # noqa: E402
from app.studies.sweep_panel import SweepPanel  # noqa: E402

PANELS = [(SweepPanel, "sweep"), (DesignPanel, "design")]


def _panel(make):
    sc = physics.default_scenario().with_values(**{"run.t_end": 2.0, "run.samples": 21})
    return make(FakeGui(), lambda: sc, lambda s: None, executor="serial")


@pytest.mark.parametrize(("make", "study"), PANELS)
def test_a_second_run_while_one_runs_is_told_so_and_the_buttons_follow_the_run(monkeypatch, make, study):
    gate, entered = threading.Event(), threading.Event()

    def held(*_, **__):
        entered.set()
        gate.wait(30)
        raise RuntimeError("released")

    monkeypatch.setattr(physics, study, held)
    panel = _panel(make)
    first = panel.start()
    assert first is not None and entered.wait(30)
    assert panel.run_btn.disabled and not panel.stop_btn.disabled
    assert panel.start() is None and panel.thread is first
    assert panel.status.content == f"A {study} is running; **Stop {study}** ends it."
    gate.set()
    first.join(30)
    assert not first.is_alive() and not panel.run_btn.disabled and panel.stop_btn.disabled
    assert panel.status.content == f"**{study.capitalize()} failed:** RuntimeError: released"
    assert panel.result_md.content == panel.status.content  # no result yet: the window says it too


@pytest.mark.parametrize(("make", "study"), PANELS)
def test_bad_input_starts_nothing_and_leaves_the_buttons(make, study):
    panel = _panel(make)
    (panel.lo1 if make is SweepPanel else panel.slots[0][1]).value = float("nan")
    assert panel.start() is None and panel.thread is None
    assert panel.status.content.startswith("**Cannot start:**") and not panel.run_btn.disabled
