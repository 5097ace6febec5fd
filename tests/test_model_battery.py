"""The same battery for every registered model (dm_control's domains_test habit)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import physics

SCENARIO = {
    "body": {"A": 1.0, "C": 1.3, "M": 1.0},
    "mass": {"m": 0.1, "rho": 1.2, "Omega": 15.0, "chi": 15.0},
    "cavity": {"beta": 1000.0, "nu": 50.0, "a0": 0.1},
    "medium": {"lambda": 0.001},
    "control": {"b": 0.001},
    "initial": {"G0": 1.0, "theta0": 0.5, "mass_state": "quasistatic"},
    "run": {"t_end": 30.0, "samples": 61},
}
MODELS = sorted(physics.REGISTRY)


def _run(name):
    model = physics.REGISTRY[name]
    sc = physics.Scenario.from_dict(SCENARIO)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", physics.ValidityWarning)
        return physics.simulate(sc, fidelity=model.fidelity), sc


@pytest.mark.parametrize("name", MODELS)
def test_model_is_deterministic_finite_and_well_shaped(name):
    a, _ = _run(name)
    b, _ = _run(name)
    n = len(a.t)
    assert n == 61
    for arr in (a.theta, a.K, a.E):
        assert arr.shape == (n,) and np.all(np.isfinite(arr))
    assert a.omega.shape == (n, 3) and a.quat.shape == (n, 4)
    assert np.allclose(np.linalg.norm(a.quat, axis=1), 1.0, atol=1e-12)
    assert np.array_equal(a.table(), b.table())
    assert a.info["model"] == name


@pytest.mark.parametrize("name", MODELS)
def test_models_start_from_the_same_rotation(name):
    tr, sc = _run(name)
    w0, _, theta0 = physics.initial_G(sc)
    assert np.allclose(tr.omega[0], w0, rtol=1e-12)
    assert np.allclose(tr.quat[0], [1, 0, 0, 0])


def test_fidelities_agree_to_the_model_accuracy():
    runs = {name: _run(name)[0] for name in MODELS}
    ref = runs["moving_mass/averaged"].theta
    for tr in runs.values():
        assert np.max(np.abs(tr.theta - ref)) < 5e-3  # eps ~ 0.08: O(eps^2) apart
