"""Numerical faults (issue 7): each is detected and the run stops cleanly with a message that says what
happened and at what time, through ``physics.simulate`` (raises IntegrationFault; braking ends the run
normally) and through ``physics.LiveRun`` (status and message, never raised; the last good state kept),
and in the app's Engine, which pauses on them and shows the message.

Every scenario here is valid input: the faults come from the numbers, not from tampering.
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest

import physics
from physics import IntegrationFault, LiveRun, Scenario, ScenarioError
from physics.stepping.live import BRAKED, FAULT, RUNNING
from physics.systems.moving_mass.closed import braking_time

TIME_TOL = 1e-6  # relative, on the braking time T


def _mass(**changes) -> dict:
    d = {"body": {"A": 1.0, "C": 1.4, "M": 1.0}, "mass": {"m": 0.2, "rho": 1.5, "Omega": 5.0, "chi": 5.0},
         "initial": {"G0": 3.0, "theta0": 0.8}, "run": {"fidelity": "full", "t_end": 10.0, "samples": 11}}
    for path, value in changes.items():
        table, _, key = path.partition("__")
        d.setdefault(table, {})[key] = value
    return d


BLOW_UP = _mass()
BLOW_UP["initial"] = {"omega": [1e160, 0.0, 1e160]}  # finite input whose energy overflows to inf
UNDERFLOW = _mass(mass__chi=1e16)  # a damping rate so fast that the stable step is under 1e-14 s
STIFF_LIVE = _mass(mass__Omega=1e7, mass__chi=1e7)  # stable steps of 3e-7 s against a motion of seconds
GIMBAL = {"body": {"A": 1.0, "C": 1.4, "M": 1.0},  # a bob above its pivot with no spring: it falls over
          "pendulum": {"m": 0.05, "l": 0.3, "h": 0.2, "k": 0.0, "c_d": 0.001},
          "initial": {"G0": 2.0, "theta0": 0.1}, "run": {"fidelity": "full", "t_end": 30.0, "samples": 31}}
GIMBAL_SPRING = {**GIMBAL, "pendulum": {**GIMBAL["pendulum"], "k": 1e-4}}  # a spring on the Cardan angles
BRAKING = _mass(control__b=0.3)  # T = G0 / b = 10 s (no medium)
INVARIANT_TOL = 1e-9  # relative drift of the inertial K and of E + W (tests/test_pendulum_full.py's)


def _at(message: str) -> float:
    """The time a message reports, 'at t = <number>'."""
    m = re.search(r"at t = ([-+0-9.eE]+)", message)
    assert m, message
    return float(m.group(1))


def _live_until_stopped(sc: Scenario, dt: float = 1.0, calls: int = 60) -> tuple[LiveRun, list]:
    run = LiveRun(sc)
    pieces = []
    for _ in range(calls):
        pieces.append(run.advance(dt, samples=4))
        if run.ended:
            break
    return run, pieces


def _assert_stopped_cleanly(run: LiveRun) -> None:
    assert np.all(np.isfinite(run.y)) and np.all(np.isfinite(run.last.theta))
    t, last = run.t, run.last
    assert len(run.advance(1.0)) == 0 and run.t == t and run.last is last  # stays stopped, no exception
    run.reset()
    assert run.status == RUNNING and run.t == 0.0


# ---- blow-up to NaN or infinity ---------------------------------------------------------------------
def test_blow_up_through_simulate():
    # a fault before the first step is the input's: it names the key (issue 24)
    with pytest.raises(IntegrationFault, match=r"non-finite \(NaN or infinity\) at t = 0; the most extreme value "
                                               r"is initial\.omega = ") as info:
        physics.simulate(Scenario.from_dict(BLOW_UP))
    assert info.value.t == 0.0


def test_blow_up_through_live_run_is_refused_up_front():
    """A live run never starts from a state whose readouts are not finite (issue 17: such a scenario is
    refused up front, naming the value; a viewer showed NaN readouts with the run "running" before)."""
    with pytest.raises(ScenarioError, match=r"^initial\.omega = .*non-finite") as info:
        LiveRun(Scenario.from_dict(BLOW_UP))
    assert info.value.key == "initial.omega"


# ---- step-size underflow -----------------------------------------------------------------------------
def test_step_size_underflow_through_simulate():
    with pytest.raises(IntegrationFault, match="step size underflow at t = ") as info:
        physics.simulate(Scenario.from_dict(UNDERFLOW))
    assert info.value.t == _at(str(info.value)) and 0.0 <= info.value.t < 1e-6


def test_step_size_underflow_through_live_run():
    run, _ = _live_until_stopped(Scenario.from_dict(UNDERFLOW))
    assert run.status == FAULT and "step size underflow" in run.message
    assert _at(run.message) == pytest.approx(run.t, abs=1e-12)
    _assert_stopped_cleanly(run)


# ---- stiffness beyond the chosen method -----------------------------------------------------------------
def test_fixed_step_beyond_its_stability_limit_blows_up_through_simulate():
    stiff = _mass(mass__Omega=50.0, mass__chi=5.0, run__method="RK4", run__dt=0.5)
    with pytest.raises(IntegrationFault, match=r"non-finite .* at t = ") as info:
        physics.simulate(Scenario.from_dict(stiff))
    assert 0.0 < info.value.t < 10.0  # mid-run, at the step where it overflowed
    assert info.value.t / 0.5 == pytest.approx(round(info.value.t / 0.5))  # a whole number of steps
    # the same problem at a step inside RK4's stability region runs to the end
    ok = physics.simulate(Scenario.from_dict(_mass(mass__Omega=50.0, mass__chi=5.0, run__method="RK4",
                                                   run__dt=0.005)))
    assert ok.info["stop_reason"] == "reached t_end" and np.all(np.isfinite(ok.theta))


def test_too_stiff_for_the_explicit_integrator_through_live_run():
    run = LiveRun(Scenario.from_dict(STIFF_LIVE))
    run.advance(1.0)  # more than one call's step budget: every step is held at the stability limit
    assert run.status == FAULT and "too stiff for the explicit integrator" in run.message
    assert "h |lambda|" in run.message and _at(run.message) == pytest.approx(run.t, rel=1e-15) and run.t > 0
    _assert_stopped_cleanly(run)


def test_stiffness_is_found_when_the_steps_come_in_small_calls():
    """The explorer asks for a few milliseconds' worth of steps per frame, so no single call runs out of
    steps: the check runs every MAX_STEPS_PER_CALL steps however they were split."""
    from physics.stepping.live import MAX_STEPS_PER_CALL

    run = LiveRun(Scenario.from_dict(STIFF_LIVE))
    for _ in range(400):
        run.advance(2e-3)  # about 7k steps each at the stable step of 3e-7 s
        if run.status != RUNNING:
            break
    assert run.status == FAULT and "too stiff for the explicit integrator" in run.message
    assert run.nsteps >= MAX_STEPS_PER_CALL  # found at the first check, not by a call running out
    _assert_stopped_cleanly(run)


def test_an_accuracy_bound_fast_problem_is_not_called_stiff():
    """Fast but undamped (chi = 0): the steps resolve the oscillation, so running out of one call's
    budget is slow progress, not a fault."""
    run = LiveRun(Scenario.from_dict(_mass(mass__Omega=1e7, mass__chi=0.0)))
    run.advance(1.0)
    assert run.status == RUNNING and 0 < run.t < 1.0


# ---- the end of braking (|G| -> 0) ---------------------------------------------------------------------
def test_end_of_braking_through_simulate():
    sc = Scenario.from_dict(BRAKING)
    T = braking_time(3.0, 0.3, 0.0)
    tr = physics.simulate(sc)
    assert tr.info["stop_reason"] == "braking brought |G| to zero"
    assert tr.info["t_stop"] == pytest.approx(T, rel=TIME_TOL) and tr.t[-1] == tr.info["t_stop"]


def test_end_of_braking_through_live_run():
    run, _ = _live_until_stopped(Scenario.from_dict(BRAKING))
    T = braking_time(3.0, 0.3, 0.0)
    assert run.status == BRAKED and "braking brought |G| to zero" in run.message
    assert _at(run.message) == pytest.approx(T, rel=TIME_TOL) and run.t == pytest.approx(T, rel=TIME_TOL)
    _assert_stopped_cleanly(run)


# ---- the gimbal singularity ------------------------------------------------------------------------------
# Without a spring the bob passes the Cardan angles' pole: the kernel switches charts (issue 17), so the
# run goes on. With a spring on the Cardan angles (undefined at the pole) it still stops there, cleanly.
def _gimbal(c_d: float, samples: int = 3001) -> Scenario:
    d = {**GIMBAL, "pendulum": {**GIMBAL["pendulum"], "c_d": c_d}, "run": {**GIMBAL["run"], "samples": samples}}
    return Scenario.from_dict(d)


def _states(tr) -> np.ndarray:
    return np.hstack([tr.omega] + [tr.internal[k][:, None] for k in ("alpha", "beta", "alpha_dot", "beta_dot")]
                     + [tr.quat, tr.internal["W_diss"][:, None], tr.internal["chart"][:, None]])


def _assert_invariants(tr, sc: Scenario, damped: bool) -> None:
    """Inertial K conserved; E falls by the damper's work only (and stays put without a damper)."""
    model = physics.get_model(sc.system, "full")
    K, E = model.invariants(_states(tr), model.pack(sc))
    W = tr.internal["W_diss"]
    assert np.max(np.linalg.norm(K - K[0], axis=1)) <= INVARIANT_TOL * np.linalg.norm(K[0])
    assert np.max(np.abs(E[0] - E - W)) <= INVARIANT_TOL * E[0]
    if damped:
        assert W[-1] > 1e-3 * E[0]  # the damper really worked
    else:
        assert np.all(W == 0.0) and np.max(np.abs(E - E[0])) <= INVARIANT_TOL * E[0]


