"""physics.LiveRun: stepping in pieces agrees with one simulate run; retune keeps the state; the end of
braking and faults are reported, not raised."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import physics
from physics.stepping.live import BRAKED, FAULT, RUNNING, LiveRun

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")

ANGLE_TOL = 1e-7  # rad: two step sequences at rtol 1e-10 over a few seconds
REL_TOL = 1e-8  # relative, |K| and E
TIME_TOL = 1e-6  # s, braking end against the closed-form T
ROOT = Path(__file__).resolve().parents[1]
# a refusal or a fault is said in words; numpy's overflow warnings only printed to the server's console, where a
# lecturer serving a class read "overflow encountered in dot" for a value that had been refused cleanly
QUIET = pytest.mark.filterwarnings("error::RuntimeWarning")


def _default(t_end: float = 4.0, samples: int = 9, fidelity: str = "full") -> physics.Scenario:
    return physics.default_scenario().with_values(**{"run.t_end": t_end, "run.samples": samples,
                                                     "run.fidelity": fidelity})


@pytest.mark.parametrize("fidelity", ["full", "averaged", "closed"])
def test_advance_in_pieces_matches_one_simulate_run(fidelity):
    sc = _default(fidelity=fidelity)
    ref = physics.simulate(sc)
    run = LiveRun(sc)
    assert run.fidelity == fidelity
    rows = [run.advance(0.5) for _ in range(8)]
    t = np.concatenate([r.t for r in rows])
    theta = np.concatenate([r.theta for r in rows])
    K = np.concatenate([r.K for r in rows])
    np.testing.assert_allclose(t, ref.t[1:], rtol=0, atol=1e-12)
    np.testing.assert_allclose(theta, ref.theta[1:], rtol=0, atol=ANGLE_TOL)
    np.testing.assert_allclose(K, ref.K[1:], rtol=REL_TOL)
    np.testing.assert_allclose(run.last.quat[0], ref.quat[-1], atol=ANGLE_TOL)
    assert run.t == pytest.approx(4.0, abs=1e-12) and run.status == RUNNING


def test_advance_returns_the_samples_asked_for():
    run = LiveRun(_default())
    tr = run.advance(1.0, samples=4)
    np.testing.assert_allclose(tr.t, [0.25, 0.5, 0.75, 1.0], atol=1e-12)
    assert len(run.last) == 1 and run.last.t[0] == tr.t[-1]
    assert set(tr.internal) >= {"ux", "uy", "uz"}


def test_retune_keeps_state_and_changes_the_motion():
    sc = _default()
    run = LiveRun(sc)
    run.advance(1.0)
    y, t = run.y.copy(), run.t
    kept = run.retune(sc.with_values(**{"mass.chi": 2.0}))
    assert kept and run.t == t
    np.testing.assert_array_equal(run.y, y)
    assert run.scenario.mass.chi == 2.0
    a = run.advance(1.0).theta[-1]
    other = LiveRun(sc)
    other.advance(1.0)
    b = other.advance(1.0).theta[-1]
    assert abs(a - b) > 1e-6  # the new damping acts at once


def test_retune_restarts_when_asked_or_for_a_closed_form_and_carries_a_fidelity_change():
    sc = _default()
    run = LiveRun(sc)
    run.advance(1.0)
    assert not run.retune(sc, keep_state=False) and run.t == 0.0 and run.energy_change is None
    run.advance(1.0)
    t = run.t
    assert run.retune(sc, fidelity="averaged") and run.t == t and run.fidelity == "averaged"  # tests/test_carry.py
    assert run.retune(sc, fidelity="closed") and run.t == t and run.fidelity == "closed"  # restarted at t
    pendulum = physics.Scenario.from_dict({"body": {"A": 1.0, "C": 1.4, "M": 1.0},
                                           "initial": {"G0": 2.0, "theta0": 0.3},
                                           "pendulum": {"m": 0.05, "l": 0.3, "h": 0.5, "k": 0.5, "c_d": 0.01},
                                           "run": {"fidelity": "full", "t_end": 10.0}})
    run = LiveRun(pendulum)
    run.advance(0.5)
    t = run.t
    assert run.retune(pendulum, fidelity="averaged") and run.t == t and run.fidelity == "averaged"  # bob at rest
    assert run.edit_note == "" and run.origin is not None  # tests/test_restart_pendulum.py


def test_retune_rejects_a_bad_scenario_without_changing_anything():
    run = LiveRun(_default())
    run.advance(0.5)
    y = run.y.copy()
    with pytest.raises(physics.ScenarioError):
        run.retune(physics.default_scenario().with_values(**{"mass.m": 5.0}))
    np.testing.assert_array_equal(run.y, y)


def test_auto_resolves_and_says_why():
    run = LiveRun(_default(fidelity="auto"))
    assert run.requested == "auto" and run.fidelity in ("full", "averaged", "closed") and run.reason


def test_braking_end_is_reported_at_T():
    sc = physics.Scenario.load("assets/scenarios/braking_cavity_medium.toml").with_values(
        **{"run.fidelity": "averaged"})
    T = physics.derived(sc)["T"]
    run = LiveRun(sc)
    assert run.remaining_braking_time() == pytest.approx(T, rel=1e-9)
    for _ in range(100):
        run.advance(100.0)
        if run.ended:
            break
    assert run.status == BRAKED and "braking" in run.message
    assert run.t == pytest.approx(T, abs=TIME_TOL * T)
    assert run.remaining_braking_time() == 0.0
    assert len(run.advance(1.0)) == 0  # ended: nothing more, no exception


def test_a_fault_is_reported_not_raised():
    run = LiveRun(_default())
    run.advance(0.5)
    t, last = run.t, run.last
    run.p = run.p * math.nan  # poison the parameters: the right-hand side turns non-finite
    out = run.advance(0.5)
    assert run.status == FAULT and "at t = " in run.message
    assert len(out) == 0 and run.t == t and run.last is last
    assert np.all(np.isfinite(run.y))
    run.reset()
    assert run.status == RUNNING and run.t == 0.0


def test_pendulum_systems_step_live():
    sc = physics.Scenario.from_dict({
        "body": {"A": 1.0, "C": 1.4, "M": 1.0},
        "plane_pendulum": [{"preset": "in_plane", "m": 0.03, "l": 0.2, "k": 0.5, "c_d": 0.01, "R": 0.5,
                            "azimuth": a} for a in (0.0, 2.0944)],
        "initial": {"G0": 2.0, "theta0": 0.3}, "run": {"t_end": 2.0, "samples": 3, "fidelity": "full"}})
    ref = physics.simulate(sc)
    run = LiveRun(sc)
    run.advance(1.0)
    tr = run.advance(1.0)
    assert tr.theta[-1] == pytest.approx(ref.theta[-1], abs=ANGLE_TOL)
    assert "a1" in tr.internal


def test_braking_switched_on_mid_run_ends_at_the_remaining_time():
    sc = _default(fidelity="averaged")
    run = LiveRun(sc)
    run.advance(1.0)
    assert run.retune(sc.with_values(**{"control.b": 0.05}))
    left = run.remaining_braking_time()
    assert math.isfinite(left) and left > 0
    while not run.ended:
        run.advance(5.0)
    assert run.status == BRAKED
    assert run.t == pytest.approx(1.0 + left, abs=TIME_TOL * left)


@pytest.mark.parametrize("method", ["RK4", "RK8", "midpoint"])
def test_a_fixed_step_method_runs_live_as_simulate_runs_it(method):
    """run.method with run.dt steps the live run with that method: pieces land on simulate's states."""
    sc = physics.default_scenario().with_values(**{"run.method": method, "run.dt": 0.01, "run.t_end": 2.0,
                                                   "run.samples": 5, "run.fidelity": "full"})
    ref = physics.simulate(sc)
    run = physics.LiveRun(sc)
    rows = [run.advance(0.5, samples=1) for _ in range(4)]
    theta = np.array([r.theta[0] for r in rows])
    assert run.status == "running" and run.nsteps == 200  # 2 s in steps of 0.01 s
    np.testing.assert_allclose(theta, ref.theta[1:], rtol=0, atol=1e-12)


