"""Scenario files: every bad input gets an error naming the key, the value and what is allowed."""

from __future__ import annotations

import copy
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import physics
from physics import ScenarioError

ROOT = Path(__file__).resolve().parents[1]

GOOD = {
    "body": {"A": 1.0, "C": 1.4, "M": 1.0},
    "mass": {"m": 0.1, "rho": 1.5, "Omega": 10.0, "chi": 10.0},
    "cavity": {"beta": 1000.0, "nu": 20.0, "a0": 0.1},
    "medium": {"lambda": 0.001},
    "control": {"b": 0.001, "law": "K"},
    "initial": {"G0": 1.0, "theta0": 0.5, "mass_state": "quasistatic"},
    "run": {"fidelity": "auto", "t_end": 10.0},
}


def _with(path: str, value):
    data = copy.deepcopy(GOOD)
    table, key = path.split(".")
    data[table][key] = value
    return data


BAD = [
    ("body.A", math.nan, "finite"), ("body.A", math.inf, "finite"), ("body.C", -1.0, "> 0"),
    ("body.A", 0.0, "> 0"), ("body.M", 0.0, "> 0"), ("body.B", "1", "number"), ("body.A", True, "number"),
    ("body.C", 5.0, "must not exceed the sum"), ("mass.m", 0.0, "> 0"), ("mass.m", 1.0, "less than body.M"),
    ("mass.m", 2.0, "less than body.M"), ("mass.rho", -0.1, ">= 0"), ("mass.Omega", 0.0, "> 0"),
    ("mass.Omega", -3.0, "> 0"), ("mass.chi", -1.0, ">= 0"), ("mass.lam_q", -1.0, ">= 0"),
    ("control.b", -0.1, ">= 0"), ("control.law", "G", '"K", "Jw"'), ("medium.lambda", -1.0, ">= 0"),
    ("cavity.nu", 0.0, "> 0"), ("cavity.nu", -2.0, "> 0"), ("cavity.a0", math.nan, "finite"),
    ("run.t_end", 0.0, "> 0"), ("run.t_end", -5.0, "> 0"), ("run.fidelity", "fast", '"full"'),
    ("run.samples", 1, "whole number"), ("run.samples", 2.5, "whole number"), ("run.rtol", 1.0, "[1e-14, 1e-2]"),
    ("run.t_eval", [0.0, 2.0, 1.0], "increase"), ("initial.theta0", 4.0, "[0, pi]"), ("initial.G0", -1.0, "> 0"),
    ("initial.G0", 5e-324, "at least 2.23e-308"), ("initial.G0", 1e-310, "smallest normal double"),
    ("initial.mass_state", "moving", '"rest"'), ("body.Z", 1.0, "unknown key"), ("mass.Omgea", 1.0, "unknown key"),
    ("medium.lambda_", 1.0, "unknown key; allowed: lambda"),
]


@pytest.mark.parametrize("path,value,allowed", BAD, ids=[f"{p}={v!r}" for p, v, _ in BAD])
def test_bad_value_names_key_value_and_range(path, value, allowed):
    with pytest.raises(ScenarioError) as err:
        physics.Scenario.from_dict(_with(path, value))
    message = str(err.value)
    assert message.startswith(path)
    assert allowed in message
    assert repr(value)[:10] in message or str(value) in message


def test_the_least_rotation_still_gives_its_angle():
    """G0 and omega smaller than the smallest normal double keep a few bits in K's components: G0 = 5e-324 at
    theta0 = 0.8 started at pi/4. They are refused by name; the smallest normal G0 starts where theta0 says."""
    with pytest.raises(ScenarioError, match=r"^initial\.omega = \[5e-324, 0.0, 5e-324\]: must have a component"):
        physics.Scenario.from_dict({**_with("initial.G0", 1.0), "initial": {"omega": [5e-324, 0.0, 5e-324]}})
    sc = physics.Scenario.from_dict(_with("initial.G0", sys.float_info.min)).with_values(
        **{"run.fidelity": "full", "run.t_end": 1.0})
    assert physics.simulate(sc).theta[0] == pytest.approx(sc.initial.theta0, abs=1e-14)
    tilted = physics.Scenario.from_dict({**_with("initial.G0", 1.0), "initial": {"omega": [1e-300, 0.0, 1.0]}})
    assert tilted.initial.omega[0] == 1e-300  # a tiny component beside a normal one is only a tiny tilt


def test_rho_too_large_for_the_frozen_inertia():
    data = _with("mass.rho", 4.0)
    with pytest.raises(ScenarioError, match="mass.rho"):
        physics.simulate(physics.Scenario.from_dict(data), fidelity="full")


@pytest.mark.parametrize("text,key", [
    ("[body\nA = 1", "scenario"),
    ("[body]\nA = 1\nC = 1\nM = 1\n[initial]\nG0 = 1\ntheta0 = 0.1\n", "run"),
    ("[nonsense]\nx = 1", "nonsense"),
    ("[body]\nA = 1\nM = 1\n[initial]\nG0 = 1\ntheta0 = 0.1\n[run]\nt_end = 1", "body.C"),
    ("[body]\nA=1\nC=1\nM=1\n[initial]\nG0=1\n[run]\nt_end=1", "initial"),
    ("[body]\nA=1\nC=1\nM=1\n[initial]\nomega=[1,2]\n[run]\nt_end=1", "initial.omega"),
    ("[body]\nA=1\nC=1\nM=1\n[initial]\nomega=[1,0,0]\nG0=1\n[run]\nt_end=1", "initial"),
    ("body = 3", "body"),
])
def test_malformed_files(text, key):
    with pytest.raises(ScenarioError) as err:
        physics.Scenario.from_toml(text)
    assert str(err.value).startswith(key)


