"""Fidelity "auto" against a requested accuracy (issue 5, physics/systems/moving_mass/accuracy.py): the cheapest model
whose measured error bound meets run.accuracy, checked against the full model."""

import json

import numpy as np
import pytest

import physics
from physics.reference.problems import moving_mass
from physics.systems.choice import choose_fidelity

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


# ---- auto says why: physics.derived and `python -m physics info` ---------------------------------

def test_derived_names_the_averaged_choice_its_bound_and_the_request():
    from physics.systems.moving_mass.accuracy import averaged_error_bound

    sc = _with_accuracy(moving_mass(0.01, t_end=100.0))
    d = physics.derived(sc)
    assert d["auto_fidelity"] in ("averaged", "closed")
    assert d["auto_model"] == f"moving_mass/{d['auto_fidelity']}"
    assert d["auto_accuracy"] == TOL
    assert d["auto_error_bound"] == d["averaged_error_bound"] == averaged_error_bound(sc)
    assert 0 < d["auto_error_bound"] <= TOL
    assert f"{TOL:g}" in d["auto_reason"] and "bound" in d["auto_reason"]


def test_derived_names_the_full_choice_and_its_method():
    sc = _with_accuracy(moving_mass(0.5, t_end=100.0, rtol=1e-9))
    d = physics.derived(sc)
    assert d["auto_fidelity"] == "full" and d["auto_model"] == "moving_mass/full"
    assert d["auto_method"] == "DOP853 (compiled), rtol = 1e-09"
    assert d["auto_error_bound"] == 0.0 and d["averaged_error_bound"] > TOL
    rk8 = physics.derived(sc.with_values(**{"run.method": "RK8", "run.dt": 0.05}))
    assert rk8["auto_method"] == "RK8 (compiled), dt = 0.05 s"


def test_derived_without_a_requested_accuracy_says_so():
    d = physics.derived(moving_mass(0.05, t_end=100.0))
    assert d["auto_accuracy"] == "not set" and d["auto_error_bound"] > 0


def test_pendulum_scenarios_name_model_and_method():
    from physics.reference.problems import p4

    d = physics.derived(p4(1.0))
    assert d["auto_model"] == f"spherical_pendulum/{d['auto_fidelity']}"
    assert d["auto_method"].startswith("DOP853 (compiled)")


def test_info_prints_model_method_accuracy_and_bound(tmp_path):
    import subprocess
    import sys
    from pathlib import Path

    sc = _with_accuracy(moving_mass(0.05, t_end=100.0, rtol=1e-9), 1e-5)  # conditions hold, bound ~1e-3
    path = tmp_path / "auto.toml"
    path.write_text(sc.to_toml())
    # --json: the text output is for people (units, meanings, 6 digits) since issue 17; JSON keeps 17 digits
    res = subprocess.run([sys.executable, "-m", "physics", "info", "--json", str(path)], capture_output=True,
                         text=True, cwd=Path(__file__).resolve().parents[1], timeout=300)
    assert res.returncode == 0, res.stderr
    values = {k: v["value"] for k, v in json.loads(res.stdout).items()}
    assert values["auto_model"] == "moving_mass/full"
    assert values["auto_method"] == "DOP853 (compiled), rtol = 1e-09"
    assert float(values["auto_accuracy"]) == 1e-5
    assert float(values["averaged_error_bound"]) == physics.derived(sc)["averaged_error_bound"] > 1e-5
    assert float(values["auto_error_bound"]) == 0.0
    assert "> requested accuracy 1e-05 rad" in values["auto_reason"]
