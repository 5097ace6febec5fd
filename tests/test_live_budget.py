"""A live run's call is bounded in steps whatever the scenario asks (issue 17): RK4 at run.dt = 1e-12 s used to
integrate a whole frame's worth (1.7e10 steps) in one call, freezing the tab and, after it closed, a core."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import physics
from physics.stepping.live import EARLY_STEPS, MAX_STEPS_PER_CALL

ROOT = Path(__file__).resolve().parent.parent


def _tiny_step():
    return physics.default_scenario().with_values(**{"run.method": "RK4", "run.dt": 1e-12})


def test_a_fixed_step_call_takes_at_most_the_per_call_budget():
    run = physics.LiveRun(_tiny_step())
    tr = run.advance(1.0 / 60, samples=4)
    assert 0 < run.nsteps <= MAX_STEPS_PER_CALL
    assert 0 < run.t <= MAX_STEPS_PER_CALL * 1e-12 * (1 + 1e-9)  # the run slowed instead
    assert len(tr) >= 1 and run.status == "running"


def test_the_engine_ticks_such_a_scene_in_bounded_steps():
    from app.state import Engine

    eng = Engine(_tiny_step(), )
    for _ in range(3):
        n0 = eng.run.nsteps
        eng.tick(1.0 / 60)
        assert eng.run.nsteps - n0 <= 2 * MAX_STEPS_PER_CALL  # the frame's own step and its trail's
    assert eng.run.status == "running" and eng.run.t > 0


def _stiff():
    """A pivot damper so strong that DOP853's step is held at its stability limit, ~3e-14 s."""
    return physics.Scenario.load(ROOT / "assets" / "scenarios" / "pendulum_resonant.toml").with_values(
        **{"pendulum.c_d": 1e12, "run.fidelity": "full"})


def test_a_stiff_scene_is_refused_within_the_first_calls_early_steps():
    """Found at the end of the call's MAX_STEPS_PER_CALL steps, such a scene cost its tab 1.9 s at every restart
    (tests/test_fuzz_engine.py's seed 85 ran 66 s in the suite); the early look finds it in EARLY_STEPS."""
    run = physics.LiveRun(_stiff())
    run.advance(1.0 / 30, samples=4)
    assert run.status == "fault" and run.nsteps == EARLY_STEPS
    assert run.message.startswith(f"too stiff for the explicit integrator (DOP853): {EARLY_STEPS} steps covered")
    assert "pendulum.c_d" in run.message
    run.retune(_stiff(), keep_state=False)  # a restart looks again
    run.advance(1.0 / 30, samples=4)
    assert run.status == "fault" and run.nsteps == EARLY_STEPS


def test_a_first_call_longer_than_the_early_steps_goes_on_to_the_end_of_its_span():
    """The early look splits the first call; a scene that is not stiff gets the whole span and its rows at the
    times asked for, as from one call."""
    sc = physics.default_scenario().with_values(**{"run.fidelity": "full"})
    split, whole = physics.LiveRun(sc), physics.LiveRun(sc)
    whole._early = False
    a, b = split.advance(2000.0, samples=5), whole.advance(2000.0, samples=5)
    assert split.nsteps > EARLY_STEPS and split.status == "running"
    np.testing.assert_allclose(a.t, [400.0, 800.0, 1200.0, 1600.0, 2000.0], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(a.t, b.t)
    np.testing.assert_allclose(a.theta, b.theta, rtol=0, atol=1e-8)
