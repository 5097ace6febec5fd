"""auto knows what each model costs (issue 23): where the model it would pick exceeds the step budget it runs one
that fits, and says so, naming the full model's estimated steps; a bare budget error only where no model fits."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import physics
from physics.core.budget import MAX_STEPS
from physics.systems.choice import choose, resolve
from physics.systems.cost import PROBE_STEPS, estimated_steps

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = ROOT / "assets" / "scenarios"
# the probe's pace against the whole run's steps on a run whose step size stays what it was at the start
# (measured 0.5-2.5 on the shipped scenarios that run in seconds): an order of magnitude is what the budget needs
STEPS_FACTOR = 4.0


def _load(name: str) -> physics.Scenario:
    return physics.Scenario.load(SCENARIOS / name)


def _strict_quadratic() -> physics.Scenario:
    """The shipped quadratic-friction scene asked for 1e-4 rad, below its cheaper models' estimate (4.9e-4 rad,
    from the mass's steady motion; 0.027 rad before it, when the default accuracy was enough for this)."""
    return _load("quadratic_friction.toml").with_values(**{"run.accuracy": 1e-4})


def test_quadratic_friction_at_the_default_accuracy_runs_its_averaged_model_by_its_estimate():
    """The averaged and closed models share one estimate; with quadratic friction the closed form costs more
    (accuracy.QUADRATIC_ORDER), so auto runs the averaged model."""
    sc = _load("quadratic_friction.toml")
    choice = choose(sc)
    assert choice.fidelity == "averaged" and estimated_steps(sc, "full") > MAX_STEPS  # the full model: over budget
    bound = physics.derived(sc)["averaged_error_bound"]
    assert bound == physics.derived(sc)["closed_error_bound"]
    assert bound <= 1e-3 and choice.reason.startswith(f"averaged error estimate {bound:.2g} rad <= accuracy")


def test_quadratic_friction_runs_a_model_that_fits_and_says_why():
    """The full model would need ~8e7 steps over 4e5 s; the cheaper models' estimate is above the accuracy asked
    for, so auto runs the most accurate one that fits, names the full model's steps and states the estimate it
    runs with."""
    sc = _strict_quadratic()
    choice = choose(sc)
    full = choice.steps["full"]
    assert full > MAX_STEPS
    assert choice.fidelity in ("averaged", "closed")
    assert estimated_steps(sc, choice.fidelity) <= MAX_STEPS
    assert f"the full model would need about {full:.2g} steps" in choice.reason
    bound = physics.derived(sc)[f"{choice.fidelity}_error_bound"]
    assert math.isfinite(bound) and f"with its error estimate {bound:.2g} rad" in choice.reason
    assert f"budget of {MAX_STEPS:.2g}" in choice.reason
    assert physics.derived(sc)["auto_reason"] == choice.reason  # the explorer's badge reads this


def test_beside_other_dissipation_quadratic_friction_runs_with_no_error_estimate_and_says_so():
    sc = _load("quadratic_friction.toml").with_values(**{"mass.chi": 1.0})
    choice = choose(sc)
    assert choice.steps["full"] > MAX_STEPS and choice.fidelity == "averaged"
    assert "no error estimate" in choice.reason and "lam_q with other dissipation" in choice.reason


def test_a_made_up_long_scene_runs_and_its_info_names_the_full_models_steps():
    """The flat spin 100 times longer: the full model over budget, the averaged model outside its estimate's
    domain (eps > 0.2); auto runs the averaged model, not a budget error, and the run's info says so."""
    base = _load("prolate_flat_spin.toml")
    sc = base.with_values(**{"run.t_end": 100 * base.run.t_end, "run.samples": 101})
    tr = physics.simulate(sc)
    info = tr.info
    assert info["fidelity"] == "averaged" and tr.t[-1] == pytest.approx(sc.run.t_end)
    assert info["full_estimated_steps"] > MAX_STEPS
    assert f"about {info['full_estimated_steps']:.2g} steps" in info["reason"]
    assert info["steps"] <= STEPS_FACTOR * info["estimated_steps"]
    assert math.isinf(info["error_bound"])  # the run states no error estimate, as the reason says


