"""The averaged model's slow (w_perp, w3) reduction for axisymmetric bodies (physics/compiled/averaged.py
``rhs_axisymmetric``), which the averaged-against-full speed target of issue 5 runs."""

import numpy as np
import pytest

import physics
from physics.compiled import dispatch
from physics.reference.problems import moving_mass
from physics.systems.moving_mass.averaged_slow import averaged_slow_theta

RATE_TOL = 1e-12  # relative, rad/s^2: the reduction is the same arithmetic, up to rounding
THETA_TOL = 1e-8  # rad: both integrated at rtol 1e-12 over ~1000 free-body revolutions


def _params(rng):
    """An averaged-model parameter vector with every torque on: mass (F, D), medium, control,
    quadratic friction, cavity; J*1 = J*2."""
    A, C = 1.0 + rng.random(), 0.3 + rng.random()
    F, D, lam, b, Bq0, kc = 0.01 * rng.random(6) + 1e-3
    return np.array([A, A, C, A, F, D, 0.0, 0.0, lam, b, Bq0, kc])


@pytest.mark.parametrize("seed", range(5))
def test_reduced_rates_are_the_radial_part_of_the_averaged_rates(seed):
    rng = np.random.default_rng(seed)
    p = _params(rng)
    wp, w3, phase = 0.5 + rng.random(), rng.standard_normal(), 2 * np.pi * rng.random()
    y7 = np.array([wp * np.cos(phase), wp * np.sin(phase), w3, 1.0, 0.0, 0.0, 0.0])
    full = np.empty(7)
    dispatch.rhs(dispatch.MASS_AVERAGED, 0.0, y7, p, full)
    slow = np.empty(2)
    dispatch.rhs(dispatch.MASS_AVERAGED_AXISYMMETRIC, 0.0, np.array([wp, w3]), p, slow)
    radial = (y7[0] * full[0] + y7[1] * full[1]) / wp
    scale = np.max(np.abs(full[:3]))
    assert abs(slow[0] - radial) <= RATE_TOL * scale
    assert abs(slow[1] - full[2]) <= RATE_TOL * scale
    G = np.array([p[0] * wp, p[2] * w3])
    assert dispatch.braking_norm(dispatch.MASS_AVERAGED_AXISYMMETRIC, np.array([wp, w3]), p) == pytest.approx(
        np.linalg.norm(G), rel=1e-15)


@pytest.mark.filterwarnings("ignore::physics.ValidityWarning")  # eps = 0.19: moves theta in 4000 s
def test_reduced_theta_follows_the_whole_averaged_model():
    sc = moving_mass(0.1, t_end=4000.0, samples=101, rtol=1e-12).with_values(**{"run.fidelity": "averaged"})
    whole = physics.simulate(sc)
    theta, nfev, steps, wall = averaged_slow_theta(sc, 1e-12)
    assert abs(whole.theta[-1] - whole.theta[0]) > 0.05  # the nutation angle has moved
    assert np.max(np.abs(theta - whole.theta)) <= THETA_TOL
    assert nfev < whole.info["nfev"] / 20  # the slow form steps over the free-body revolutions


def test_reduction_refuses_a_triaxial_body():
    sc = moving_mass(0.05, t_end=10.0).with_values(**{"body.B": 1.2, "run.fidelity": "averaged"})
    with pytest.raises(ValueError, match="axisymmetric"):
        averaged_slow_theta(sc, 1e-9)
