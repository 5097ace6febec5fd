"""The spherical pendulum's averaged solution restarted at t from the present K and attitude, its bob at rest
(physics/systems/pendulum/restart.py through LiveRun.retune and the explorer's fidelity control; issue 13 point 1)."""

from __future__ import annotations

import numpy as np
import pytest

import physics
from app.engine.edit_report import LABEL
from app.engine.presets import load_preset
from app.state import FRAME_HZ, Engine
from physics.core.rotation import qmul, rotate
from physics.stepping.live import LiveRun

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")

PRESET = "Spherical pendulum damper, resonant"
K_TOL = 1e-12  # relative: the carry solves K to rounding (Newton, K_RTOL = 1e-14)
SAME_TOL = 1e-10  # the restarted solution against a fresh solve from an omega found another way (rounding)
SETTLE = 5.0  # s of the full model first, so the bob swings and has dissipated work
AFTER = 4.0  # s of the averaged solution after the switch
ASYMMETRIC = {"body": {"A": 1.0, "B": 1.1, "C": 1.4, "M": 1.0},
              "pendulum": {"m": 0.05, "l": 0.3, "h": 0.5, "k": "resonant", "c_d": 0.01},
              "initial": {"G0": 2.0, "theta0": 0.3}, "run": {"fidelity": "full", "t_end": 60.0}}


def scenes() -> list[physics.Scenario]:
    return [load_preset(PRESET), physics.Scenario.from_dict(ASYMMETRIC)]


def fresh_averaged(sc: physics.Scenario, K: np.ndarray, q: np.ndarray, s: np.ndarray) -> physics.Trajectory:
    """The averaged solution started anew (``simulate``) from the bob at rest with inertial momentum K at
    attitude q: omega = J^-1 R(q)^T K (the frozen system's K), found without physics.carry's Newton solve."""
    data = sc.to_dict()
    J = np.array([sc.body.A, sc.body.B, sc.body.C])
    omega = rotate(q * np.array([1.0, -1.0, -1.0, -1.0]), K) / J
    data["initial"] = {"omega": [float(w) for w in omega]}
    data["pendulum"]["k"] = physics.resolved_stiffness(sc)[0]  # the spring in force, not re-tuned to this spin
    data["run"] = {"fidelity": "averaged", "t_end": float(s[-1]), "t_eval": [float(x) for x in s]}
    return physics.simulate(physics.Scenario.from_dict(data))


@pytest.mark.parametrize("sc", scenes(), ids=["resonant-preset", "asymmetric"])
def test_full_to_averaged_keeps_K_attitude_and_t_and_goes_on_as_a_fresh_solve(sc):
    run = LiveRun(sc)
    run.advance(SETTLE)
    assert run.status == "running", run.message
    K0, q0, t0, E0 = run.momentum(), run.last.quat[0].copy(), run.t, float(run.last.E[0])
    W0 = float(run.last.internal["W_diss"][0])
    assert abs(run.last.internal["alpha"][0]) > 1e-3 and W0 > 0  # the bob swings and has worked: a real carry
    assert run.retune(sc, "averaged"), run.edit_note
    assert run.fidelity == "averaged" and run.t == t0 and run.edit_note == "" and run.origin is not None
    assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    assert np.linalg.norm(run.edit.K_after - K0) <= K_TOL * np.linalg.norm(K0)  # the full model's K of the new row
    np.testing.assert_array_equal(run.last.quat[0], q0)
    assert float(run.last.K[0]) == pytest.approx(np.linalg.norm(K0), rel=K_TOL)
    for name in ("alpha", "beta", "alpha_dot", "beta_dot"):
        assert run.last.internal[name][0] == 0.0, name  # the averaged solution starts its bob at rest
    # the dissipated work goes on from where it was, bit for bit: the averaged solution's work at its own t = 0 is
    # exactly zero by construction (it was the difference of two roundings of one quadratic form: on another
    # machine 0.011830203245704694 came back as 0.0118302032457047)
    assert run.last.internal["W_diss"][0] == W0
    assert run.energy_change == pytest.approx(float(run.last.E[0]) - E0, rel=1e-12)
    assert run.energy_change != 0.0  # the swing's energy is not in the bob at rest

    tr = run.advance(AFTER, samples=8)
    assert run.status == "running" and tr.t[0] > t0 and run.t == pytest.approx(t0 + AFTER)
    ref = fresh_averaged(sc, K0, q0, tr.t - t0)
    np.testing.assert_allclose(tr.omega, ref.omega, rtol=0, atol=SAME_TOL * np.linalg.norm(ref.omega[0]))
    np.testing.assert_allclose(tr.theta, ref.theta, rtol=0, atol=SAME_TOL)
    for name in ("alpha", "beta", "alpha_dot", "beta_dot"):
        np.testing.assert_allclose(tr.internal[name], ref.internal[name], rtol=0, atol=SAME_TOL)
    np.testing.assert_allclose(tr.internal["W_diss"], ref.internal["W_diss"] + W0, rtol=0, atol=SAME_TOL)
    np.testing.assert_allclose(tr.quat, qmul(q0, ref.quat), rtol=0, atol=SAME_TOL)
    assert np.max(np.abs(tr.internal["alpha"])) > 1e-3  # the bob swings again: the comparison is not of zeros
    assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)  # the solution's K is fixed in space


