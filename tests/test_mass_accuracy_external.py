"""The moving mass's error estimate with a medium and a brake (issue 23): the forced response carries the full
model's |K| and theta_K through the energy balance and |K|' = (K/|K|).M, so the estimate stays finite where the
brake stops the body and tracks the measured error closely on cases picked here (not drawn by the calibration
study). Before it, the brake's and medium's turn of K was a term of its own and the estimate said pi (theta's
whole range) on 11 of the 22 shipped scenarios."""

from __future__ import annotations

import math
import warnings

import pytest

import physics
from bench.fidelity import max_theta_error
from physics.systems.moving_mass import accuracy

BRAKING = "assets/scenarios/explorer/1_braking_quasistatic.toml"  # law "Jw", the run ends when |J* w| reaches 0
SHIPPED_WITH_EXTERNAL = (BRAKING, "assets/scenarios/braking_cavity_medium.toml")

# (name, values over the explorer's braking preset): each runs the full model in about a second
CASES = {
    "braking, law Jw (the preset)": {},
    "braking, law K, with a medium": {"control.law": "K", "medium.lambda": 0.002},
    "prolate, a medium only": {"body.C": 0.7, "control.b": 0.0, "medium.lambda": 0.004, "run.t_end": 300.0,
                               "initial.theta0": 0.5},
    "braking from rest, law K": {"control.law": "K", "initial.mass_state": "rest"},
}
# the calibration sets' full-model errors were at most (1 + 2.11 eps^2) of the predicted ones (accuracy.forced_safety):
# the estimate lies within a band around forced_safety() x the measured error, widened a little for cases it
# was not fitted on
BAND = (0.9, 1.1)


@pytest.mark.parametrize("path", SHIPPED_WITH_EXTERNAL)
def test_a_brake_that_stops_the_body_leaves_the_estimate_finite_and_small(path):
    sc = physics.Scenario.load(path)
    parts = accuracy.terms(sc)
    assert parts.predicted is not None and math.isfinite(parts.predicted)
    assert physics.derived(sc)["closed_error_bound"] < 0.02


@pytest.mark.parametrize("name", CASES)
def test_the_estimate_tracks_the_measured_error_with_a_medium_or_a_brake(name):
    base = physics.Scenario.load(BRAKING)
    sc = base.with_values(**CASES[name]) if CASES[name] else base
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = physics.simulate(sc, fidelity="full")
        closed = physics.simulate(sc, fidelity="closed")
    actual, _ = max_theta_error(full.t, full.theta, closed.t, closed.theta)
    stated = physics.derived(sc)["closed_error_bound"]
    assert actual <= stated
    assert BAND[0] <= stated / (accuracy.forced_safety(sc) * actual) <= BAND[1], (actual, stated)
