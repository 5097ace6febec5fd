"""The app's engine under anything a raw websocket client can send (issue 17): every slider key and every
action, with values across magnitudes (5e-324 to 1e308, both signs, 0, NaN, inf) and of the wrong type,
in a seeded random order. Each tick must return a frame (never raise), with finite numbers or the run
stopped as a fault; a rejected change must say why; and no tick may integrate without a bound (the
engine's frame budget and LiveRun's step budget), which is counted in integrator steps, not timed."""

from __future__ import annotations

import math
import random
import re

import numpy as np
import pytest
from fake_gui import FakeGui, chart_finite

from app.engine import controls, presets
from app.engine.buffers import PENDING_EACH
from app.panel.plots import build_plots, update_plots
from app.state import FRAME_HZ, Engine

pytestmark = [pytest.mark.filterwarnings("ignore::physics.ValidityWarning"),
              pytest.mark.filterwarnings("ignore::RuntimeWarning")]
MAGNITUDES = (5e-324, 1e-300, 1e-12, 1e-3, 0.5, 1.0, 3.0, 1e3, 1e12, 1e200, 1e308)
ODD = (0.0, math.nan, math.inf, -math.inf, "1", "resonant", None, [1.0], {"a": 1})
ACTIONS = ("play", "pause", "step", "reset", "warp", "preset", "system", "fidelity", "view", "exaggeration",
           "overlay", "tune", "bob", "polhode", "restart_on_change", "accuracy", "pivot", "no such action")
CHANGES = 400
# What Python and numpy say of a value they cannot take, which the tab showed before the values were checked where
# they arrive (a warp of "bogus": "could not convert string to float"; a preset of [1.0]: "unhashable type")
PYTHONS_WORDS = re.compile(r"[A-Z][A-Za-z]*Error\b|could not convert|invalid literal|unhashable|not supported between"
                           r"|\(34, 'Numerical result")
STEPS_PER_TICK_MAX = 400_000  # LiveRun's per-call budget (200k) twice over: a tick is bounded by counts


def _value(rng: random.Random):
    if rng.random() < 0.25:
        return rng.choice(ODD)
    return rng.choice((1, -1)) * rng.choice(MAGNITUDES)


def _action_value(rng: random.Random, action: str):
    good = {"preset": presets.preset_names(), "system": ["moving_mass", "spherical_pendulum", "plane_pendulums"],
            "fidelity": ["auto", "full", "averaged", "closed"], "view": ["inertial", "body"],
            "overlay": ["none", "averaged", "closed"], "accuracy": [None, 1e-4, 1e-2, 0.1],
            "pivot": ["cardan", "isotropic"]}
    if action in good and rng.random() < 0.6:
        return rng.choice(good[action])
    return _value(rng) if rng.random() < 0.7 else rng.choice(("bogus", "", "../../etc/passwd"))


def _frame_is_sane(fr, eng: Engine) -> None:
    numbers = [fr.t, fr.theta, fr.K, fr.E]
    if fr.status == "running":
        assert all(math.isfinite(x) for x in numbers), (numbers, eng.scenario)
        for v in (fr.K_vec, fr.omega_vec, fr.axis_vec, fr.body_wxyz):
            assert np.all(np.isfinite(v)), (v, eng.scenario)
    else:
        assert fr.status in ("braked", "fault") and fr.message, (fr.status, fr.message)


def _charts_are_sane(charts, eng: Engine) -> None:
    """The charts take the run's plot data as the tab does (a subnormal theta once raised ZeroDivisionError
    there): every plotted number and axis end finite."""
    update_plots(charts, eng.plot_data())
    for h in charts.handles.values():
        assert chart_finite(h), (h.title, h.scales, eng.scenario)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2, 3, 23, 60, 85])  # 3, 60 and 85 found a NaN shown as running (closed
# form with G0 = 5e-324; a body of M = 5e-324 drawn at an infinite size) in a 120-seed run; 23 is the first of 15 in
# 1-82 whose theta chart the plot scale of b3488bd drew as inf (a subnormal theta over 10.0**-324 == 0.0)
def test_the_engine_survives_anything_a_client_sends(seed):
    rng = random.Random(seed)
    eng = Engine()
    charts = build_plots(FakeGui(), eng.plot_data())  # the tab's charts take every frame's data too
    keys = [p.key for p in controls.PARAMS]
    rejected = 0
    for _ in range(CHANGES):
        before = eng.scenario
        if rng.random() < 0.6:
            eng.request_value(rng.choice(keys), _value(rng))
        else:
            action = rng.choice(ACTIONS)
            eng.request(action, _action_value(rng, action))
        steps0, run0 = eng.run.nsteps, eng.run
        fr = eng.tick(1.0 / FRAME_HZ)  # never raises
        if eng.run is run0:
            assert eng.run.nsteps - steps0 <= STEPS_PER_TICK_MAX
        _frame_is_sane(fr, eng)
        _charts_are_sane(charts, eng)
        if eng.error:
            rejected += 1
            assert eng.scenario == before or eng.scenario is not None  # the last good scenario stays usable
            assert len(eng.error) < 2000  # said in a line, not a dump
            assert not PYTHONS_WORDS.search(eng.error), eng.error  # the project's words, naming what was refused
        if fr.status == "fault" and rng.random() < 0.5:
            eng.request("reset")  # as a user would: the fault's own recovery
            eng.tick(1.0 / FRAME_HZ)
    assert rejected > 0  # the storm did contain bad values, and they were said
    eng.request("preset", presets.DEFAULT)
    eng.request("play")
    t0 = eng.tick(1.0 / FRAME_HZ).t
    assert eng.tick(1.0 / FRAME_HZ).t > t0  # and the tab still plays


