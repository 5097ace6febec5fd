"""What one slider change costs the tab's loop: the tick that applies it builds and validates the new scenario
once, and calls few functions of the project (counted, never timed: a count is the same on any machine).

The engine judges a typed value by building the scenario it makes (app.engine.edits, the guard's screen); the
tick then applies that very scenario instead of building it again, and the panel's run-level choices (fidelity,
auto's accuracy, pivot) are already in the base it is built from (Engine._chosen_base), so no third build adds
them. Before: 2 ``Scenario.from_dict`` and 3 scenarios built, 1,412 project calls (612 in physics/registry.py);
after: 1, 1 and 996 (408), on the default scene, paused, mass.m 0.21 -> 0.22 kg; with physics's table lookup
made a dict read (a Scenario's part attributes no longer walk the registry's tables), 665 calls, of which 11
look a system or a model up in the registry (``get_system``, ``get_model``, ``systems``, ``tables``).
"""

from __future__ import annotations

import sys
import threading
from collections import Counter
from pathlib import Path

import physics
from app.engine.engine import Engine
from physics.kernels.build import wait as kernel_build_done

ROOT = Path(__file__).resolve().parents[1]
PROJECT = (str(ROOT / "physics") + "/", str(ROOT / "app") + "/")
FRAME_S = 1.0 / 60.0
CALLS_MAX = 1100  # project calls in the tick that applies one slider change: 665 measured, 1,412 before
LOOKUPS_MAX = 15  # registry lookups of a system or a model in that tick: 11 measured (hundreds before)
LOOKUPS = ("get_system", "get_model", "systems", "tables")
BUILD_WAIT_S = 600.0  # a kernel build an earlier test started (numba: minutes on a busy machine)


def _warm_engine(first_value: float) -> Engine:
    """The default scene, paused, after one slider change already applied: whatever a first use compiles
    (numba loads a kernel on its first call) is done before anything is counted, and a build an earlier test
    started has finished, so the counted tick does not switch to compiled kernels halfway."""
    kernel_build_done(BUILD_WAIT_S)
    eng = Engine()
    eng.playing = False  # the apply path alone: stepping's cost depends on the clock's budget
    for _ in range(3):
        eng.tick(FRAME_S)
    eng.request_value("mass.m", first_value)
    eng.tick(FRAME_S)
    return eng


def _one_change(monkeypatch):
    """(scenarios built, from_dict calls, project calls by (file, function)) in the tick after one slider change,
    counted on this thread only (the engine's workers run on their own)."""
    eng = _warm_engine(0.21)
    me = threading.get_ident()
    built, from_dict, calls = Counter(), Counter(), Counter()
    init, parse = physics.Scenario.__init__, physics.Scenario.from_dict.__func__

    def counted_init(self, *args, **kwargs):
        if threading.get_ident() == me:
            built["Scenario"] += 1
        return init(self, *args, **kwargs)

    def counted_from_dict(cls, data):
        if threading.get_ident() == me:
            from_dict["Scenario.from_dict"] += 1
        return parse(cls, data)

    def profile(frame, event, _arg):
        if event == "call" and frame.f_code.co_filename.startswith(PROJECT):
            calls[(frame.f_code.co_filename, frame.f_code.co_name)] += 1

    eng.request_value("mass.m", 0.22)
    monkeypatch.setattr(physics.Scenario, "__init__", counted_init)
    monkeypatch.setattr(physics.Scenario, "from_dict", classmethod(counted_from_dict))
    sys.setprofile(profile)
    try:
        eng.tick(FRAME_S)
    finally:
        sys.setprofile(None)
    monkeypatch.undo()
    assert eng.error == "" and eng.values["mass.m"] == 0.22 and eng.scenario.mass.m == 0.22  # the change applied
    return built["Scenario"], from_dict["Scenario.from_dict"], calls


def test_a_slider_change_builds_its_scenario_once(monkeypatch):
    built, parsed, _ = _one_change(monkeypatch)
    assert (built, parsed) == (1, 1)


def test_a_slider_change_calls_few_project_functions(monkeypatch):
    _, _, calls = _one_change(monkeypatch)
    total = sum(calls.values())
    assert total <= CALLS_MAX, (total, calls.most_common(10))


def test_a_slider_change_looks_the_registry_up_a_handful_of_times(monkeypatch):
    _, _, calls = _one_change(monkeypatch)
    lookups = {name: n for (path, name), n in calls.items()
               if path.endswith("physics/registry.py") and name in LOOKUPS}
    assert 0 < sum(lookups.values()) <= LOOKUPS_MAX, lookups


def test_the_choices_a_slider_change_keeps_are_built_once_not_per_change(monkeypatch):
    """After a fidelity chosen by hand, a slider change still builds one scenario, with that fidelity in it."""
    eng = _warm_engine(0.2)
    eng.request("fidelity", "averaged")
    eng.tick(FRAME_S)
    eng.request_value("mass.m", 0.21)
    eng.tick(FRAME_S)  # the base with the choice is built here, with the first change after the choice
    me, built = threading.get_ident(), Counter()
    init = physics.Scenario.__init__

    def counted_init(self, *args, **kwargs):
        if threading.get_ident() == me:
            built["Scenario"] += 1
        return init(self, *args, **kwargs)

    eng.request_value("mass.m", 0.22)
    monkeypatch.setattr(physics.Scenario, "__init__", counted_init)
    eng.tick(FRAME_S)
    monkeypatch.undo()
    assert built["Scenario"] == 1
    assert eng.scenario.run.fidelity == "averaged" and eng.scenario.mass.m == 0.22


def test_a_playing_tick_asks_the_model_for_its_momentum_twice_however_many_samples_it_draws(monkeypatch):
    """The trail's points of a frame's samples share one K (the frame's): asking the model's invariants once per
    sample cost 6 calls a tick at 4 samples, half the tick's time on the default scene."""
    eng = _warm_engine(0.2)
    eng.playing = True
    counted = Counter()
    run_type = type(eng.run)
    momentum = run_type.momentum

    def counted_momentum(self):
        counted["momentum"] += 1
        return momentum(self)

    monkeypatch.setattr(run_type, "momentum", counted_momentum)
    for warp in (1.0, 1e4):  # 1e4: the frame's last turns are sampled densely for the trail (app.engine.trail)
        eng.warp = warp
        eng.tick(FRAME_S)
        counted.clear()
        ticks_before, samples_before = eng.frames, eng.plot_all.appended
        for _ in range(10):
            eng.tick(FRAME_S)
        assert eng.frames - ticks_before == 10 and eng.plot_all.appended - samples_before >= 30, warp  # it drew samples
        assert counted["momentum"] <= 2 * 10, (warp, counted)
