"""A run that cannot reach its t_end within the step budget is refused before its first step (issue 24, point 3),
in one line naming run.t_end, its value and the t_end the budget allows: through ``physics.simulate`` with the
model requested or picked by auto, and through ``python -m physics run``. Before, a spherical pendulum asked for
t_end = 1e8 s integrated for seconds until its pace check refused it."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import physics
import physics.stepping.simulate as SIM
from physics.systems.cost import estimated_steps

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = ROOT / "assets" / "scenarios"


class Stepped(Exception):
    """Raised by a stand-in for the integrator: the run got as far as stepping."""


def _no_stepping(monkeypatch) -> None:
    def integrate(*args, **kwargs):
        raise Stepped

    monkeypatch.setattr(SIM, "integrate", integrate)


@pytest.mark.parametrize(("name", "fidelity", "t_end"), [("pendulum_resonant.toml", "full", 1e8),
                                                         ("plane_pendulums_three.toml", "auto", 1e9),
                                                         ("quadratic_friction.toml", "full", 1e9)])
def test_an_unreachable_t_end_is_refused_before_a_step_naming_the_t_end_allowed(monkeypatch, name, fidelity, t_end):
    _no_stepping(monkeypatch)
    sc = physics.Scenario.load(SCENARIOS / name).with_values(**{"run.t_end": t_end, "run.fidelity": fidelity})
    with pytest.raises(physics.ScenarioError) as err:
        physics.simulate(sc)
    text = str(err.value)
    assert "\n" not in text and text.startswith(f"run.t_end = {t_end!r}: the full model would need about ")
    assert f"more than the budget of {SIM.MAX_STEPS} steps per run: t_end at most about " in text
    allowed = float(text.rsplit("about ", 1)[1].removesuffix(" s"))
    assert 0 < allowed < t_end


def test_a_run_estimated_within_a_few_times_the_budget_still_starts(monkeypatch):
    """The estimate is the run's steps to within a few times: near the budget, the pace check decides."""
    sc = physics.Scenario.load(SCENARIOS / "pendulum_detuned.toml").with_values(**{"run.fidelity": "full"})
    est = estimated_steps(sc, "full")
    _no_stepping(monkeypatch)
    monkeypatch.setattr(SIM, "MAX_STEPS", int(est / (SIM.REFUSE_FACTOR / 2)))  # over budget, within the factor
    with pytest.raises(Stepped):
        physics.simulate(sc)
    monkeypatch.setattr(SIM, "MAX_STEPS", int(est / (2 * SIM.REFUSE_FACTOR)))  # far over it
    with pytest.raises(physics.ScenarioError, match=r"^run\.t_end = "):
        physics.simulate(sc)


def test_the_command_line_refuses_it_in_one_line(tmp_path):
    sc = physics.Scenario.load(SCENARIOS / "pendulum_resonant.toml").with_values(
        **{"run.t_end": 1e8, "run.fidelity": "full"})
    path = tmp_path / "long.toml"
    path.write_text(sc.to_toml())
    res = subprocess.run([sys.executable, "-m", "physics", "run", str(path)], capture_output=True, text=True,
                         cwd=ROOT, timeout=300, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert res.returncode == 2, res.stderr
    assert res.stderr.startswith("error: run.t_end = 100000000.0: the full model would need about ")
    assert res.stderr.count("\n") == 1 and "Traceback" not in res.stderr


def test_the_refusal_names_the_extreme_value_that_sets_the_pace(monkeypatch):
    _no_stepping(monkeypatch)
    sc = physics.Scenario.load(SCENARIOS / "plane_pendulums_three.toml").with_values(**{"plane_pendulum.k": 9.2e18})
    with pytest.raises(physics.ScenarioError, match=r"^run\.t_end = 30\.0: .*\(the most extreme value is "
                                                    r"plane_pendulum\[0\]\.k = 9\.2e\+18\): t_end at most about "):
        physics.simulate(sc)


@pytest.mark.parametrize(("name", "key", "value"), [("pendulum_detuned.toml", "pendulum.m", 1e-30),
                                                    ("pendulum_resonant.toml", "pendulum.k", 1e30),
                                                    ("pendulum_asymmetric.toml", "pendulum.k", 9.2e18),
                                                    ("pendulum_resonant.toml", "pendulum.m", 1e-30),
                                                    ("pendulum_detuned.toml", "pendulum.c_d", 1e30)])
def test_the_averaged_pendulum_s_refusal_names_the_pendulum_s_keys_when_they_set_the_pace(name, key, value):
    """The averaged model's attitude quadrature steps with the slow phase, which a spring far off resonance turns
    fast (the detuning omega_0 - Omega): the refusal names the spring's keys beside run.t_end (before, only
    run.t_end, though t_end was the shipped one; python -m bench refusals counted these 8 misses)."""
    sc = physics.Scenario.load(SCENARIOS / name).with_values(**{key: value, "run.fidelity": "averaged"})
    with pytest.raises(physics.ScenarioError) as err:
        physics.simulate(sc)
    text = str(err.value)
    assert text.startswith("run.t_end = ") and f"{key} = {value:g}" in text and "slow rates reach" in text, text


def test_an_averaged_pendulum_near_resonance_over_its_budget_blames_t_end_alone():
    sc = physics.Scenario.load(SCENARIOS / "pendulum_resonant.toml").with_values(**{"run.t_end": 1e9,
                                                                                   "run.fidelity": "averaged"})
    near = r"^run\.t_end = 1000000000\.0: .*averaged model[^;]*: shorten t_end$"  # no spring named
    with pytest.raises(physics.ScenarioError, match=near):
        physics.simulate(sc)