@pytest.mark.parametrize("sent", [{"a": 1}, [1.0], None, "1", True])
def test_a_slider_sent_something_else_than_a_number_is_refused_in_words(sent):
    """The note beside the slider says what came and what is allowed; before, a dict or a string made the
    note's own formatting fail ("TypeError: unsupported format string passed to dict.__format__")."""
    eng = Engine()
    eng.request_value("body.M", sent)
    eng.tick(1.0 / FRAME_HZ)
    assert eng.error == f"body.M = {sent!r}: must be a number"
    assert eng.guard.note.text == f"Rejected: M = {sent!r}: must be a number. M stays 1 kg."
    assert eng.scenario.body.M == 1.0


@pytest.mark.parametrize("sent", [[1.0], "bogus", None, 3.0])
def test_an_overlay_that_is_not_offered_is_refused_and_no_worker_starts(sent, capfd):
    eng = Engine()
    eng.request("overlay", sent)
    eng.tick(1.0 / FRAME_HZ)
    assert "overlay" in eng.error and "expected one of none, averaged, closed" in eng.error
    assert eng.overlay_fidelity == "none" and eng.prediction.thread is None
    assert "Traceback" not in capfd.readouterr().err  # before, the worker thread died printing one


def test_a_flood_of_any_action_queues_a_bounded_few_and_the_latest_counts():
    """A raw client's clicks at any rate between two ticks: at most PENDING_EACH of each action wait, so one tick
    applies a bounded few (10,000 Resets would each start a new run), and the latest request of each counts."""
    eng = Engine()
    eng.tick(1 / FRAME_HZ)
    for i in range(10_000):
        eng.request("reset")
        eng.request("warp", float(1 + i % 50))
        eng.request("play" if i % 2 else "pause")
    queued = [a for a, _ in eng._actions]
    assert len(queued) == 4 * PENDING_EACH  # reset, warp, play and pause
    assert queued.count("reset") == queued.count("warp") == PENDING_EACH
    fr = eng.tick(1 / FRAME_HZ)
    assert eng.warp == 50.0 and eng.playing and not eng._actions and eng.error == "" and fr.status == "running"


@pytest.mark.parametrize("action, sent, said", [
    # Python's own words before: "ValueError: could not convert string to float: 'bogus'", "KeyError: -1e+200",
    # "TypeError: unhashable type: 'list'"; none named what was refused or what is allowed
    ("warp", "bogus", "time warp 'bogus': expected a number of times real time (0.1x to 10000x)"),
    ("warp", math.inf, "time warp inf: expected a number of times real time (0.1x to 10000x)"),
    ("preset", -1e200, "preset '-1e+200': expected one of the presets"),
    ("preset", [1.0], "preset '[1.0]': expected one of the presets"),
    ("exaggeration", {"a": 1}, "exaggerate u (x) {'a': 1}: expected a number in [1, 1000]"),
    ("system", [1.0], "system = [1.0]: is not one of moving_mass, spherical_pendulum"),  # the storm's seed 85
])
def test_an_action_sent_a_value_it_cannot_take_says_which_and_what_it_takes(action, sent, said):
    eng = Engine()
    warp = eng.warp
    eng.request(action, sent)
    fr = eng.tick(1.0 / FRAME_HZ)
    assert eng.error.startswith(said) and "Error" not in eng.error
    assert fr.status == "running" and eng.warp == warp and eng.scenario.system == "moving_mass"


def test_a_bob_number_that_is_no_whole_number_is_refused_naming_the_bobs_it_may_be():
    eng = Engine()
    eng.request("system", "plane_pendulums")
    eng.tick(1.0 / FRAME_HZ)
    for sent in ("bogus", math.nan, math.inf, 1.5, [1]):
        eng.request("bob", sent)
        eng.tick(1.0 / FRAME_HZ)
        assert f"{sent!r}: expected a whole number from 0 to " in eng.error and "Error" not in eng.error, sent
    eng.request("bob", 1e300)  # a whole number past the last bob is the last, as a slider's end
    eng.tick(1.0 / FRAME_HZ)
    assert eng.item == len(eng.scenario.to_dict()["plane_pendulum"]) - 1


def test_a_value_that_is_not_a_number_is_judged_even_for_another_systems_slider():
    """body.B = None is a value (an axisymmetric body) and was applied, then failed comparing None with the
    slider's end ("TypeError: '>' not supported..."), which undid it; kept as the slider's value, it would have
    failed the panel's next sync the same way, so the slider shows the B it resolves to. A list sent to the
    wheel's slider while a moving-mass scene runs was kept unjudged and failed the same way."""
    eng = Engine()
    eng.request_value("body.B", None)
    eng.tick(1.0 / FRAME_HZ)
    assert eng.error == "" and eng.scenario.body.B == eng.scenario.body.A  # applied: B is A again
    assert eng.values["body.B"] == eng.scenario.body.A and eng.sliders_changed  # the slider shows the B that runs
    eng.request_value("wheel.c", [1.0])
    eng.tick(1.0 / FRAME_HZ)
    assert eng.error == "wheel.c = [1.0]: must be a number"