def test_midpoint_refuses_what_it_does_not_cover_live():
    sc = physics.default_scenario().with_values(**{"run.method": "midpoint", "run.dt": 0.01, "control.b": 0.01,
                                                   "control.law": "K"})
    with pytest.raises(physics.ScenarioError, match="midpoint"):
        physics.LiveRun(sc)


@QUIET
def test_a_reset_that_cannot_start_is_refused_with_the_run_as_it_was():
    """A value carried into a running state (mass.lam_q = 1e200: the state is kept, then the run faults) can
    make t = 0 non-finite; Reset must then say so by name and leave the run as it was, not half started at
    t = 0 with |K| = inf (found by tests/test_fuzz_engine.py's storm)."""
    sc = physics.default_scenario()
    run = LiveRun(sc)
    run.advance(1.0)
    assert run.retune(sc.with_values(**{"mass.lam_q": 1e200}), keep_state=True)
    run.advance(0.05)
    before = dict(vars(run))
    with pytest.raises(physics.ScenarioError, match=r"mass\.lam_q = 1e\+200.*non-finite"):
        run.reset()
    assert vars(run).keys() == before.keys() and all(vars(run)[k] is v for k, v in before.items())
    assert run.t == 1.0 and np.isfinite(run.last.K).all()


@QUIET
def test_a_closed_form_that_starts_non_finite_is_refused_by_name():
    """G0 = 1e-300 on the spherical pendulum's averaged solution gave K's direction as NaN at t = 0, shown as a
    running value (tests/test_fuzz_engine.py, seed 21); a closed form's start is now checked as a state is."""
    sc = physics.Scenario.from_dict({
        "body": {"A": 1.0, "C": 1.4, "M": 10.0},
        "pendulum": {"m": 0.05, "l": 0.3, "h": 0.5, "k": 3.0, "c_d": 0.01},
        "initial": {"G0": 1e-300, "theta0": 0.785}, "run": {"fidelity": "averaged", "t_end": 60.0}})
    with pytest.raises(physics.ScenarioError, match=r"initial\.G0 = 1e-300: makes the closed form's .* non-finite"):
        LiveRun(sc)
    assert np.isfinite(LiveRun(sc.with_values(**{"initial.G0": 1e-3})).momentum()).all()  # a small G0 is fine