def test_within_budget_the_systems_own_pick_stands():
    sc = _load("explorer/1_braking_quasistatic.toml")
    choice = choose(sc)
    assert choice.fidelity == physics.choose_fidelity(sc)[0] == "full"
    assert set(choice.steps) == {"full"} and choice.steps["full"] <= MAX_STEPS
    assert "budget" not in choice.reason


def test_where_no_model_fits_the_pick_stands_and_the_reason_says_so():
    """Plane pendulums have only the full model: over budget, nothing else can run the scene."""
    base = _load("plane_pendulums_three.toml")
    sc = base.with_values(**{"run.t_end": 1e6 * base.run.t_end})
    choice = choose(sc)
    assert choice.fidelity == "full" and choice.steps["full"] > MAX_STEPS
    assert "no other model fits" in choice.reason


def test_a_requested_model_is_not_replaced():
    sc = _load("quadratic_friction.toml").with_values(**{"run.fidelity": "full"})
    res = resolve(sc)
    assert res.fidelity == "full" and res.reason == "requested" and res.steps is None


@pytest.mark.parametrize("name", ["explorer/1_braking_quasistatic.toml", "figures/seed004_fig2_oblate.toml",
                                  "pendulum_detuned.toml"])
def test_the_estimate_is_the_runs_steps_to_within_a_few_times(name):
    sc = _load(name)
    est = estimated_steps(sc, "full")
    steps = physics.simulate(sc, fidelity="full").info["steps"]
    assert steps > PROBE_STEPS  # the probe did not simply run the whole thing
    assert steps / STEPS_FACTOR <= est <= STEPS_FACTOR * steps


def test_a_closed_form_costs_no_steps_and_a_fixed_step_its_count():
    sc = _load("oblate_settling.toml")
    assert estimated_steps(sc, "closed") == 0.0
    fixed = sc.with_values(**{"run.method": "RK4", "run.dt": 0.01})
    assert estimated_steps(fixed, "full") == math.ceil(sc.run.t_end / 0.01)


def test_while_the_kernels_build_there_is_no_probe_and_nothing_is_kept(monkeypatch):
    """The interpreted probe would stall a slider for seconds: no estimate then, and auto's own pick stands."""
    from physics.systems import cost

    sc = _strict_quadratic().with_values(**{"run.samples": 1234})  # a scenario not yet cached
    monkeypatch.setattr(cost, "compiled_ready", lambda: False)
    assert estimated_steps(sc, "full") is None and estimated_steps(sc, "closed") == 0.0
    assert choose(sc).fidelity == "full"
    monkeypatch.setattr(cost, "compiled_ready", lambda: True)
    assert estimated_steps(sc, "full") > MAX_STEPS  # the None was not kept


def test_over_budget_auto_tries_the_cheaper_models_in_the_system_s_own_order(monkeypatch):
    """Where the pick would exceed the budget, the cheapest model within the accuracy runs, cheapest by the system's
    ``cheapest_first``: with quadratic friction the averaged model before the closed form (which evaluates its
    quadrature from t = 0 at every point), as auto's own rule orders them. The pick is forced to the full model
    (8e7 steps here) so that both cheaper models, whose shared estimate meets the default accuracy, are in play."""
    sc = _load("quadratic_friction.toml")
    system = physics.get_system(sc.system)
    assert system.cheapest_first(sc) == ("averaged", "closed")
    assert system.cheapest_first(_load("oblate_settling.toml")) == ("closed", "averaged")
    monkeypatch.setattr(system, "choose", lambda _: ("full", "forced for this test"))
    choice = choose(sc)
    assert choice.steps["full"] > MAX_STEPS and choice.steps["averaged"] <= MAX_STEPS
    assert choice.fidelity == "averaged", choice.reason
    assert "the cheapest model that fits" in choice.reason