def _bob(tr, sc: Scenario) -> tuple[np.ndarray, np.ndarray]:
    """The bob's position from the carrier's COM (n, 3) and its speed relative to the carrier (n,)."""
    from physics.compiled import pendulum as kernel

    p = physics.get_model(sc.system, "full").pack(sc)
    Y = _states(tr)
    R = np.array([kernel._state_geometry(y, p)[0][0] for y in Y])
    speed = np.array([np.linalg.norm(kernel._state_geometry(y, p)[1][0] @ y[5:7]) for y in Y])
    return R, speed


@pytest.mark.parametrize("c_d", [0.001, 0.0], ids=["damped", "undamped"])
def test_gimbal_pole_is_passed_through_simulate(c_d):
    sc = _gimbal(c_d)
    tr = physics.simulate(sc)
    assert tr.t[-1] == 30.0 and tr.info["stop_reason"] == "reached t_end"
    chart = tr.internal["chart"]
    switches = int(np.sum(chart[1:] != chart[:-1]))
    assert switches >= 3 and set(np.unique(chart)) == {0.0, 1.0}  # several passes near the old pole
    assert np.max(np.abs(np.sin(tr.internal["beta"]))) < 1.0 - 1e-3  # neither chart comes near its own pole
    _assert_invariants(tr, sc, damped=c_d > 0)
    # the bob's position is continuous across the switches: between samples it moves at most its speed
    # times the sample interval (a wrong map between the charts moves it by a good part of l = 0.3 m)
    R, speed = _bob(tr, sc)
    dt = np.diff(tr.t)
    jump = np.linalg.norm(np.diff(R, axis=0), axis=1)
    assert np.all(jump <= 1.5 * np.maximum(speed[1:], speed[:-1]) * dt + 1e-12)


