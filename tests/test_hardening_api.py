"""Issue 24, point 3: the public API raises only its documented error types (ScenarioError for bad input,
IntegrationFault for a run that cannot go on) for any argument, bounds every point count it is given, and
names the key whose value causes a refusal."""

from __future__ import annotations

import os
import subprocess
import sys
import tracemalloc
from pathlib import Path

import pytest

import physics
import physics.studies.sweep
from physics import ScenarioError
from physics.core.errors import NumericalFault


class Unshowable:
    """A caller's object whose every text conversion raises: the error about it must still be made."""

    def __repr__(self):
        raise KeyError("repr")

    def __str__(self):
        raise KeyError("str")

    def __format__(self, spec):
        raise KeyError("format")

    def __float__(self):
        raise KeyError("float")


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
