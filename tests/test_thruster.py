"""A thruster fixed in the body (control.law "+e1" ... "-e3", issue 25's braking challenge): the torque b along a
body axis, checked against Euler's equations solved by hand for an axisymmetric rigid body, and refused by name
by the models that brake along G only."""

from __future__ import annotations

import numpy as np
import pytest

import physics

A, C, W3, B_TORQUE = 2.0, 3.0, 1.0, 0.05


def spin(law: str, t_end: float = 10.0, fidelity: str = "auto") -> physics.Scenario:
    """A rigid axisymmetric body (no mass) spinning about e3 with the thruster ``law`` on."""
    return physics.Scenario.from_dict(dict(
        body=dict(A=A, B=A, C=C, M=10.0), control=dict(b=B_TORQUE, law=law),
        initial=dict(omega=[0.0, 0.0, W3]), run=dict(fidelity=fidelity, t_end=t_end, samples=41)))


@pytest.mark.parametrize("law, sign", [("-e3", -1.0), ("+e3", 1.0)])
def test_a_thruster_along_the_spin_axis_changes_k_at_the_rate_b(law, sign):
    """Along the spin axis: C w3' = +-b exactly, K stays on e3 in space."""
    tr = physics.simulate(spin(law))
    np.testing.assert_allclose(tr.K, C * W3 + sign * B_TORQUE * tr.t, rtol=1e-10)
    np.testing.assert_allclose(tr.omega[:, :2], 0.0, atol=1e-12)
    assert tr.info["fidelity"] == "full"


@pytest.mark.parametrize("law, axis, sign", [("+e1", 0, 1.0), ("-e1", 0, -1.0), ("+e2", 1, 1.0), ("-e2", 1, -1.0)])
def test_a_thruster_across_the_spin_axis_follows_euler_s_equations_solved_by_hand(law, axis, sign):
    """A = B, w(0) = (0, 0, w3), torque s b e_i: w3 stays, and with n = (C - A) w3 / A the transverse rate is a
    circle through 0: for e1, w1 = s (b / (A n)) sin nt, w2 = s (b / (A n)) (1 - cos nt); e2 is e1 turned by
    90 degrees about e3 (w1 = -s (b / (A n)) (1 - cos nt), w2 = s (b / (A n)) sin nt). The work done is
    E(t) - E(0) = b (b / (A n^2)) (1 - cos nt)."""
    tr = physics.simulate(spin(law))
    n = (C - A) * W3 / A
    r = B_TORQUE / (A * n)
    s, c = np.sin(n * tr.t), 1.0 - np.cos(n * tr.t)
    w1, w2 = (sign * r * s, sign * r * c) if axis == 0 else (-sign * r * c, sign * r * s)
    np.testing.assert_allclose(tr.omega[:, 0], w1, atol=1e-9)
    np.testing.assert_allclose(tr.omega[:, 1], w2, atol=1e-9)
    np.testing.assert_allclose(tr.omega[:, 2], W3, atol=1e-12)
    np.testing.assert_allclose(tr.E - tr.E[0], B_TORQUE * r / n * c, atol=1e-10)


@pytest.mark.parametrize("fidelity", ["averaged", "closed"])
def test_the_models_that_brake_along_g_refuse_a_thruster_by_name(fidelity):
    with pytest.raises(physics.ScenarioError) as err:
        physics.simulate(spin("+e1", fidelity=fidelity))
    assert "run.fidelity" in str(err.value) and "thruster" in str(err.value)


def test_auto_runs_a_thruster_on_the_full_model_and_says_why():
    sc = spin("-e2", t_end=1.0).with_values(**{"mass.m": 0.1, "mass.rho": 0.5, "mass.Omega": 40.0,
                                               "mass.chi": 5.0})
    fidelity, reason = physics.choose_fidelity(sc)
    assert fidelity == "full" and "control.law" in reason, reason


def test_an_unknown_law_is_refused_with_the_choices():
    with pytest.raises(physics.ScenarioError) as err:
        physics.Scenario.from_dict(dict(body=dict(A=A, B=A, C=C, M=10.0), control=dict(b=1.0, law="+e4"),
                                        initial=dict(omega=[0, 0, 1.0])))
    assert "control.law" in str(err.value) and "+e3" in str(err.value)


@pytest.mark.parametrize("law", ["+e1", "-e2", "+e3"])
def test_the_torque_s_direction_is_the_thruster_s_body_axis_in_space(law):
    """LiveRun.torque_direction (the explorer's arrow) against d K_inertial / dt of the full model: for a rigid
    body the only torque is the thruster's, so K's inertial rate is b times that direction."""
    run = physics.LiveRun(spin(law))
    run.advance(3.0)
    K0, dt = run.momentum(), 1e-3
    run.advance(dt / 2)
    d = run.torque_direction()  # at the midpoint: the difference below is second order
    run.advance(dt / 2)
    np.testing.assert_allclose((run.momentum() - K0) / dt, B_TORQUE * d, atol=1e-8)
    assert abs(np.linalg.norm(d) - 1.0) < 1e-12


def test_the_brake_s_direction_is_against_k():
    run = physics.LiveRun(spin("K"))
    run.advance(1.0)
    K = run.momentum()
    np.testing.assert_allclose(run.torque_direction(), -K / np.linalg.norm(K), rtol=1e-15)