def test_a_chart_switch_keeps_the_motion_exactly():
    from physics.compiled import pendulum as kernel

    sc = _gimbal(0.001)
    model = physics.get_model(sc.system, "full")
    p = model.pack(sc)
    tr = physics.simulate(sc)
    done = 0
    for y in _states(tr)[::20]:  # each sampled state, written in the other chart where that chart is regular
        z = y.copy()
        kernel.to_chart(z, 1 - int(y[kernel.CHART]))
        assert z[kernel.CHART] != y[kernel.CHART]
        if abs(math.cos(z[4])) < 0.3:
            continue
        done += 1
        before, after = kernel._state_geometry(y, p), kernel._state_geometry(z, p)
        assert np.allclose(after[0], before[0], rtol=0, atol=1e-15)  # the bob's position (m)
        assert np.allclose(after[3], before[3], rtol=0, atol=1e-14)  # and velocity (m/s)
        assert np.allclose(kernel.momentum(z, p), kernel.momentum(y, p), rtol=1e-13, atol=0)
        assert kernel.energy(z, p) == pytest.approx(kernel.energy(y, p), rel=1e-13)
    assert done >= 100
    # switch_chart switches only near the pole of the chart in use (|beta| past 60 deg in chart 0)
    y = _states(tr)[0].copy()
    assert y[kernel.CHART] == 0.0 and kernel.switch_chart(y, p) == 0
    y[4] = math.radians(61.0)
    assert kernel.switch_chart(y, p) == 1 and y[kernel.CHART] == 1.0 and kernel.switch_chart(y, p) == 0