def test_back_to_full_and_a_slider_while_averaged_keep_t_attitude_and_the_bob():
    sc = load_preset(PRESET)
    run = LiveRun(sc)
    run.advance(SETTLE)
    K0 = run.momentum()
    assert run.retune(sc, "averaged")
    run.advance(1.0)
    t1, q1 = run.t, run.last.quat[0].copy()
    # a slider while averaged: restarted again at t from the present K (its row read as the full model's state)
    softer = sc.with_values(**{"pendulum.c_d": 0.02})
    assert run.retune(softer, "averaged"), run.edit_note
    assert run.t == t1 and run.edit_note == "" and run.origin.t0 == t1
    np.testing.assert_array_equal(run.last.quat[0], q1)
    # the K the solution showed is kept, not the full model's K at its row (which differs by its ~1 % error)
    assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    run.advance(1.0)
    row = run.last
    assert run.retune(softer, "full"), run.edit_note
    assert run.fidelity == "full" and run.t == row.t[0]
    np.testing.assert_allclose(run.last.quat[0], row.quat[0], rtol=0, atol=1e-15)
    for name in ("alpha", "beta", "alpha_dot", "beta_dot", "W_diss"):
        assert run.last.internal[name][0] == row.internal[name][0], name
    assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)  # omega solved for the shown K


def test_an_averaged_start_shows_its_K_where_the_full_model_has_it():
    """From t = 0 with an omega off the x-z plane: K is J omega(0) (inertial = body at the identity), the full
    model's K at the first row; switching to full keeps it."""
    sc = load_preset(PRESET).with_values(**{"initial.omega": [0.3, 0.2, 1.4], "run.fidelity": "averaged"})
    run = LiveRun(sc)
    full = physics.get_model("spherical_pendulum", "full")
    p = full.pack(sc)
    K_full = full.invariants(full.initial_state(sc, p)[None, :], p)[0][0]
    assert K_full[1] != 0.0 and np.linalg.norm(run.momentum() - K_full) <= K_TOL * np.linalg.norm(K_full)
    run.advance(1.0)
    K0 = run.momentum()
    assert run.retune(sc, "full"), run.edit_note
    assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)


def test_an_averaged_solution_that_cannot_run_is_refused_before_the_switch():
    sc = physics.Scenario.from_dict(ASYMMETRIC | {"pendulum": ASYMMETRIC["pendulum"] | {"k": 0.0}})
    run = LiveRun(sc)
    run.advance(1.0)
    t, y = run.t, run.y.copy()
    with pytest.raises(physics.ScenarioError, match="pendulum.k"):
        run.retune(sc, "averaged")
    assert run.fidelity == "full" and run.t == t
    np.testing.assert_array_equal(run.y, y)


def test_the_explorer_switches_to_averaged_without_restarting():
    e = Engine()
    e.request("preset", PRESET)
    e.tick(1.0 / FRAME_HZ)
    e.request("play")
    for _ in range(40):
        e.tick(1.0 / FRAME_HZ)
    e.request("pause")
    e.tick(0.0)
    t, K0, q0 = e.run.t, e.momentum(), e.run.last.quat[0].copy()
    assert t > 0 and e.run.fidelity == "full"
    e.request("fidelity", "averaged")
    e.tick(0.0)
    assert e.error == "", e.error
    assert e.run.fidelity == "averaged" and e.run.t == t
    readouts = e.readouts()
    assert "last edit" not in readouts and not any("restarted" in v for v in readouts.values()), readouts
    assert LABEL in readouts  # the bob put at rest changes E, and the page says so
    assert np.linalg.norm(e.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    np.testing.assert_array_equal(e.run.last.quat[0], q0)
    e.request("play")
    for _ in range(10):
        e.tick(1.0 / FRAME_HZ)
    assert e.run.t > t and e.run.status == "running", e.run.message
