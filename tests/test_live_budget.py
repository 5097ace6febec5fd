"""A live run's call is bounded in steps whatever the scenario asks (issue 17): RK4 at run.dt = 1e-12 s used to
integrate a whole frame's worth (1.7e10 steps) in one call, freezing the tab and, after it closed, a core."""

from __future__ import annotations

import physics
from physics.stepping.live import MAX_STEPS_PER_CALL


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