def test_the_app_draws_the_bob_in_the_chart_in_use():
    from physics.compiled import pendulum as kernel
    from physics.systems.pendulum.figure import spherical_bob

    sc = _gimbal(0.0, samples=301)
    p = physics.get_model(sc.system, "full").pack(sc)
    tr = physics.simulate(sc)
    Y = _states(tr)
    assert set(np.unique(Y[:, kernel.CHART])) == {0.0, 1.0}
    for y in Y:
        R = kernel._state_geometry(y, p)[0][0]
        pivot, bob = spherical_bob(sc.pendulum.h, sc.pendulum.l, y[3], y[4], y[kernel.CHART])
        np.testing.assert_allclose(bob - pivot, R - p[kernel.HEADER + 4:kernel.HEADER + 7], atol=1e-15)


def test_gimbal_pole_is_passed_through_live_run():
    sc = _gimbal(0.001, samples=31)
    run = LiveRun(sc)
    rows = []
    while run.t < 30.0 - 1e-9 and run.status == RUNNING:
        rows.append(run.advance(min(0.5, 30.0 - run.t), samples=50))
    assert run.status == RUNNING and run.message in (None, "") and run.t == pytest.approx(30.0, abs=1e-12)
    chart = np.concatenate([r.internal["chart"] for r in rows])
    assert int(np.sum(chart[1:] != chart[:-1])) >= 3
    K = np.concatenate([r.K for r in rows])
    E = np.concatenate([r.E for r in rows])
    W = np.concatenate([r.internal["W_diss"] for r in rows])
    assert np.max(np.abs(K - K[0])) <= INVARIANT_TOL * K[0]
    assert np.max(np.abs(E[0] - E - W)) <= INVARIANT_TOL * E[0] and W[-1] > 1e-3 * E[0]


def test_gimbal_singularity_with_a_spring_through_simulate():
    with pytest.raises(IntegrationFault, match=r"gimbal singularity .*\(\|beta\| -> 90 deg\) at t = ") as info:
        physics.simulate(Scenario.from_dict(GIMBAL_SPRING))
    assert 1.0 < info.value.t < 30.0 and "spring" in str(info.value)


def test_gimbal_singularity_with_a_spring_through_live_run():
    run, _ = _live_until_stopped(Scenario.from_dict(GIMBAL_SPRING))
    assert run.status == FAULT and "gimbal singularity" in run.message
    ref = None
    try:
        physics.simulate(Scenario.from_dict(GIMBAL_SPRING))
    except IntegrationFault as exc:
        ref = exc.t
    assert _at(run.message) == pytest.approx(ref, rel=1e-5)  # where simulate stops, to the tolerance
    _assert_stopped_cleanly(run)


def test_the_app_engine_runs_past_the_gimbal_pole():
    from app.state import Engine

    eng = Engine(Scenario.from_dict(GIMBAL))
    eng.warp = 10.0
    for _ in range(400):  # at least real time a tick: 40 s of simulated time at most
        fr = eng.tick(0.1)
        if fr.status != RUNNING or fr.t >= 30.0:
            break
    assert fr.status == RUNNING and not fr.message and fr.t >= 30.0
    assert math.isfinite(fr.theta) and np.all(np.isfinite(fr.part("bob0").centre))


# ---- the app: the tab pauses on a fault, keeps the last good state and says why --------------------------
def test_the_app_engine_refuses_a_scene_that_starts_non_finite_and_keeps_the_last_good():
    from app.state import Engine

    eng = Engine()
    before = eng.scenario
    eng.request("scenario", (Scenario.from_dict(BLOW_UP), "blow-up"))
    fr = eng.tick(0.1)
    assert "initial.omega" in eng.error and "non-finite" in eng.error
    assert eng.scenario == before and fr.status == RUNNING and math.isfinite(fr.E)


@pytest.mark.parametrize("data, needle", [(GIMBAL_SPRING, "gimbal singularity"),
                                          (STIFF_LIVE, "too stiff"), (BRAKING, "braking brought")])
def test_the_app_engine_stops_and_shows_why(data, needle):
    from app.state import Engine

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        eng = Engine(Scenario.from_dict(data))
    eng.warp = 10.0
    for _ in range(400):
        fr = eng.tick(0.1)
        if fr.status != RUNNING:
            break
    assert fr.status in (FAULT, BRAKED) and needle in fr.message and "at t = " in fr.message
    assert math.isfinite(fr.theta) and np.all(np.isfinite(fr.body_wxyz))
    t = fr.t
    assert eng.tick(0.1).t == t  # stays where it stopped
    assert Scenario.from_toml(eng.toml().decode()) == eng.scenario  # and the scenario can still be exported
