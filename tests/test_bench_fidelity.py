"""bench/fidelity.py (issue 15): the calibration study's scenario generator and its error measure.

No simulation: the generator is checked over a few hundred seeded draws, the error on hand-made trajectories."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import physics
from bench import fidelity as F

N_DRAWS = 240


@pytest.fixture(scope="module")
def cases():
    return F.draw(seed=3, n=N_DRAWS)


def test_the_generator_is_deterministic_for_a_seed():
    a, b, c = F.draw(seed=7, n=12), F.draw(seed=7, n=12), F.draw(seed=8, n=12)
    assert json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)
    assert json.dumps(a, sort_keys=True) != json.dumps(c, sort_keys=True)


def test_every_draw_is_a_valid_scenario_that_a_run_accepts(cases):
    for data, _desc in cases:
        sc = physics.Scenario.from_dict(data)
        check = physics.get_system(sc.system).check_run
        if check is not None:
            check(sc)  # raises ScenarioError on a carrier the run would refuse
        assert sc.run.t_end > 0 and np.isfinite(sc.run.t_end)


def _within(x, lo_hi):
    return lo_hi[0] - 1e-12 <= x <= lo_hi[1] + 1e-12


def test_moving_mass_draws_stay_in_the_stated_ranges_and_cover_the_domain(cases):
    mass = [(physics.Scenario.from_dict(d), desc) for d, desc in cases if desc["system"] == "moving_mass"]
    assert len(mass) >= N_DRAWS // 2
    for sc, desc in mass:
        ca = sc.body.C / sc.body.A
        assert _within(ca, F.C_OVER_A) and abs(1 - ca) >= F.MIN_ASPHERICITY
        assert sc.mass.m * sc.mass.rho**2 / sc.body.A == pytest.approx(desc["kappa"])
        assert _within(desc["kappa"], F.KAPPA) and _within(sc.initial.theta0, F.THETA0_MASS)
        eps = physics.derived(sc)["eps"]
        assert 0.5 * F.EPS[0] <= eps <= 2 * F.EPS[1]  # drawn from |w0| before the mass's O(eps^2) shift
        assert (sc.body.B != sc.body.A) == ("triaxial" in desc["kind"])
    kinds = {desc["kind"] for _sc, desc in mass}
    assert {"oblate", "prolate"} <= kinds and any("triaxial" in k for k in kinds)
    ca = [sc.body.C / sc.body.A for sc, _desc in mass]
    assert sum(_within(x, F.NEAR_SPHERE) for x in ca) >= len(ca) // 5
    assert max(d["kappa"] for _sc, d in mass) > 0.6 and max(sc.initial.theta0 for sc, _d in mass) > 1.1
    for flag in ("cavity", "medium", "braking"):
        assert any(sc_desc[1][flag] for sc_desc in mass) and not all(sc_desc[1][flag] for sc_desc in mass)
    assert {d["damping"] for _sc, d in mass} == {"weak", "strong"}
    assert all((sc.cavity is not None) == d["cavity"] and (sc.control is not None) == d["braking"]
               for sc, d in mass)


def test_quadratic_friction_draws_are_the_mass_alone_over_the_equivalent_damping_range():
    """The set ``--system quadratic_friction`` draws (issue 23): quadratic friction with nothing beside it, a
    symmetric body, chi_eq(theta0)/Omega over QUADRATIC_CHI, both shapes."""
    from physics.systems.moving_mass.accuracy import equivalent_chi

    cases = F.draw(seed=3, n=60, system="quadratic_friction")
    assert len(cases) == 60
    ratios = []
    for data, _desc in cases:
        sc = physics.Scenario.from_dict(data)
        assert sc.mass.lam_q > 0 and sc.mass.chi == 0 and sc.body.A == sc.body.B
        assert sc.cavity is None and sc.medium is None and sc.control is None
        assert sc.initial.mass_state == "quasistatic" and np.isfinite(sc.run.t_end) and sc.run.t_end > 0
        ratios.append(equivalent_chi(sc) / sc.mass.Omega)
        assert _within(ratios[-1], F.QUADRATIC_CHI)
    assert min(ratios) < 0.2 < 1.0 < max(ratios)  # below the viscous study's range and across it
    assert {d["kind"] for _data, d in cases} == {"quadratic oblate", "quadratic prolate"}


def test_pendulum_draws_are_resonant_and_detuned_with_weak_and_strong_damping(cases):
    pend = [(physics.Scenario.from_dict(d), desc) for d, desc in cases if desc["system"] == "spherical_pendulum"]
    assert len(pend) >= N_DRAWS // 4
    assert {d["kind"] for _sc, d in pend} == {"resonant", "detuned"}
    assert {d["damping"] for _sc, d in pend} == {"weak", "strong"}
    for sc, desc in pend:
        assert _within(sc.initial.theta0, F.THETA0_PENDULUM)
        assert (sc.pendulum.k == "resonant") == (desc["kind"] == "resonant")
        if desc["kind"] == "detuned":
            assert abs(desc["detuning"] - 1) >= 0.02


def test_the_error_is_the_max_difference_on_the_reference_times():
    t = np.linspace(0.0, 4.0, 5)
    ref = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    other = ref + np.array([0.0, -0.5, 0.25, 0.0, 0.1])
    err, end = F.max_theta_error(t, ref, t, other)
    assert err == pytest.approx(0.5) and end == 4.0


def test_the_error_interpolates_and_stops_where_the_shorter_run_stops():
    t_ref = np.linspace(0.0, 4.0, 9)
    ref = np.zeros_like(t_ref)
    t = np.array([0.0, 1.0, 2.0])  # a braked run that stopped at t = 2: its values after 2 are not compared
    theta = np.array([0.0, 2.0, 0.0])
    err, end = F.max_theta_error(t_ref, ref, t, theta)
    assert end == 2.0 and err == pytest.approx(2.0)
    err_half, _ = F.max_theta_error(t_ref[[0, 1, 4]], ref[[0, 1, 4]], t, theta)  # t = 0.5 lies halfway up
    assert err_half == pytest.approx(1.0)


def test_auto_s_choice_is_timed_with_its_estimates_computed_afresh(monkeypatch):
    """The study charges auto's choice with computing the error estimates, as a run of a new scenario pays for them:
    even after ``derived`` has computed (and cached) them, each accuracy's timed choice computes them again. Before,
    the choice read them from the cache, and the pendulum's prediction was never timed."""
    from physics.systems.pendulum import normal_form

    F._warm()
    sc = physics.Scenario.load(Path(__file__).resolve().parents[1] / "assets" / "scenarios" / "pendulum_detuned.toml")
    physics.derived(sc)
    calls = []
    predict = normal_form.predict
    monkeypatch.setattr(normal_form, "predict", lambda *a, **k: calls.append(1) or predict(*a, **k))
    physics.derived(sc)
    assert not calls  # derived again: the cached estimate
    picks = F.auto_picks(sc)
    assert len(calls) == len(F.ACCURACIES)
    assert all(picks[f"choose_s_{a:g}"] > 0 for a in F.ACCURACIES)