def test_rows_that_turn_non_finite_stop_the_run_and_the_last_good_row_stays():
    """A finite state can still give a non-finite row (E = inf); the run stops there as a fault and keeps the
    last finite row, never showing NaN or inf as a running value."""
    run = LiveRun(_default())
    run.advance(0.2)
    good = run.last
    observe = run._observe

    def overflowing(t, Y):  # the model's own rows, with E overflowing from the second one on
        tr = observe(t, Y)
        tr.E[1:] = np.inf
        return tr

    run._observe = overflowing
    tr = run.advance(0.1, samples=4)
    assert run.status == FAULT and "non-finite" in run.message
    assert len(tr) == 1 and np.isfinite(run.last.E).all() and run.last.t[-1] > good.t[-1]
    assert run.advance(0.1).t.size == 0  # ended: nothing more is integrated


# Registry reads (calls of systems, get_system, get_model or tables, each of which checks the registry first) one
# slider change may make. Measured with this test's counter: from_dict 0 and retune 5 for each system's example;
# before the scenario kept its table maps per registry version, from_dict 20-28 and retune 13-21, each read of
# tables() walking every system's tables.
FROM_DICT_READS = 0
RETUNE_READS = 8


@pytest.mark.parametrize("system", ["moving_mass", "spherical_pendulum", "plane_pendulums"])
def test_a_slider_change_reads_the_registry_a_few_times(system, monkeypatch):
    from physics import registry

    sc = physics.Scenario.from_toml(physics.get_system(system).example)
    run = LiveRun(sc)
    data = sc.to_dict()
    table = next(t.name for t in physics.get_system(system).tables)
    for block in data[table] if isinstance(data[table], list) else [data[table]]:
        block["c_d" if "pendulum" in table else "chi"] *= 1.1
    reads = []
    ready = registry._ready
    monkeypatch.setattr(registry, "_ready", lambda: (reads.append(1), ready())[1])
    new = physics.Scenario.from_dict(data)
    assert len(reads) <= FROM_DICT_READS
    run.retune(new)
    assert 0 < len(reads) <= FROM_DICT_READS + RETUNE_READS  # 0: the count would not see reads at all


