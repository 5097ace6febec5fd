"""The averaged model's axisymmetric form (physics/compiled/averaged.py ``rhs_axisymmetric``): the slow
(|w_perp|, w3) equations with the phases alpha and psi as quadratures, which ``physics.simulate``, auto, the sweeps
and the explorer run for an axisymmetric body at fidelity averaged (docs/models.md A.3)."""

from pathlib import Path

import numpy as np
import pytest

import physics
from physics.compiled import dispatch
from physics.reference.problems import P2_T, moving_mass
from physics.stepping.simulate import integrate
from physics.systems.moving_mass.models import AVERAGED, AXISYMMETRIC

SCENARIOS = Path(__file__).resolve().parents[1] / "assets" / "scenarios"
RATE_TOL = 1e-12  # relative, rad/s^2 (rad/s for the phases): the reduction is the same arithmetic, up to rounding
THETA_TOL = 1e-9  # rad: the reduced model against the whole averaged model (w integrated with the attitude)
REFERENCE_RTOL = 1e-12  # the whole averaged model's tolerance when it is the reference: its error well below THETA_TOL


def _params(rng):
    """An averaged-model parameter vector with every torque on: mass (F, D), medium, control,
    quadratic friction, cavity; J*1 = J*2."""
    A, C = 1.0 + rng.random(), 0.3 + rng.random()
    F, D, lam, b, Bq0, kc = 0.01 * rng.random(6) + 1e-3
    return np.array([A, A, C, A, F, D, 0.0, 0.0, lam, b, Bq0, kc])


@pytest.mark.parametrize("seed", range(5))
def test_reduced_rates_are_the_averaged_rates_at_the_phase_of_w_perp(seed):
    rng = np.random.default_rng(seed)
    p = _params(rng)
    wp, w3, phase = 0.5 + rng.random(), rng.standard_normal(), 2 * np.pi * rng.random()
    whole = np.array([wp * np.cos(phase), wp * np.sin(phase), w3, 0.0, 1.0, 0.0, 0.0, 0.0])
    rates = np.empty(8)
    dispatch.rhs(dispatch.MASS_AVERAGED, 0.0, whole, p, rates)
    slow = np.empty(8)
    dispatch.rhs(dispatch.MASS_AVERAGED_AXISYMMETRIC, 0.0, np.array([wp, w3, phase, 0.0, 1.0, 0.0, 0.0, 0.0]), p,
                 slow)
    radial = (whole[0] * rates[0] + whole[1] * rates[1]) / wp
    tangential = (whole[0] * rates[1] - whole[1] * rates[0]) / wp**2  # the phase's rate
    scale = np.max(np.abs(rates[:3]))
    assert abs(slow[0] - radial) <= RATE_TOL * scale
    assert abs(slow[1] - rates[2]) <= RATE_TOL * scale
    assert abs(slow[2] - tangential) <= RATE_TOL * max(abs(tangential), scale)
    assert abs(slow[3] - rates[3]) <= RATE_TOL * abs(rates[3])  # psi': the same precession, without its 0/0
    assert not np.any(slow[4:]) and not np.any(rates[4:])  # K's frame does not move
    G = np.array([p[0] * wp, p[2] * w3])
    reduced = np.array([wp, w3, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    assert dispatch.braking_norm(dispatch.MASS_AVERAGED_AXISYMMETRIC, reduced, p) == pytest.approx(
        np.linalg.norm(G), rel=1e-15)


def test_on_the_axis_the_phases_turn_the_body_at_the_spin():
    """G along e3: psi' - alpha' (the turn about K, phi = pi/2 - alpha) is w3, and nothing is 0/0."""
    p = _params(np.random.default_rng(7))
    out = np.empty(8)
    dispatch.rhs(dispatch.MASS_AVERAGED_AXISYMMETRIC, 0.0, np.array([0.0, 1.3, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]), p,
                 out)
    assert np.all(np.isfinite(out)) and out[0] == 0.0
    assert out[3] - out[2] == pytest.approx(1.3, rel=1e-7)


def _whole(sc):
    """The whole averaged model (w and the precession phase integrated, every free-body revolution followed)."""
    return integrate(AVERAGED, sc.with_values(**{"run.rtol": REFERENCE_RTOL}), sc.run.times())


@pytest.mark.filterwarnings("ignore::physics.ValidityWarning")
@pytest.mark.parametrize("case", ["P2", "oblate_settling"])
def test_the_product_runs_the_reduction_with_the_whole_models_theta(case):
    if case == "P2":  # prolate, eps = 0.1, over the P2 horizon
        sc = moving_mass(0.1, t_end=P2_T, samples=401, rtol=1e-10)
    else:
        sc = physics.Scenario.load(SCENARIOS / "oblate_settling.toml")
    sc = sc.with_values(**{"run.fidelity": "averaged"})
    reduced = physics.simulate(sc)
    whole = _whole(sc)
    assert reduced.info["model"] == "moving_mass/averaged" and reduced.info["fidelity"] == "averaged"
    assert reduced.info["reduction"].startswith("axisymmetric")
    assert whole.info["reduction"].startswith("none")
    assert abs(whole.theta[-1] - whole.theta[0]) > 0.05  # the nutation angle has moved
    assert np.max(np.abs(reduced.theta - whole.theta)) <= THETA_TOL
    assert reduced.info["steps"] < whole.info["steps"] / 10  # the slow form steps over the free-body revolutions
    # omega and the attitude too: the same body, whichever form ran (to the integrators' phase error)
    assert np.max(np.abs(reduced.omega - whole.omega)) <= 1e-6 * np.max(np.abs(whole.omega))


@pytest.mark.filterwarnings("ignore::physics.ValidityWarning")  # |A - B|/A = 0.2: outside, run anyway
def test_a_triaxial_body_runs_the_whole_model():
    sc = moving_mass(0.05, t_end=10.0).with_values(**{"body.B": 1.2, "run.fidelity": "averaged"})
    assert AVERAGED.for_scenario(sc) is AVERAGED
    assert AVERAGED.for_scenario(sc.with_values(**{"body.B": 1.0})) is AXISYMMETRIC
    assert physics.simulate(sc).info["reduction"].startswith("none")
