"""Issue 24, point 3: the public API raises only its documented error types (ScenarioError for bad input,
IntegrationFault for a run that cannot go on) for any argument, bounds every point count it is given, and
names the key whose value causes a refusal."""

from __future__ import annotations

import os
import subprocess
import sys
import tracemalloc
import warnings
from pathlib import Path

import pytest

import physics
import physics.studies.sweep
from bench import api_escapes
from bench.api_escapes import Unshowable  # an object whose every text conversion raises
from physics import ScenarioError
from physics.core.errors import NumericalFault


def test_an_error_about_a_value_whose_repr_raises_is_still_one_line_naming_the_key():
    err = ScenarioError("mass.chi", Unshowable(), "must be a number")
    assert str(err) == "mass.chi = (a Unshowable that cannot be shown): must be a number"
    err = ScenarioError(Unshowable(), 1.0, Unshowable())  # key and allowed text too
    assert "\n" not in str(err) and "Unshowable" in str(err)
    fault = NumericalFault("the run failed", Unshowable(), Unshowable())
    assert "cannot be shown" in str(fault)


# ---- a. bounded point counts -----------------------------------------------------------------------------
MAX_POINTS = physics.studies.sweep.MAX_POINTS
ROOT = Path(__file__).resolve().parents[1]
RESONANT = ROOT / "assets" / "scenarios" / "pendulum_resonant.toml"
NOT_MADE_BYTES = 1_000_000  # far under the 0.8 MB a grid of MAX_POINTS floats takes: no grid was made


@pytest.mark.parametrize("spec", ["0.01:0.5:1000000000", "0.01:0.5:1e9", "log:0.01:0.5:" + "9" * 30,
                                  (0.01, 0.5, 10 ** 30), "1," * MAX_POINTS + "1"])
def test_an_axis_over_the_largest_grid_is_refused_naming_the_key_before_any_value_is_made(spec):
    tracemalloc.start()
    try:
        with pytest.raises(ScenarioError) as err:
            physics.axis_values(spec, "vary m")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert str(err.value).startswith("vary m = ") and f"more than {MAX_POINTS} values" in str(err.value)
    assert "\n" not in str(err.value)
    assert peak < NOT_MADE_BYTES + len(repr(spec))


def test_the_largest_axis_is_taken_and_a_count_written_with_an_exponent_is_a_count():
    assert len(physics.axis_values(f"0:1:{MAX_POINTS}")[0]) == MAX_POINTS
    assert physics.axis_values("0:1:1e1")[0] == physics.axis_values("0:1:10")[0]


def test_a_grid_of_axes_each_allowed_but_together_over_the_bound_is_refused_before_a_run():
    sc = physics.Scenario.load(RESONANT)
    with pytest.raises(ScenarioError, match=rf"^vary = \(1000 pendulum.k x 1000 pendulum.c_d = 1000000 points\): "
                                            rf"a sweep takes at most {MAX_POINTS} points"):
        physics.sweep(sc, {"k": "10:100:1000", "c_d": "1:20:1000"}, executor="serial")


