"""physics.stepping.simulate's own promises: output times, progress, methods, fidelity override."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import physics

ANGLE_TOL = 1e-8  # rad: two integrations at rtol 1e-11 of the same problem


def _scenario(**run):
    sc = physics.default_scenario()
    return sc.replace(run=physics.Run(**{"t_end": 20.0, "samples": 201, "rtol": 1e-11, "fidelity": "full", **run}))


def test_t_eval_starting_late_integrates_from_zero():
    whole = physics.simulate(_scenario())
    late = physics.simulate(_scenario(t_eval=(5.0, 10.0, 20.0)))
    assert np.array_equal(late.t, [5.0, 10.0, 20.0])
    idx = [np.argmin(abs(whole.t - t)) for t in late.t]
    assert np.max(np.abs(late.theta - whole.theta[idx])) < ANGLE_TOL


def test_progress_is_reported_in_order_up_to_one():
    seen = []
    tr = physics.simulate(_scenario(), progress=seen.append)
    assert len(seen) >= 10 and seen[-1] == pytest.approx(1.0)
    assert all(b > a for a, b in zip(seen, seen[1:], strict=False))
    plain = physics.simulate(_scenario())
    assert np.max(np.abs(tr.theta - plain.theta)) < ANGLE_TOL  # chunking does not change the answer


@pytest.mark.parametrize("method", ["DOP853", "LSODA"])
def test_scipy_methods_agree_with_the_compiled_path(method):
    sc = _scenario(t_end=5.0, samples=51)
    fast = physics.simulate(sc)
    slow = physics.simulate(sc, method=method)
    assert slow.info["method"] == f"scipy {method}" and slow.info["nfev"] > 0
    assert np.max(np.abs(fast.theta - slow.theta)) < 1e-7


def test_unavailable_fidelity_for_a_system_is_a_clear_error():
    sc = physics.Scenario.load(Path(__file__).parents[1] / "assets/scenarios/plane_pendulums_three.toml")
    with pytest.raises(physics.ScenarioError, match="run.fidelity = 'closed': is not available for plane_pendulums"):
        physics.simulate(sc, fidelity="closed")