def test_round_trip_is_exact():
    sc = physics.Scenario.from_dict(_with("initial.theta0", 0.1 + 0.2))  # a float with no short decimal form
    again = physics.Scenario.from_toml(sc.to_toml())
    assert again == sc
    assert again.initial.theta0 == 0.1 + 0.2


def test_absent_tables_mean_absent_parts():
    data = {k: v for k, v in GOOD.items() if k not in ("cavity", "medium", "control")}
    sc = physics.Scenario.from_dict(data)
    assert sc.cavity is None and sc.medium is None and sc.control is None
    assert sc.body.B == sc.body.A


def test_averaged_outside_validity_warns_and_names_the_condition():
    sc = physics.Scenario.from_dict(_with("mass.Omega", 2.0))  # eps ~ 0.5
    with pytest.warns(physics.ValidityWarning, match="eps = "):
        tr = physics.simulate(sc, fidelity="averaged")
    assert len(tr.t) > 1


def test_auto_reports_choice_and_reason():
    tr = physics.simulate(physics.Scenario.from_dict(_with("mass.Omega", 2.0)))
    assert tr.info["fidelity"] == "full" and "eps" in tr.info["reason"]
    good = physics.Scenario.from_dict(GOOD).with_values(**{"run.accuracy": 1e-2})
    tr = physics.simulate(good)
    assert tr.info["fidelity"] == "closed" and "estimate" in tr.info["reason"] and "<= accuracy" in tr.info["reason"]
    assert 0 < tr.info["error_bound"] <= 1e-2  # the estimate it states meets the accuracy asked


def test_mass_state_belongs_to_the_moving_mass():
    """initial.mass_state is the moving mass's start: another system refuses "quasistatic" naming the owner,
    drops "rest" (files and share links written before carry it: what every other part does anyway) and never
    writes it; the moving mass validates it, and reads a missing one as "rest"."""
    data = {"body": {"A": 100.5, "C": 150.0, "M": 505.0}, "pendulum": {"m": 5.0, "l": 1.0, "h": -0.7, "k": 40.0},
            "initial": {"G0": 300.0, "theta0": 0.1, "mass_state": "quasistatic"}, "run": {"t_end": 1.0}}
    with pytest.raises(ScenarioError, match="initial.mass_state = 'quasistatic': belongs to the moving mass; this "
                                            "scenario runs the spherical pendulum"):
        physics.Scenario.from_dict(data)
    data["initial"]["mass_state"] = "rest"
    sc = physics.Scenario.from_dict(data)
    assert sc.system == "spherical_pendulum" and sc.initial.mass_state is None
    assert "mass_state" not in sc.to_toml()
    shipped = physics.Scenario.load(ROOT / "assets" / "scenarios" / "figures" / "seed002_resonance_detuned.toml")
    assert shipped.system == "spherical_pendulum" and shipped.initial.mass_state is None
    with pytest.raises(ScenarioError, match="initial.mass_state = 'moving': must be one of .rest., .quasistatic."):
        physics.Scenario.from_dict(_with("initial.mass_state", "moving"))
    bare = dict(GOOD, initial={"G0": 1.0, "theta0": 0.5})
    assert physics.Scenario.from_dict(bare).initial.mass_state is None
    assert [c.name for c in physics.averaged_conditions(physics.Scenario.from_dict(bare))] == [
        c.name for c in physics.averaged_conditions(physics.Scenario.from_dict(_with("initial.mass_state", "rest")))]


def test_a_file_path_is_named_whole_and_a_path_past_any_use_keeps_its_file_name(tmp_path):
    """A value is cut at 80 characters, but a file's path is what the user must find: it is shown whole, and one
    longer than MAX_PATH loses its middle, not its file name."""
    from physics.core.errors import MAX_PATH

    deep = tmp_path / ("x" * 120) / "missing scenario.toml"
    with pytest.raises(physics.ScenarioError) as info:
        physics.Scenario.load(deep)
    assert f"scenario = '{deep}': cannot be read" in str(info.value)
    huge = "/" + "y" * 3000 + "/the file.toml"
    with pytest.raises(physics.ScenarioError) as info:
        physics.Scenario.load(huge)
    shown = str(info.value).split(": cannot be read")[0]
    assert shown.endswith("/the file.toml'") and "..." in shown and len(shown) <= len("scenario = ") + MAX_PATH


@pytest.mark.parametrize("t_end", [5e-324, 1e-320, 1e-306])
def test_a_horizon_too_short_for_distinct_sample_times_is_refused_by_name(t_end):
    """Subnormal spacing repeats sample times: t_end = 5e-324 reached the run and came back as scipy's own words
    ("Values in `t_eval` are not properly sorted"). Refused on load instead, with the shortest t_end allowed."""
    base = physics.Scenario.load(ROOT / "assets" / "scenarios" / "oblate_settling.toml")
    with pytest.raises(physics.ScenarioError, match=r"run\.t_end = .*too short for 2001 distinct sample times"):
        base.with_values(**{"run.t_end": t_end})
    shortest = 2.2250738585072014e-308 * 2000
    assert base.with_values(**{"run.t_end": shortest * 1.0001}).run.times()[1] > 0  # just above: distinct times
    few = base.with_values(**{"run.samples": 2, "run.t_end": 1e-307})
    assert np.all(np.diff(few.run.times()) > 0)
