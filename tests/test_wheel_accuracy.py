"""The wheel damper's closed-form error estimate against the full model (physics/systems/wheel/accuracy.py), its
domain, and auto's choice from it. The scenarios are hand-made, none from the calibration draws: each kind the
estimate's parts answer for (the second-order response, the spin-up's drift, the separatrix), each held."""

from __future__ import annotations

import math
import tomllib
import warnings

import numpy as np
import pytest

import physics
from physics.systems.wheel import accuracy

# an estimate at most this many times the actual error: the 1/sin^2 theta_s scaling near a separatrix and a free
# wheel's drift are where it over-states the most (19x and 11x here; the study's median is ~4x)
OVER_MAX = 25.0


def scene(body, wheel, theta0, t_end, G0=3.0) -> physics.Scenario:
    return physics.Scenario.from_dict({"body": {"A": 1.0, "M": 1.0, **body}, "wheel": wheel,
                                       "initial": {"G0": G0, "theta0": theta0},
                                       "run": {"t_end": t_end, "samples": 2001, "rtol": 1e-11}})


def actual(sc) -> float:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", physics.ValidityWarning)
        full = physics.simulate(sc, fidelity="full")
        closed = physics.simulate(sc, fidelity="closed")
    return float(np.max(np.abs(closed.theta - full.theta)))


HANDFUL = {
    # an oblique wheel on a symmetric body: the second-order response dominates
    "oblique": scene({"C": 1.5}, {"J": 0.2, "c": 0.3, "axis": [1.0, 0.0, 0.8]}, 0.05, 40.0),
    # a transverse wheel, weakly damped, many turns: the spin-up's drift dominates
    "spin-up": scene({"C": 1.8}, {"J": 0.02, "c": 0.05, "axis": [1.0, 0.0, 0.0]}, 0.08, 600.0),
    # triaxial, theta0 a quarter of the separatrix angle (B close to C)
    "separatrix": scene({"B": 1.15, "C": 1.25}, {"J": 0.05, "c": 0.2, "axis": [1.0, 1.0, 0.3]}, 0.08, 200.0),
    # near a sphere, a strong bearing
    "near sphere": scene({"C": 1.03}, {"J": 0.01, "c": 2.0, "axis": [0.0, 1.0, 0.2]}, 0.03, 300.0),
    # a free wheel (c = 0): no decay, the error is the drift alone
    "free wheel": scene({"B": 1.05, "C": 1.6}, {"J": 0.1, "c": 0.0, "axis": [1.0, 0.0, 0.0]}, 0.04, 100.0),
}


@pytest.mark.parametrize("name", list(HANDFUL))
def test_the_estimate_holds_on_fresh_scenarios(name):
    sc = HANDFUL[name]
    bound = physics.get_system("wheel").error_bounds(sc, "closed")
    assert bound is not None, [str(c) for c in accuracy.domain(sc) if not c.holds]
    err = actual(sc)
    assert err <= bound, (err, bound)
    assert bound <= OVER_MAX * err or bound <= 10 * accuracy.FLOOR, (err, bound)


def test_the_estimate_claims_nothing_outside_its_domain():
    wheels = physics.get_system("wheel")
    base = HANDFUL["oblique"]
    outside = {
        "theta0 > 0.1": base.with_values(**{"initial.theta0": 0.12}),
        "near the separatrix": scene({"B": 1.2, "C": 1.21}, {"J": 0.05, "c": 0.2, "axis": [1.0, 0.0, 0.0]}, 0.08,
                                     50.0),
        "prolate: the nutation grows": scene({"C": 0.8}, {"J": 0.05, "c": 0.2, "axis": [1.0, 0.0, 0.0]}, 0.05,
                                             200.0),
        "too many turns": base.with_values(**{"run.t_end": 4e4}),
    }
    for name, sc in outside.items():
        assert wheels.error_bounds(sc, "closed") is None, name
        assert physics.derived(sc)["closed_error_bound"] == math.inf, name
        assert physics.derived(sc)["auto_fidelity"] == "full", name
    assert wheels.error_bounds(base, "full") is None


def test_auto_runs_the_closed_form_where_its_estimate_meets_the_accuracy():
    preset = physics.Scenario.from_dict(tomllib.loads(physics.get_system("wheel").example))
    d = physics.derived(preset)  # theta0 = 0.4: past the closed form's 0.1
    assert d["auto_fidelity"] == "full" and "theta0" in d["auto_reason"]
    small = preset.with_values(**{"initial.theta0": 0.01})
    d = physics.derived(small)
    assert d["auto_fidelity"] == "closed" and d["auto_error_bound"] <= physics.DEFAULT_ACCURACY
    assert d["error_bound_method"] == accuracy.METHOD
    strict = small.with_values(**{"run.accuracy": d["closed_error_bound"] / 2})
    assert physics.derived(strict)["auto_fidelity"] == "full"  # asked for more than the estimate promises
    assert actual(small.with_values(**{"run.rtol": 1e-11})) <= d["closed_error_bound"]


def test_the_check_study_quoted_in_the_docs_is_what_its_results_file_holds():
    """docs/models.md C.4 quotes `python -m bench fidelity --system wheel --n 60 --seed 15`: the table row and the
    auto sentence are recomputed from bench/results/fidelity_wheel.csv (a rerun that changes them fails here)."""
    import csv
    import re
    import statistics
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    rows = list(csv.DictReader((root / "bench/results/fidelity_wheel.csv").open()))
    claimed = [r for r in rows if r["estimate"] not in ("", "nan", "None") and math.isfinite(float(r["estimate"]))]
    ratios = [float(r["actual_error"]) / float(r["estimate"]) for r in claimed]
    over = statistics.median(float(r["estimate"]) / float(r["actual_error"]) for r in claimed)
    picked = [r for r in rows if r["auto_0.001"] == "closed"]
    assert all(float(r["actual_error"]) <= 1e-3 for r in picked)
    text = (root / "docs/models.md").read_text()
    row = f"| wheel / closed | {len(rows)} | {len(claimed)} | {max(ratios):.2f} | {over:.1f} |"
    assert row in text, row
    said = re.search(r"auto picks the closed form in (\d+) of the (\d+), all within it", text)
    assert said and (int(said[1]), int(said[2])) == (len(picked), len(rows))
