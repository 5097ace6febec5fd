"""The spherical pendulum's averaged-model error estimate against the full model (issue 15;
physics/systems/pendulum/accuracy.py, validity.py), auto's choice from it, and the averaged model's long-horizon
NaN fixed (physics/systems/pendulum/averaged.py)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import physics
from physics.systems.choice import DEFAULT_ACCURACY, choose_fidelity
from physics.systems.pendulum import accuracy, validity
from physics.systems.pendulum import averaged as pa
from physics.systems.pendulum import linear as pl
from physics.systems.pendulum.geometry import pendulum_system

deg = math.pi / 180
USEFUL = 10.0  # the issue's usefulness goal: an estimate at most this many times the actual error

# issue 15's reproduction: auto picked averaged; the averaged e-folding time was 241 s against the full model's 167
REPRO = {"body": {"A": 100.00983818953664, "B": 100.00983818953664, "C": 174.02745353415781, "M": 696.1927397013416},
         "pendulum": {"m": 1.2340016570643757, "l": 0.3764052949489212, "h": -0.28719510047130004,
                      "k": 0.6365312201679668, "c_d": 0.02001365125790713},
         "initial": {"omega": [0.04288997377273595, 0.0, 1.1081875157419305]},
         "run": {"fidelity": "auto", "t_end": 445.76, "samples": 4001}}

# a calibration-study draw (bench fidelity, pendulum_case before issue 15) whose averaged theta turned NaN after
# t ~ 1140 s: strong damping (ct / lambda_1 = 10) made e^{tau t/2} underflow while cosh(q t) overflowed
NAN_CASE = {"body": {"A": 100.0, "C": 132.11456121980575, "M": 337.6727173322763},
            "pendulum": {"m": 0.6008399513979463, "l": 0.4864963499432823, "h": -0.22043882637225132,
                         "k": 0.6508537286533053, "c_d": 1.7181858081531496},
            "initial": {"G0": 225.79629288590507, "theta0": 0.10202122263253555},
            "run": {"t_end": 1866.4626866388292, "samples": 1001, "rtol": 1e-10}}


def set_r(eps: float, *, theta0: float = 1 * deg, t_end: float | None = None, c_d: float | None = None,
          k="resonant", samples: int = 2001) -> physics.Scenario:
    """Set R with the coupling D (through h) and the damping c_d scaled by eps (as tests/test_pendulum_averaged)."""
    M0, m, l, W = 500.0, 5.0, 1.0, 2.0
    h = -l + 0.3 * eps
    A = 100.0 + m * (M0 + m) * (h + l) ** 2 / M0
    return physics.Scenario.from_dict({
        "body": {"A": A, "C": 150.0, "M": M0 + m},
        "pendulum": {"m": m, "l": l, "h": h, "k": k, "c_d": 8.0 * eps if c_d is None else c_d},
        "initial": {"omega": [150.0 * W * math.tan(theta0) / A, 0.0, W]},
        "run": {"t_end": 60.0 / eps if t_end is None else t_end, "samples": samples, "rtol": 1e-11},
    })


def actual_error(sc: physics.Scenario) -> tuple[float, physics.Trajectory]:
    """(max |theta_averaged - theta_full| on the full model's samples, the full trajectory)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", physics.ValidityWarning)
        full = physics.simulate(sc, fidelity="full")
        avg = physics.simulate(sc, fidelity="averaged")
    assert np.array_equal(full.t, avg.t)
    return float(np.max(np.abs(avg.theta - full.theta))), full


def test_the_issue_reproduction_is_covered():
    sc = physics.Scenario.from_dict(REPRO)
    err, full = actual_error(sc)
    d = physics.derived(sc)
    assert err > 1e-3  # what the issue saw: the averaged model is off by much more than B.10's "5 %" promised
    assert d["averaged_error_bound"] >= err and d["averaged_error_bound"] <= USEFUL * err
    assert d["auto_fidelity"] == "full" or d["auto_error_bound"] >= err
    assert d["error_bound_method"] == validity.METHOD and "averaged error estimate" in d["auto_reason"]
    # the estimate (~9e-3 rad) is within 1e-2 rad (auto runs averaged, and its bound holds) but not within the
    # default 1e-3, where auto falls back to the full model and says why
    loose = physics.derived(sc.with_values(**{"run.accuracy": 1e-2}))
    assert loose["auto_fidelity"] == "averaged" and err <= loose["auto_error_bound"] <= 1e-2
    assert d["auto_fidelity"] == "full" and d["auto_error_bound"] == 0.0 and ">" in d["auto_reason"]
    assert d["averaged_error_bound"] > DEFAULT_ACCURACY


# (scenario, which part of the estimate dominates): each estimate against the full model
HANDFUL = {
    "resonant, 0.5 deg": (lambda: set_r(1 / 8, theta0=0.5 * deg), "rate_gap"),
    "detuned": (lambda: set_r(1 / 8, theta0=0.5 * deg, k=5.0 * 500 / 505 * 3.3**2), "linear_gap"),
    "strong coupling (g/|Omega| = 0.2)": (lambda: set_r(1.0), "linear_gap"),
    "strong damping (ct/lambda_1 = 4)": (lambda: set_r(1 / 8, c_d=20.0, t_end=200.0), "linear_gap"),
    "3 deg, the bob swings 0.06 rad": (lambda: set_r(1 / 8, theta0=3 * deg, t_end=300.0), "rate_gap"),
}


@pytest.mark.parametrize("name", HANDFUL)
def test_the_estimate_holds_and_is_useful(name):
    make, dominant = HANDFUL[name]
    sc = make()
    err, _ = actual_error(sc)
    q = accuracy.scenario_parts(sc)
    assert err <= accuracy.averaged_error_bound(sc) <= USEFUL * err
    assert max(q.linear_gap, q.detuning_gap, q.rate_gap) == getattr(q, dominant)


def test_the_linear_gap_is_the_error_where_the_full_model_is_linear():
    """0.2 deg, detuned: the nonlinear parts vanish and the full model follows linear theory, so the actual error
    is the averaged model's distance from linear theory (the estimate's exact part) to within 2 %."""
    sc = set_r(1 / 4, theta0=0.2 * deg, k=5.0 * 500 / 505 * 3.3**2, t_end=240.0)
    err, _ = actual_error(sc)
    q = accuracy.scenario_parts(sc)
    assert max(q.detuning_gap, q.rate_gap) < 0.01 * q.linear_gap
    assert q.linear_gap == pytest.approx(err, rel=0.02)


def test_the_conditions_use_the_pendulums_own_amplitude():
    """The issue: in weakly coupled cases the bob swings ~6 times theta0, so an amplitude condition on theta0
    misjudges the nonlinearity. The remaining condition is on the swing from linear theory, which matches the
    full model's and scales with theta0."""
    sc = physics.Scenario.from_dict(REPRO)
    _, full = actual_error(sc)
    swing_full = float(np.max(np.hypot(full.internal["alpha"], full.internal["beta"])))
    theta0 = physics.derived(sc)["theta0"]
    conds = {c.name: c for c in validity.averaged_conditions(sc)}
    swing = conds["pendulum swing (linear theory, rad)"]
    assert swing.value == accuracy.pendulum_amplitude(sc)
    assert swing.value == pytest.approx(swing_full, rel=0.05) and swing.value > 5 * theta0
    assert not any("theta0" in name for name in conds)
    half = sc.with_values(**{"initial.omega": [REPRO["initial"]["omega"][0] / 2, 0.0, REPRO["initial"]["omega"][2]]})
    assert accuracy.pendulum_amplitude(half) == pytest.approx(swing.value / 2, rel=1e-3)
    # a swing beyond the calibrated range fails the condition, and auto then says so
    wide = sc.with_values(**{"initial.omega": [REPRO["initial"]["omega"][0] * 10, 0.0, REPRO["initial"]["omega"][2]]})
    fid, why = choose_fidelity(wide)
    assert accuracy.pendulum_amplitude(wide) > validity.SWING_MAX
    assert fid == "full" and "pendulum swing" in why
    assert validity.error_bounds(wide, "averaged") is None and validity.error_bounds(sc, "full") is None


def test_the_strongly_damped_case_stays_finite_and_matches_the_full_model():
    sc = physics.Scenario.from_dict(NAN_CASE)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", physics.ValidityWarning)
        avg = physics.simulate(sc, fidelity="averaged")
    assert np.all(np.isfinite(avg.theta)) and np.all(np.isfinite(avg.quat)) and np.all(np.isfinite(avg.E))
    co = pa.AveragedCoefficients(pl.spherical_linear(pendulum_system(sc)))
    from scipy.linalg import expm

    t = np.array([10.0, 1142.3, 1866.0])  # past 1142 s the old propagator returned NaN
    exact = np.array([expm(co.matrix * s) for s in t])
    assert np.allclose(co.propagator(t), exact, rtol=1e-9, atol=1e-12 * np.max(np.abs(exact)))
    # and the estimate covers it over a shortened horizon (the full model needs ~1.7e5 steps for all of it)
    short = sc.with_values(**{"run.t_end": 400.0})
    err, _ = actual_error(short)
    assert err <= accuracy.averaged_error_bound(short) <= USEFUL * err


def test_the_studys_pendulum_draws_are_valid_for_both_models():
    """bench fidelity's pendulum_case: damping drawn relative to the nutation (an absolute c_d made the full
    model too stiff for DOP853), horizons within the step cap (and so within the averaged model's attitude
    budget), swings within the cap; resonant and detuned, weak and strong damping, some A != B."""
    from bench import fidelity as F

    rng = np.random.default_rng(2)
    cases = []
    while len(cases) < 30:
        try:
            cases.append(F.pendulum_case(rng))
        except physics.ScenarioError:  # draw() redraws these too (a triaxial carrier that is not oblate)
            continue
    kinds = {(d["kind"], d["damping"]) for _data, d in cases}
    assert kinds == {("resonant", "weak"), ("resonant", "strong"), ("detuned", "weak"), ("detuned", "strong")}
    assert any(d["B_over_A"] != 1.0 for _data, d in cases)
    for data, desc in cases:
        sc = physics.Scenario.from_dict(data)
        assert F.full_steps_estimate(sc, desc) <= F.PENDULUM_STEPS * (1 + 1e-9)
        assert accuracy.pendulum_amplitude(sc) <= F.PENDULUM_SWING_MAX
        assert F.THETA0_PENDULUM[0] <= sc.initial.theta0 <= F.THETA0_PENDULUM[1]
    shortest = sorted(cases, key=lambda c: c[0]["run"]["t_end"])[:3]
    for data, _desc in shortest:  # the whole study's 200 draws all ran in both models (docs/models.md)
        err, _ = actual_error(physics.Scenario.from_dict(data))
        assert math.isfinite(err)


# issue 23's fresh check (seed 2027, scenario 83): detuned (lambda_1 0.80 against Omega 0.91), weakly damped, 5755 s.
# The full model's nutation fell to 0.007 rad within 290 s, a resonant decay; the averaged model's slowly. The
# estimate read the detuning at sigma +- shift only (|sigma| > shift with the linear swing): 0.061 rad stated,
# 0.074 rad measured
JUMP_CASE = {"body": {"A": 100.0, "C": 165.9921506448927, "M": 511.40753601909194},
             "pendulum": {"m": 1.8424379594830234, "l": 0.44919792487155186, "h": -0.5280696116893582,
                          "k": 1.7670127667295272, "c_d": 0.019814217305083495},
             "initial": {"G0": 230.74016003206043, "theta0": 0.0819667035463139},
             "run": {"t_end": 5755.421057294443, "samples": 1001, "rtol": 1e-10}}


def test_a_swing_that_can_pull_the_bob_into_resonance_is_read_at_the_resonance():
    sc = physics.Scenario.from_dict(JUMP_CASE)
    q = accuracy.scenario_parts(sc)
    co = pa.AveragedCoefficients(pl.spherical_linear(pendulum_system(sc)))
    assert abs(co.sigma) > q.shift  # the linear swing's detuning does not reach the resonance ...
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = physics.simulate(sc, fidelity="full")
        averaged = physics.simulate(sc, fidelity="averaged")
    actual = float(np.max(np.abs(np.interp(full.t, averaged.t, averaged.theta) - full.theta)))
    assert full.theta[np.searchsorted(full.t, 300.0)] < 0.1 * full.theta[0]  # ... but the full model decays as if
    assert actual <= accuracy.averaged_error_bound(sc)  # at resonance, and the estimate now reads it there


def _mode_one_rate(pivot: str, swing: float) -> tuple[float, float]:
    """(the bob's mean turning rate in the body, omega_0) with the bob started in its co-rotating mode 1 at
    ``swing`` rad on a carrier 1e8 times heavier, which the bob cannot move: its own frequency, free of coupling."""
    from scipy.integrate import solve_ivp

    from physics.compiled import pendulum as kernel
    from physics.systems.pendulum.models import initial_state, pack

    sc = physics.Scenario.from_dict({"body": {"A": 1e8, "C": 1.5e8, "M": 1e8},
                                     "pendulum": {"m": 1.0, "l": 1.0, "h": 0.5, "k": 4.0, "pivot": pivot},
                                     "initial": {"G0": 1.5e8, "theta0": 0.0}, "run": {"t_end": 1.0}})
    p, lin = pack(sc), pl.spherical_linear(pendulum_system(sc))
    y0 = initial_state(sc, p).copy()
    lambda1 = lin.omega0 - lin.W
    y0[3], y0[6] = swing, lambda1 * swing  # alpha = a, beta' = lambda_1 a: the circular mode 1
    out = np.empty_like(y0)

    def f(t, y):
        kernel.rhs(t, y, p, out)
        return out.copy()

    t = np.linspace(0.0, 60 * 2 * math.pi / lambda1, 6001)
    y = solve_ivp(f, (0.0, t[-1]), y0, method="DOP853", rtol=1e-11, atol=1e-13, t_eval=t).y
    azimuth = np.unwrap(np.arctan2(-np.sin(y[3]) * np.cos(y[4]), np.sin(y[4])))  # of e = (sin b, -sin a cos b, .)
    return float(np.polyfit(t, azimuth, 1)[0]), lin.omega0


@pytest.mark.parametrize("pivot", ["cardan", "isotropic"])
def test_the_bob_s_frequency_rises_with_its_swing_as_the_reach_takes_it(pivot):
    """SWING_SHIFT, which decides whether a swing can carry the detuning to the resonance, is the bob's measured
    hardening: its mode-1 frequency rises by SWING_SHIFT omega_0 a^2 (0.375 on the Cardan angles' spring, 0.25 on
    the arm's direction), not the a^2/4 scale of AMPLITUDE_SHIFT for both."""
    small, omega0 = _mode_one_rate(pivot, 0.01)
    wide, _ = _mode_one_rate(pivot, 0.2)
    measured = (wide - small) / (omega0 * 0.2**2)
    assert measured == pytest.approx(accuracy.SWING_SHIFT[pivot], rel=0.02)


# seed 4099, scenario 26 (an asymmetric carrier, B/A = 1.054) with A and B both set to their mean: detuned
# (sigma = -0.074 rad/s against a resonance width of 0.087), weakly damped. The bob swings to 0.29 rad where linear
# theory says 0.19, and its hardening carries it towards the resonance; with a^2/4 for the Cardan pivot the reach
# (0.061 rad/s) fell short of |sigma|, the resonance was not read, and 9.66e-3 rad was stated against 9.88e-3
SHORT_REACH_CASE = {"body": {"A": 102.71195474940031, "B": 102.71195474940031, "C": 159.1770772919187,
                             "M": 510.62423328715977},
                    "pendulum": {"m": 0.5777389994788448, "l": 0.649678263923422, "h": -0.8477450841575038,
                                 "k": 1.1530248515414, "c_d": 0.007715768562258571},
                    "initial": {"G0": 231.06536988381492, "theta0": 0.025806308262236732},
                    "run": {"t_end": 2262.5111560752516, "samples": 1001, "rtol": 1e-10}}


def _actual(sc: physics.Scenario) -> float:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = physics.simulate(sc, fidelity="full")
        averaged = physics.simulate(sc, fidelity="averaged")
    return float(np.max(np.abs(np.interp(full.t, averaged.t, averaged.theta) - full.theta)))


def test_a_cardan_bob_s_hardening_is_read_in_full_when_it_may_reach_the_resonance():
    from physics.scenario.initial import initial_G

    sc = physics.Scenario.from_dict(SHORT_REACH_CASE)
    assert all(c.holds for c in validity.averaged_conditions(sc))
    w0, _, _ = initial_G(sc)
    p = pl.spherical_linear(pendulum_system(sc))
    short = accuracy.parts(p, float(w0[0]), float(w0[1]), sc.run.t_end, accuracy.AMPLITUDE_SHIFT)
    actual = _actual(sc)
    assert short.bound < actual <= accuracy.scenario_parts(sc).bound


def test_an_asymmetric_carrier_has_an_estimate_that_holds():
    """The same draw as it was, B/A = 1.054 (no estimate before issue 23's last change: A != B was a structural
    condition); its actual error, 1.37e-2 rad, was 1.21x the estimate computed with the short reach."""
    data = {**SHORT_REACH_CASE, "body": {"A": 100.0, "B": 105.42390949880063, "C": 159.1770772919187,
                                         "M": 510.62423328715977}}
    sc = physics.Scenario.from_dict(data)
    assert all(c.holds for c in validity.averaged_conditions(sc))
    actual = _actual(sc)
    assert actual > 1e-2
    assert actual <= validity.error_bounds(sc, "averaged")


def test_the_polhode_gap_is_third_order_in_theta_and_nil_on_a_symmetric_carrier():
    """The free triaxial body's nutation departs from its linearisation at third order in theta (the extremes of
    theta move by O(theta^3)): doubling theta0 multiplies the gap by 8. On a symmetric carrier theta is constant in
    both, and the gap is 0."""
    asymmetric = pl.SphericalLinear(A=100.0, C=150.0, W=1.0, mu=0.0, l=1.0, D=0.0, k=1.0, c_d=0.0, B=105.0)
    gaps = [accuracy.polhode_gap(asymmetric, math.tan(th) * 1.5, 0.0, 1e4) for th in (0.02, 0.04, 0.08)]
    assert gaps[1] / gaps[0] == pytest.approx(8.0, rel=0.02) and gaps[2] / gaps[1] == pytest.approx(8.0, rel=0.02)
    symmetric = pl.SphericalLinear(A=100.0, C=150.0, W=1.0, mu=0.0, l=1.0, D=0.0, k=1.0, c_d=0.0)
    assert accuracy.polhode_gap(symmetric, 0.1, 0.05, 1e4) == 0.0


@pytest.mark.parametrize("W, B", [(1e-7, 105.0), (0.0, 105.0), (1.0, 149.999)], ids=["near 90 deg", "at 90 deg",
                                                                                  "near the separatrix"])
def test_the_polhode_gap_claims_nothing_where_the_free_motion_outruns_its_linearisation(W, B):
    """A nutation near 90 deg (the spin W tiny against the transverse rate) or a spin near the separatrix (C close
    to B) has no linear rate to speak of: integrating the exact motion over POLHODE_TURNS of it would take steps
    without bound (27 s for theta0 = 1.5707 over 1e7 s, before the bound), so the gap is inf, and the estimate with
    it."""
    p = pl.SphericalLinear(A=100.0, C=150.0, W=W, mu=0.0, l=1.0, D=0.0, k=1.0, c_d=0.0, B=B)
    assert accuracy.polhode_gap(p, 1.0, 0.0, 1e9) == math.inf


# a fresh draw (seed 8111, scenario 10): an asymmetric carrier (B/A = 1.056) nutating wide (theta0 = 0.27 rad). The
# averaged model's error is nearly all the swing of theta it lacks (linear_gap 3.63e-2 rad; the nonlinear gaps 1 %
# of it), but the actual error is 1.11 times linear_gap: the swing's own nonlinearity
WIDE_ASYMMETRIC_CASE = {"body": {"A": 100.0, "C": 124.47144102765246, "M": 632.8211358484753,
                                 "B": 105.60802155120076},
                        "pendulum": {"m": 0.8453186982892089, "l": 0.7432485365442107, "h": -0.6973562143438815,
                                     "k": 3.0731247253246705, "c_d": 0.025390821014164844},
                        "initial": {"G0": 195.99246219973762, "theta0": 0.26655085431834624},
                        "run": {"t_end": 13823.484438717169, "samples": 1001, "rtol": 1e-10}}


def test_the_polhode_gap_is_what_the_wide_swing_adds_to_the_linear_gap():
    sc = physics.Scenario.from_dict(WIDE_ASYMMETRIC_CASE)
    q = accuracy.scenario_parts(sc)
    actual = _actual(sc)
    assert max(q.detuning_gap, q.rate_gap) < 0.02 * q.linear_gap < 0.02 * actual
    assert actual > 1.1 * q.linear_gap  # beyond the linear part's own safety factor
    assert actual - q.linear_gap == pytest.approx(q.polhode_gap, rel=0.1)
    assert actual <= q.bound
