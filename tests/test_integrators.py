"""The compiled integrators of physics/compiled/: tableaus, convergence orders, agreement with scipy,
structure preservation, and their routes through physics.simulate (issue 5)."""


import numpy as np
import pytest

import physics
from physics.compiled import dispatch, dop853, fixed, midpoint
from physics.core.errors import ScenarioError
from physics.reference import problems as P

ORDER_SLACK = 0.3  # measured order within this of the nominal one (issue 5)
OMEGA_TOL = 1e-8  # rad/s, compiled DOP853 vs scipy DOP853 at rtol 1e-12
ROUNDING = 1e-13  # relative: "kept to rounding" over a long run
ENERGY_BOUND = 1e-3  # relative energy oscillation of the undamped midpoint run (bounded, no drift)
T_ORDER = P.P1_T  # s, P1 horizon for the order fits


def _p1_error(tableau, dt):
    t = np.linspace(0.0, T_ORDER, 5)
    Y, n, status, *_ = fixed.run(tableau, dispatch.MASS_FULL, P.p1_initial(), P.p1_params(), t, dt)
    assert status == dop853.OK and n == t.size
    return np.max(np.abs(Y[:, :3] - P.rigid_body_exact(t)))


def _fitted_order(errors, steps):
    return np.polyfit(np.log(steps), np.log(errors), 1)[0]


def test_tableaus_are_consistent():
    for tab in fixed.TABLEAUS.values():
        assert tab.b.sum() == pytest.approx(1.0, abs=1e-14)
        assert np.allclose(tab.a.sum(axis=1), tab.c, atol=1e-13)
    with pytest.raises(ValueError, match="weights sum"):
        fixed.ButcherTableau("bad", 1, np.zeros((2, 2)), np.array([0.5, 0.4]), np.zeros(2))


def test_rigid_body_exact_solution_matches_tight_integration():
    t = np.linspace(0.0, P.P1_T, 101)
    Y, *_ = dop853.integrate(dispatch.MASS_FULL, P.p1_initial(), P.p1_params(), t, 1e-13, 1e-16, 0.0, 0.0,
                             10**9, 0.0, 1.0)
    assert np.max(np.abs(Y[:, :3] - P.rigid_body_exact(t))) < 1e-11
    w = P.rigid_body_exact(np.array([0.0, P.rigid_body_period()]))
    assert np.allclose(w[0], w[1], atol=1e-12)


@pytest.mark.parametrize("name, steps", [("RK4", (0.2, 0.1, 0.05, 0.025)), ("RK8", (0.35, 0.3, 0.25, 0.2))])
def test_fixed_step_order(name, steps):
    """diffrax's test_ode_order: the slope of log error against log step is the nominal order."""
    tab = fixed.TABLEAUS[name]
    errors = [_p1_error(tab, dt) for dt in steps]
    assert min(errors) > 3e-13  # above rounding (~1e-15 per step), so the slope is the truncation error's
    assert abs(_fitted_order(errors, steps) - tab.order) < ORDER_SLACK


def test_midpoint_order_two():
    t = np.linspace(0.0, T_ORDER, 5)
    steps = (0.1, 0.05, 0.025, 0.0125)
    errors = []
    for dt in steps:
        Y, n, status, *_ = midpoint.integrate(P.p1_initial(), P.p1_params(), t, dt)
        errors.append(np.max(np.abs(Y[:, :3] - P.rigid_body_exact(t))))
    assert abs(_fitted_order(errors, steps) - 2) < ORDER_SLACK


def test_fast_path_agrees_with_scipy_at_tight_tolerance():
    sc = P.moving_mass(0.1, t_end=200.0, samples=41, rtol=1e-12)
    fast = physics.simulate(sc)
    ref = physics.simulate(sc, method="DOP853")
    assert fast.info["method"] == "DOP853 (compiled)" and ref.info["method"] == "scipy DOP853"
    assert np.max(np.abs(fast.omega - ref.omega)) < OMEGA_TOL
    assert np.max(np.abs(fast.theta - ref.theta)) < OMEGA_TOL
    for name in ("RK4", "RK8", "midpoint"):
        tr = physics.simulate(sc.with_values(**{"run.method": name, "run.dt": 0.005}))
        assert tr.info["nfev"] > 0 and tr.info["steps"] == 40000
        tol = {"RK4": 1e-7, "RK8": 1e-10, "midpoint": 1e-3}[name]
        assert np.max(np.abs(tr.theta - ref.theta)) < tol, name