@QUIET
@pytest.mark.parametrize("scene, fidelity, changes, to, key, words", [
    # OverflowError from the quasi-static displacement, shown by the explorer as "OverflowError: (34, ...)"
    ("figures/seed000_fig1b_oblate", "auto", {"mass.Omega": 1.7e100, "run.t_end": 0.5}, "auto", "mass.Omega",
     "a number grew past the largest a float can hold"),
    # ValueError from the quadratic-friction closed form ("Bq0 = nan"), carried into at t > 0
    ("quadratic_friction", "averaged", {"body.C": 1e-100, "mass.Omega": 1e-308}, "closed", "mass.Omega",
     "not finite"),
    # LinAlgError from the pendulum's averaged exponents ("Array must not contain infs or NaNs")
    ("figures/seed002_frequencies_set_R", "averaged", {"pendulum.m": 1.7e-300, "pendulum.l": 1e-323}, "averaged",
     "pendulum.l", "not finite"),
])
def test_a_retune_the_arithmetic_cannot_take_is_refused_naming_the_key_and_the_run_goes_on(
        scene, fidelity, changes, to, key, words):
    sc0 = physics.Scenario.from_toml((ROOT / "assets" / "scenarios" / f"{scene}.toml").read_text())
    run = LiveRun(sc0, fidelity)
    run.advance(0.5, 3)
    before = dict(vars(run))
    with pytest.raises(physics.ScenarioError) as info:
        run.retune(sc0.with_values(**changes), to, keep_state=True)
    assert info.value.key == key and words in str(info.value) and "Error" not in str(info.value)
    assert all(vars(run)[k] is v for k, v in before.items())  # every attribute as it was
    assert run.status == RUNNING and len(run.advance(0.5, 3).t) == 3


def test_a_start_the_arithmetic_cannot_take_is_refused_naming_the_key():
    sc = physics.Scenario.from_toml((ROOT / "assets" / "scenarios" / "figures" / "seed000_fig1b_oblate.toml")
                                    .read_text()).with_values(**{"mass.Omega": 1.7e100, "run.t_end": 0.5})
    with pytest.raises(physics.ScenarioError) as info:
        LiveRun(sc, "auto")
    assert info.value.key == "mass.Omega" and "Error" not in str(info.value)


@QUIET
@pytest.mark.parametrize("changes", [
    {"mass.Omega": 1.7e-100},  # RightSideError: eq. (13)'s right side not finite at t = 0
    {"cavity.a0": 1e30, "medium.lambda": 5.1},  # RuntimeError: eq. (13)'s integration underflowed its step
])
def test_a_closed_form_that_fails_while_advancing_is_a_fault_not_an_exception(changes):
    """Found by the retune fuzz on seed 004's figures: the closed form's eq. (13) raised RuntimeError out of
    advance, which catches only ValueError; a fault is recorded, as the stepped models' are."""
    sc0 = physics.Scenario.from_toml((ROOT / "assets" / "scenarios" / "figures" / "seed004_fig1_prolate.toml")
                                     .read_text())
    run = LiveRun(sc0, "closed")
    run.retune(sc0.with_values(**changes), "closed", keep_state=True)  # nothing is evaluated until advance
    tr = run.advance(1.0, 5)
    assert run.status == FAULT and len(tr.t) == 0
    assert run.message.startswith("closed form failed: ") and "Error" not in run.message


def test_a_fault_at_the_start_names_the_value_as_simulate_does():
    """A body with C = 1e-8 beside A = B = 1 faults at t = 0 (the step size underflows). physics.simulate names
    body.C; the live run (the explorer's) said only "step size underflow at t = 0", so a scene loaded from a file
    or a share code stopped with no word of which value to change. A fault later in the run is the run's, and is
    said as it was."""
    sc = _default().with_values(**{"body.C": 1e-8})
    with pytest.raises(physics.IntegrationFault) as refused:  # a NumericalFault, which is one
        physics.simulate(sc)
    run = LiveRun(sc)
    run.advance(0.1, samples=4)
    assert run.status == FAULT
    assert run.message == str(refused.value)
    assert "the most extreme value is body.C = 1e-08" in run.message
