"""The same battery for every registered model (dm_control's domains_test habit)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import physics

RUN = {"t_end": 30.0, "samples": 61}  # the battery's run settings, the same for every system

# a moving-mass scene at eps ~ 0.08 for the agreement test: its fidelities are O(eps^2) apart
SMALL_EPS = {
    "body": {"A": 1.0, "C": 1.3, "M": 1.0},
    "mass": {"m": 0.1, "rho": 1.2, "Omega": 15.0, "chi": 15.0},
    "cavity": {"beta": 1000.0, "nu": 50.0, "a0": 0.1},
    "medium": {"lambda": 0.001},
    "control": {"b": 0.001},
    "initial": {"G0": 1.0, "theta0": 0.5, "mass_state": "quasistatic"},
    "run": RUN,
}
MODELS = sorted(physics.REGISTRY)


def battery_scenario(system: str) -> physics.Scenario:
    """The system's own example (``System.example``) with the battery's run settings: a system registered
    anywhere (a toy in a test too) is covered with no entry here."""
    data = physics.Scenario.from_toml(physics.get_system(system).example).to_dict()
    data["run"] = dict(RUN)
    return physics.Scenario.from_dict(data)


def _run(name, sc=None):
    model = physics.REGISTRY[name]
    sc = battery_scenario(model.system) if sc is None else sc
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


@pytest.mark.parametrize("system", sorted(physics.SYSTEMS))
def test_every_system_example_is_a_scenario_of_that_system(system):
    """The battery runs each system on its example: it must load as a scenario of that very system."""
    assert battery_scenario(system).system == system


# system -> (scenario, reference model, largest theta difference of its other fidelities, rad)
AGREEMENT = {
    "moving_mass": (SMALL_EPS, "moving_mass/averaged", 5e-3),  # eps ~ 0.08: O(eps^2) apart
}


@pytest.mark.parametrize("system", sorted(AGREEMENT))
def test_fidelities_agree_to_the_model_accuracy(system):
    data, ref_name, tol = AGREEMENT[system]
    sc = physics.Scenario.from_dict(data)
    runs = {name: _run(name, sc)[0] for name in MODELS if physics.REGISTRY[name].system == system}
    ref = runs[ref_name].theta
    for tr in runs.values():
        assert np.max(np.abs(tr.theta - ref)) < tol
