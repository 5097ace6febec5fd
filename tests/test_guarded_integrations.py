"""The small scipy integrations inside closed forms and error estimates end, whatever the input: a right side that
is not finite, or one that would be evaluated without end, stops them with a message (physics/core/guarded.py).
Each case is run in a child process with a time limit, so that a regression fails here instead of hanging the
suite; what is asserted is the message and the counts, not the time."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from physics.core.guarded import RightSideError, guarded

ROOT = Path(__file__).resolve().parent.parent
LIMIT_S = 120  # a child that has not answered by then is stuck (each takes about a second)


def test_a_right_side_that_turns_nan_ends_the_integration_at_once():
    calls = []

    def rhs(t, y):
        calls.append(t)
        return [math.nan if t > 0.5 else -y[0]]

    with pytest.raises(RightSideError, match="decay.*not finite"):
        solve_ivp(guarded(rhs, 10_000, "decay"), (0.0, 1.0), [1.0], method="DOP853", rtol=1e-10)
    assert len(calls) < 1000  # stopped at the first NaN, not after the cap


def test_the_cap_counts_right_sides():
    with pytest.raises(RightSideError, match="more than 50 evaluations"):
        solve_ivp(guarded(lambda t, y: -1e3 * y, 50, "stiff"), (0.0, 1e3), [1.0], method="DOP853")
    sol = solve_ivp(guarded(lambda t, y: -y, 10_000, "decay"), (0.0, 1.0), [1.0], method="DOP853", rtol=1e-10,
                    atol=1e-12)
    assert abs(sol.y[0, -1] - math.exp(-1.0)) < 1e-9  # a guarded right side integrates as the bare one


def _child(scene: str, edits: dict, fidelity: str) -> dict:
    code = f"""
import json, warnings, physics
warnings.simplefilter("ignore")
sc = physics.Scenario.load({str(ROOT / "assets" / "scenarios" / scene)!r}).with_values(**{edits!r})
try:
    physics.simulate(sc, fidelity={fidelity!r})
    print(json.dumps(dict(kind="ok")))
except Exception as e:
    print(json.dumps(dict(kind=type(e).__name__, message=str(e),
                          documented=isinstance(e, (physics.ScenarioError, physics.IntegrationFault)))))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=LIMIT_S)
    return json.loads(out.stdout.strip().splitlines()[-1])


# found by fuzzing the shipped scenes' keys across magnitudes: the first two looped for good inside solve_ivp (seed
# 004 eq. (13) with an overflowing right side), the third crawled (its rates 1e100 times the scene's)
@pytest.mark.parametrize("scene,edits,key,why", [
    ("quadratic_friction.toml", {"body.C": 1e-300, "run.t_end": 10.0}, "body.C", "not finite"),
    ("explorer/3_intermediate_axis_flip.toml", {"initial.G0": 1e300, "run.t_end": 1.0}, "initial.G0", "not finite"),
    ("explorer/1_braking_quasistatic.toml", {"body.C": 1e-100, "run.t_end": 10.0}, "body.C", "more than 100000"),
])
def test_an_overflowing_closed_form_is_refused_with_the_parameter_that_caused_it(scene, edits, key, why):
    r = _child(scene, edits, "closed")
    assert r["documented"] and key in r["message"] and why in r["message"], r


def test_a_horizon_of_1e300_seconds_is_refused_or_run_by_every_fidelity_of_the_default_scene():
    for fidelity in ("closed", "averaged", "full", "auto"):
        r = _child("oblate_settling.toml", {"run.t_end": 1e300}, fidelity)
        assert r["kind"] == "ok" or (r["documented"] and "run.t_end" in r["message"]), (fidelity, r)


def test_the_guard_is_used_by_the_integrations_it_protects():
    """Every solve_ivp in physics outside the run's own stepper (which has its budget) goes through ``guarded``."""
    seen = 0
    for path in (ROOT / "physics").rglob("*.py"):
        text = path.read_text()
        if path.name == "stepper.py":
            continue
        calls = [line for line in text.splitlines() if re.search(r"(?<![.\w])solve_ivp\(", line)]
        assert all("guarded(" in c for c in calls), (path, calls)
        seen += len(calls)
    assert seen >= 4  # closed004, the forced response's two, the polhode


def test_numpy_rhs_values_are_checked():
    g = guarded(lambda t, y: np.array([1.0, np.inf]), 10, "pair")
    with pytest.raises(RightSideError, match="pair"):
        g(0.0, np.zeros(2))