def test_the_sweep_cli_refuses_a_billion_points_in_one_line(tmp_path):
    out = tmp_path / "s.csv"
    res = subprocess.run([sys.executable, "-m", "bench", "sweep", str(RESONANT), "--vary", "k=10:100:1000000000",
                          "--out", str(out), "--no-chart"], capture_output=True, text=True, cwd=ROOT, timeout=120,
                         env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert res.returncode == 2, res.stderr
    assert res.stderr.count("\n") == 1 and "Traceback" not in res.stderr
    assert res.stderr.startswith("error: vary k = '10:100:1000000000': asks for more than")
    assert not out.exists()


# ---- b. only the documented error types, for any argument -------------------------------------------------
DOCUMENTED = (ScenarioError, physics.IntegrationFault)
HOSTILE = (Unshowable(), {"a": 1}, "x", None, [1, 2], 3, float("nan"), object())


def _small():
    return physics.Scenario.load(ROOT / "assets" / "scenarios" / "oblate_settling.toml").with_values(
        **{"run.t_end": 0.1})


CALLS = {  # the study's entry points (python -m bench api-escapes), and the arguments only a test passes
    **api_escapes.calls(physics),
    "sweep stop": lambda sc, v: physics.sweep(sc, {"mass.chi": "1:2:2"}, executor="serial", stop=v),
    "sweep out": lambda sc, v: physics.sweep(sc, {"mass.chi": "1:2:2"}, executor="serial", out=v),
    "end_state K": lambda sc, v: physics.end_state(sc, K=v),
    "end_state E": lambda sc, v: physics.end_state(sc, E=v),
    "edit_dict data": lambda sc, v: physics.edit_dict(v, "mass.m", 1.0),
}


@pytest.mark.parametrize("call", CALLS)
def test_a_hostile_argument_gets_a_documented_error_type_in_one_line(call, tmp_path, monkeypatch):
    # "x" is a valid file name: a sweep given out="x" writes it, so the test runs where that cannot land in the tree.
    monkeypatch.chdir(tmp_path)
    sc = _small()
    for value in HOSTILE:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                CALLS[call](sc, value)
        except DOCUMENTED as exc:
            assert "\n" not in str(exc)
        except Exception as exc:  # noqa: BLE001 - what the test is for
            pytest.fail(f"{call}({type(value).__name__}) raised {type(exc).__name__}: {exc}")


def test_derived_of_a_dict_names_the_argument():
    with pytest.raises(ScenarioError, match=r"^scenario = 'dict': must be a physics.Scenario$"):
        physics.derived({"body": {"A": 1.0}})


def test_a_progress_that_is_no_function_is_refused_before_the_run():
    with pytest.raises(ScenarioError, match=r"^progress = 'x': must be a function \(or None\)$"):
        physics.simulate(_small(), progress="x")


# ---- c. a wrong method name is input, not a numerical fault -----------------------------------------------
def test_a_wrong_method_argument_is_refused_naming_it_and_the_methods():
    with pytest.raises(ScenarioError) as err:
        physics.simulate(_small(), method="bogus")
    assert not isinstance(err.value, physics.IntegrationFault) and "rtol" not in str(err.value)
    assert str(err.value).startswith("method = 'bogus': must be one of \"auto\", \"DOP853\"")


def test_a_wrong_method_in_run_is_refused_naming_run_method():
    with pytest.raises(ScenarioError, match=r"^run.method = 'bogus': must be one of \"auto\", \"DOP853\""):
        _small().with_values(**{"run.method": "bogus"})


# ---- d. a fault at t = 0 names the key that causes it ----------------------------------------------------
@pytest.mark.parametrize(("name", "key", "value"), [("plane_pendulums_three", "run.t_end", 1e-300),
                                                     ("quadratic_friction", "mass.chi", 1e30),
                                                     ("quadratic_friction", "mass.chi", 1e12),
                                                     ("prolate_flat_spin", "medium.lambda", 1e30),
                                                     ("pendulum_asymmetric", "pendulum.k", 1e30)])  # at t = 8e-13
def test_a_fault_before_the_first_step_names_the_changed_key(name, key, value):
    sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / f"{name}.toml").with_values(**{key: value})
    with pytest.raises(physics.IntegrationFault) as err, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        physics.simulate(sc)
    assert err.value.t == 0.0 and err.value.key == key, str(err.value)
    assert f"the most extreme value is {key} = " in str(err.value)


def test_a_subnormal_value_is_named_as_the_most_extreme_not_raised_as_a_math_domain_error():
    """A fault on a scenario holding 5e-324 (the smallest double): the value's distance from its key's usual span
    divided it by the span's top, which underflowed to 0, and log10(0) raised ValueError from inside the handler
    that turns a failure into a fault naming a key (found by a fuzz of the asymmetric pendulum carriers)."""
    from physics.core.blame import most_extreme

    sc = physics.Scenario.from_dict({"body": {"A": 100.0, "B": 100.95667768880405, "C": 100.00001, "M": 100.0},
                                     "pendulum": {"m": 5e-324, "l": 0.1, "h": -10, "k": 1e-12, "c_d": 1e-300},
                                     "initial": {"G0": 1e-06, "theta0": 1.5707963}, "run": {"t_end": 1e-300}})
    assert most_extreme(sc) == ("pendulum.m", 5e-324)  # 323 decades from 1 (run.t_end: 297 under its 1e-3)
    with pytest.raises((ScenarioError, NumericalFault), match="5e-324"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        physics.derived(sc)


def test_a_bob_placed_beyond_any_carrier_is_blamed_on_its_own_key_not_on_body_a():
    sc = physics.Scenario.load(RESONANT)
    with pytest.raises(ScenarioError, match=r"^pendulum\.h = 9\.2e\+18: places a bob so far from O"):
        physics.simulate(sc.with_values(**{"pendulum.h": 9.2e18}))
    with pytest.raises(ScenarioError, match=r"^pendulum\.l = 1e\+30: places a bob so far from O"):
        physics.simulate(sc.with_values(**{"pendulum.l": 1e30}))


# ---- e. a refusal names the key that was changed, among those it blames (bench/refusals.py) -----------------------
@pytest.mark.parametrize(("name", "key", "value"), [("oblate_settling", "body.B", 1e-300),
                                                     ("plane_pendulums_three", "plane_pendulum.azimuth", 1e30),
                                                     ("plane_pendulums_three", "body.C", 1e-300),
                                                     ("pendulum_resonant", "body.C", 1e-30)])
def test_a_refusal_names_the_changed_key(name, key, value):
    from bench.refusals import names

    with pytest.raises((ScenarioError, physics.IntegrationFault)) as err, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        physics.simulate(physics.Scenario.load(ROOT / "assets" / "scenarios" / f"{name}.toml").with_values(
            **{key: value}, **{"run.t_end": 1.0}))
    assert names(str(err.value), key), str(err.value)
