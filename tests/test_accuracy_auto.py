"""Fidelity "auto" against a requested accuracy (issue 5, physics/accuracy.py): the cheapest model
whose measured error bound meets run.accuracy, checked against the full model."""

import numpy as np
import pytest

import physics
from bench.problems import moving_mass
from physics.validity import choose_fidelity

TOL = 1e-3  # rad, the requested theta accuracy of these scenarios
HORIZON = 1500.0  # s: long enough for the nutation to move, short enough for the full model


def _with_accuracy(sc, tol=TOL):
    return sc.with_values(**{"run.accuracy": tol})


def test_auto_picks_averaged_family_at_small_eps():
    fid, why = choose_fidelity(_with_accuracy(moving_mass(0.01, t_end=100.0)))
    assert fid in ("averaged", "closed")  # closed is the averaged model integrated analytically
    assert "bound" in why


def test_auto_picks_full_at_large_eps():
    fid, why = choose_fidelity(_with_accuracy(moving_mass(0.5, t_end=100.0)))
    assert fid == "full"


def test_accuracy_must_be_positive():
    with pytest.raises(physics.ScenarioError, match="run.accuracy"):
        _with_accuracy(moving_mass(0.1, t_end=10.0), -1.0)


@pytest.mark.slow
@pytest.mark.parametrize("eps, C, theta0, tol", [
    (0.05, 0.5, 0.3, TOL), (0.03, 0.5, 1.0, TOL), (0.02, 1.4, 1.0, 2e-3), (0.1, 1.4, 1.0, TOL),
    (0.05, 0.5, 0.3, 1e-5), (0.2, 0.5, 0.6, TOL), (0.05, 0.5, 0.6, TOL),
])
def test_chosen_model_meets_the_requested_accuracy(eps, C, theta0, tol):
    sc = _with_accuracy(moving_mass(eps, C=C, theta0=theta0, t_end=HORIZON, samples=201, rtol=1e-10), tol)
    sc = sc.with_values(**{"run.fidelity": "auto"})
    chosen = physics.simulate(sc)
    assert chosen.info["fidelity"] in ("averaged", "closed", "full")
    full = physics.simulate(sc.with_values(**{"run.fidelity": "full"}))
    assert np.max(np.abs(chosen.theta - full.theta)) <= tol, chosen.info["reason"]
