"""Headless: an edit in the explorer keeps the angular momentum K (magnitude and inertial direction) and the
attitude, and the readouts report what it did to E (issue 13 point 1; physics side in tests/test_carry.py)."""

from __future__ import annotations

import numpy as np
import pytest

from app.engine.edit_report import LABEL
from app.state import FRAME_HZ, Engine

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")
DT = 1.0 / FRAME_HZ
K_TOL = 1e-12  # relative, as physics.carry solves it
DIRECTION_TOL = 1e-12  # rad between K's inertial directions before and after


def played(n: int = 30) -> Engine:
    e = Engine()
    for _ in range(n):
        e.tick(DT)
    e.request("pause")
    e.tick(DT)
    return e


def edit(e: Engine, key: str, value: float) -> None:
    e.request_value(key, value)
    e.tick(0.0)
    assert e.error == "", e.error


def angle(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), a @ b))


def test_mass_off_and_on_keeps_K_and_attitude_and_reports_E():
    """The issue's sequence on the default scene: m 0.2 -> 0 -> 0.2 with the state kept (it took |K| from
    3.50 to 0.40 and E from 4.36 to 0.059 before)."""
    e = played()
    t, K0, q0, E0 = e.run.t, e.momentum(), e.run.last.quat[0].copy(), float(e.run.last.E[0])
    assert t > 0 and e.scenario.mass.m == 0.2
    edit(e, "mass.m", 0.0)
    assert e.scenario.mass is None and e.run.t == t
    K1 = e.momentum()
    assert np.linalg.norm(K1) == pytest.approx(np.linalg.norm(K0), rel=K_TOL)
    assert angle(K1, K0) < DIRECTION_TOL
    np.testing.assert_array_equal(e.run.last.quat[0], q0)
    E1 = float(e.run.last.E[0])
    assert e.edit_dE == pytest.approx(E1 - E0, rel=1e-12)
    assert e.readouts()[LABEL].startswith(f"{E1 - E0:+.3g} J")
    edit(e, "mass.m", 0.2)
    assert e.scenario.mass.m == 0.2 and e.run.t == t
    K2 = e.momentum()
    assert np.linalg.norm(K2) == pytest.approx(np.linalg.norm(K0), rel=K_TOL)
    assert angle(K2, K0) < DIRECTION_TOL
    np.testing.assert_array_equal(e.run.last.quat[0], q0)
    assert float(e.readouts()["|K|"].split()[0]) == pytest.approx(np.linalg.norm(K0), rel=1e-5)  # 6 digits shown
    # the view keeps K up: the inertial frame the scene is drawn in has not turned
    np.testing.assert_allclose(e.frame().K_vec / np.linalg.norm(e.frame().K_vec), [0, 0, 1], atol=1e-9)


def test_the_edit_line_lasts_until_the_next_edit_or_reset():
    e = played()
    edit(e, "body.A", 1.2)
    assert LABEL in e.readouts()
    edit(e, "mass.chi", 2.0)  # damping: K and E at this state are what they were
    assert e.edit_dE == 0.0 and LABEL not in e.readouts()
    edit(e, "mass.rho", 1.2)
    assert LABEL in e.readouts()
    e.request("reset")
    e.tick(0.0)
    assert e.run.t == 0.0 and LABEL not in e.readouts()


def test_a_fidelity_change_keeps_the_state_unless_asked_or_closed():
    e = played()
    t, K0, q0 = e.run.t, e.momentum(), e.run.last.quat[0].copy()
    e.request("fidelity", "averaged")
    e.tick(0.0)
    assert e.run.fidelity == "averaged" and e.run.t == t
    assert np.linalg.norm(e.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    # rebuilt from K's fixed frame (a product of four rotations): the attitude to rounding, not bit for bit
    np.testing.assert_allclose(e.run.last.quat[0], q0, rtol=0, atol=4 * np.finfo(float).eps)
    e.request("fidelity", "full")
    e.tick(0.0)
    assert e.run.fidelity == "full" and e.run.t == t
    assert np.linalg.norm(e.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    e.request("fidelity", "closed")  # restarted at t from the present K and attitude
    e.tick(0.0)
    assert e.run.fidelity == "closed" and e.run.t == t
    assert np.linalg.norm(e.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    np.testing.assert_allclose(e.run.last.quat[0], q0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(e.frame().K_vec / np.linalg.norm(e.frame().K_vec), [0, 0, 1], atol=1e-9)  # K up
    e.request("step")
    e.tick(0.0)
    t, G = e.run.t, float(e.run.last.K[0])
    e.request("fidelity", "full")  # from the closed form's row: its G = |J* omega| and attitude carried
    e.tick(0.0)
    assert e.run.fidelity == "full" and e.run.t == t > 0
    assert np.linalg.norm(e.momentum()) == pytest.approx(G, rel=K_TOL)
    e.request("restart_on_change", True)
    e.request("fidelity", "averaged")
    e.tick(0.0)
    assert e.run.fidelity == "averaged" and e.run.t == 0.0 and e.edit_dE is None


def test_the_pendulum_averaged_solution_goes_on_at_t_with_K_kept():
    e = Engine()
    e.request("system", "spherical_pendulum")
    e.tick(DT)
    t, K0 = e.run.t, e.momentum()
    e.request("fidelity", "averaged")  # restarted at t from the present K and attitude, its bob at rest
    e.tick(0.0)
    assert e.run.fidelity == "averaged" and e.run.t == t > 0
    assert "last edit" not in e.readouts()
    assert np.linalg.norm(e.momentum() - K0) <= K_TOL * np.linalg.norm(K0)


def test_initial_condition_sliders_still_restart():
    e = played()
    edit(e, "initial.theta0", 0.3)
    assert e.run.t == 0.0 and LABEL not in e.readouts()
