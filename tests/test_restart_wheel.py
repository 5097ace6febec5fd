"""The wheel damper's closed form restarted from a running state (physics/systems/wheel/restart.py): a slider
moved while it runs, and fidelity switches, keep the inertial K and the attitude, and t goes on."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

import physics
from physics import LiveRun

K_TOL = 1e-12  # relative: K carried across an edit, rounding of a few-term sum and the carry's Newton solve
QUAT_TOL = 1e-15  # the attitude is copied
E_TOL = 1e-12  # relative: c enters neither K nor E, so a change of c leaves E as it was
DRIFT_TOL = 1e-10  # relative: the full model's own drift of K as it runs on (its rtol)
SETTLE = 3.0  # s run before the edit: the wheel is turning


def preset(**values) -> physics.Scenario:
    sc = physics.Scenario.from_dict(tomllib.loads(physics.get_system("wheel").example))
    return sc.with_values(**values) if values else sc


def test_a_change_of_c_while_closed_restarts_the_closed_form_at_t_with_K_kept():
    run = LiveRun(preset(), fidelity="closed")
    run.advance(SETTLE, samples=3)
    K0, row = run.momentum(), run.last
    assert abs(row.internal["Omega_w"][0]) > 1e-3  # the wheel turns: its rate is state to carry
    assert run.retune(run.scenario.with_values(**{"wheel.c": 0.6}), "closed"), run.edit_note
    assert run.fidelity == "closed" and run.t == pytest.approx(SETTLE, abs=1e-12) and run.origin is not None
    assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    np.testing.assert_allclose(run.last.quat[0], row.quat[0], rtol=0, atol=QUAT_TOL)
    for name in ("Omega_w", "phi_w", "W_diss"):  # the wheel and the counters go on from where they were
        assert run.last.internal[name][0] == pytest.approx(row.internal[name][0], rel=1e-12, abs=1e-15), name
    # c enters neither K nor E; what E does change by is the closed form's own mismatch between its row and the K
    # it shows (fixed in space, the linear theory's K is not exactly so): small, at theta0 = 0.4
    assert abs(run.energy_change) <= 1e-3 * float(row.E[0])
    rows = run.advance(2.0, samples=4)
    assert run.status == "running" and rows.t[0] > SETTLE and run.t == pytest.approx(SETTLE + 2.0)
    # K's direction stays fixed in space as the closed form goes on (its |K| is the linear state's)
    K1 = run.momentum()
    assert np.linalg.norm(np.cross(K1 / np.linalg.norm(K1), K0 / np.linalg.norm(K0))) <= K_TOL


def test_the_restarted_closed_form_follows_the_full_model_from_the_same_state():
    """After the same edit from the same state, the closed form (restarted) and the full model (carried) agree
    to the closed form's own error at this small nutation: the restart starts it from the state, not from t = 0
    (from t = 0 the run would be SETTLE s behind and theta off by far more)."""
    sc = preset(**{"initial.theta0": 0.03})
    closed, full = LiveRun(sc, fidelity="full"), LiveRun(sc, fidelity="full")
    closed.advance(SETTLE)
    full.advance(SETTLE)
    edited = sc.with_values(**{"wheel.c": 0.05})
    assert closed.retune(edited, "closed") and full.retune(edited, "full")
    a, b = closed.advance(5.0, samples=50), full.advance(5.0, samples=50)
    np.testing.assert_allclose(a.t, b.t, rtol=0, atol=1e-12)
    bound = physics.get_system("wheel").error_bounds(sc.with_values(**{"run.t_end": 10.0}), "closed")
    assert np.max(np.abs(a.theta - b.theta)) <= bound
    assert np.ptp(b.theta) > 10 * bound  # theta moves over the window: agreeing is not trivial


def test_full_closed_full_keeps_K():
    run = LiveRun(preset(), fidelity="full")
    run.advance(SETTLE)
    K0 = run.momentum()
    assert run.retune(run.scenario, "closed"), run.edit_note
    assert abs(run.energy_change) <= E_TOL * float(run.last.E[0])  # the closed form starts at the state itself
    assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    run.advance(1.0)
    q = run.last.quat[0].copy()
    K1 = run.momentum()  # the K the closed form shows
    assert run.retune(run.scenario, "full"), run.edit_note
    assert run.fidelity == "full" and run.t == pytest.approx(SETTLE + 1.0)
    assert np.linalg.norm(run.momentum() - K1) <= K_TOL * np.linalg.norm(K1)
    np.testing.assert_allclose(run.last.quat[0], q / np.linalg.norm(q), rtol=0, atol=QUAT_TOL)
    K2 = run.momentum()
    run.advance(2.0)
    assert np.linalg.norm(run.momentum() - K2) <= DRIFT_TOL * np.linalg.norm(K2)