def test_structure_preserving_keeps_K_and_bounds_E_undamped():
    """~1000 revolutions of the undamped moving mass (chi = 0, mass released at rest): |K| to
    rounding, E oscillating inside a bound with no drift; RK4 at the same step drifts."""
    sc = P.moving_mass(0.1, t_end=3000.0, samples=301, chi=0.0, mass_state="rest")
    runs = {m: physics.simulate(sc.with_values(**{"run.method": m, "run.dt": 0.02})) for m in ("midpoint", "RK4")}
    tr = runs["midpoint"]
    assert np.max(np.abs(tr.K / tr.K[0] - 1)) < ROUNDING * 100
    dE = tr.E / tr.E[0] - 1
    assert np.max(np.abs(dE)) < ENERGY_BOUND
    # no drift: the late half oscillates like the early half
    half = len(dE) // 2
    assert abs(np.mean(dE[half:]) - np.mean(dE[:half])) < 0.2 * ENERGY_BOUND
    # the integrated quaternion (the state, before observe_full normalises it for the trajectory) keeps
    # unit norm: the midpoint rule preserves quadratic invariants
    from physics.compiled import midpoint

    p = physics.get_model("moving_mass", "full").pack(sc)
    y0 = physics.get_model("moving_mass", "full").initial_state(sc, p)
    Y = midpoint.integrate(np.ascontiguousarray(y0, dtype=float), np.asarray(p, dtype=float), tr.t, 0.02)[0]
    assert np.max(np.abs(np.linalg.norm(Y[:, 9:13], axis=1) - 1.0)) < ROUNDING * 100
    rk4 = runs["RK4"]
    assert np.max(np.abs(rk4.K / rk4.K[0] - 1)) > 100 * np.max(np.abs(tr.K / tr.K[0] - 1))


def test_fixed_methods_need_dt_and_midpoint_rejects_what_it_cannot_keep():
    with pytest.raises(ScenarioError, match="run.dt"):
        P.moving_mass(0.1, t_end=10.0).with_values(**{"run.method": "RK4"})
    with pytest.raises(ScenarioError, match="run.dt"):
        P.moving_mass(0.1, t_end=10.0).with_values(**{"run.method": "RK4", "run.dt": -1.0})
    with pytest.raises(ScenarioError, match="run.dt"):
        physics.simulate(P.moving_mass(0.1, t_end=10.0), method="RK8")
    with pytest.raises(ScenarioError, match="midpoint"):
        physics.simulate(P.p4(t_end=1.0).with_values(**{"run.method": "midpoint", "run.dt": 0.1}))


@pytest.mark.filterwarnings("ignore::physics.ValidityWarning")
def test_fixed_step_braking_ends_at_T():
    _, T = P.p3_exact(0.0)
    tr = physics.simulate(P.p3().with_values(**{"run.method": "RK4", "run.dt": 0.02}))
    assert tr.info["stop_reason"] == dop853.STATUS_TEXT[dop853.BRAKED]
    assert tr.t[-1] == pytest.approx(T, rel=1e-9)


def test_pendulum_runs_on_fixed_step():
    sc = P.p4(t_end=5.0, samples=11)
    ref = physics.simulate(sc)
    tr = physics.simulate(sc.with_values(**{"run.method": "RK8", "run.dt": 0.01}))
    assert np.max(np.abs(tr.theta - ref.theta)) < 1e-9
    # one right-hand side evaluation per stage of the tableau, each of 500 steps (5 s at dt = 0.01)
    from physics.compiled import fixed

    assert tr.info["nfev"] == fixed.TABLEAUS["RK8"].b.size * 500


def test_an_unknown_kernel_id_gets_nan_or_a_fault_never_another_models_value():
    """dispatch names every id it knows; an unknown one (registration refuses it) must not fall through to the
    averaged model's |G| or any other model's numbers: the integrator then stops (NONFINITE or MODEL_FAULT)."""
    unknown = max(dispatch.KERNELS) + 1
    y, p, out = np.ones(7), np.ones(8), np.zeros(7)
    dispatch.rhs(unknown, 0.0, y, p, out)
    assert np.all(np.isnan(out))
    assert np.isnan(dispatch.braking_norm(unknown, y, p))
    assert dispatch.fault(unknown, y, p) == dispatch.UNKNOWN_KERNEL_FAULT > 0
    assert dispatch.switch_chart(unknown, y, p) == 0  # nothing re-expressed
    for known in (dispatch.MASS_AVERAGED, dispatch.MASS_AVERAGED_AXISYMMETRIC):
        assert dispatch.fault(known, y, p) == 0  # a known id is not a fault
