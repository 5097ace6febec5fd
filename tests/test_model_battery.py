"""The same battery for every registered model (dm_control's domains_test habit)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import physics

# one small scenario per system; every model runs its own system's
SCENARIOS = {
    "moving_mass": {
        "body": {"A": 1.0, "C": 1.3, "M": 1.0},
        "mass": {"m": 0.1, "rho": 1.2, "Omega": 15.0, "chi": 15.0},
        "cavity": {"beta": 1000.0, "nu": 50.0, "a0": 0.1},
        "medium": {"lambda": 0.001},
        "control": {"b": 0.001},
        "initial": {"G0": 1.0, "theta0": 0.5, "mass_state": "quasistatic"},
        "run": {"t_end": 30.0, "samples": 61},
    },
    # MODELS B.8 set R (frozen A = 100 + mu D^2), 10 deg
    "spherical_pendulum": {
        "body": {"A": 100.45450045, "C": 150.0, "M": 505.0},
        "pendulum": {"m": 5.0, "l": 1.0, "h": -0.7, "k": "resonant", "c_d": 8.0},
        "initial": {"G0": 304.6, "theta0": 0.1745},
        "run": {"t_end": 30.0, "samples": 61},
    },
    # two in-plane pendulums (MODELS B.7) on a triaxial carrier
    "plane_pendulums": {
        "body": {"A": 120.0, "B": 130.0, "C": 220.0, "M": 504.0},
        "plane_pendulum": [
            {"m": 2.0, "l": 1.0, "k": 0.0, "c_d": 2.0, "preset": "in_plane", "R": 1.0, "z_p": 0.5, "azimuth": 0.0},
            {"m": 2.0, "l": 1.0, "k": 5.0, "c_d": 2.0, "preset": "in_plane", "R": 1.0, "z_p": 0.5, "azimuth": 3.1},
        ],
        "initial": {"G0": 460.0, "theta0": 0.1745},
        "run": {"t_end": 30.0, "samples": 61},
    },
}
MODELS = sorted(physics.REGISTRY)


def battery_scenario(system: str) -> physics.Scenario:
    """The system's scenario above, or, for a system registered elsewhere (a toy in a test), its own example
    with the battery's run settings."""
    if system in SCENARIOS:
        return physics.Scenario.from_dict(SCENARIOS[system])
    data = physics.Scenario.from_toml(physics.get_system(system).example).to_dict()
    data["run"] = {"t_end": 30.0, "samples": 61}
    return physics.Scenario.from_dict(data)


def _run(name):
    model = physics.REGISTRY[name]
    sc = battery_scenario(model.system)
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


def test_every_system_has_a_battery_scenario():
    assert {physics.REGISTRY[name].system for name in MODELS} <= set(SCENARIOS)


# system -> (reference model, largest theta difference of its other fidelities, rad)
AGREEMENT = {
    "moving_mass": ("moving_mass/averaged", 5e-3),  # eps ~ 0.08: O(eps^2) apart
}


@pytest.mark.parametrize("system", sorted(AGREEMENT))
def test_fidelities_agree_to_the_model_accuracy(system):
    ref_name, tol = AGREEMENT[system]
    runs = {name: _run(name)[0] for name in MODELS if physics.REGISTRY[name].system == system}
    ref = runs[ref_name].theta
    for tr in runs.values():
        assert np.max(np.abs(tr.theta - ref)) < tol
